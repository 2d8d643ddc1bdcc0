#include "volume/cpu_reference.h"

#include "volume/density_grid.h"
#include "volume/emission.h"
#include "volume/ray_box.h"

#include "base/error.h"

#include <openvdb/tools/Interpolation.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace veil::volume {

namespace {
constexpr double kPi = 3.14159265358979323846;

double henyeyGreenstein(double cosTheta, double g) {
    const double d = 1.0 + g * g - 2.0 * g * cosTheta;
    return (1.0 - g * g) / (4.0 * kPi * d * std::sqrt(d));
}

double smoothstep(double e0, double e1, double x) {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}
} // namespace

CpuFogReference::CpuFogReference(const scene::Scene& scene,
                                 std::vector<openvdb::FloatGrid::ConstPtr> grids)
    : scene_(scene) {
    std::size_t g = 0;
    for (const auto& ref : scene.volumes) {
        if (ref.procedural == "homogeneous") {
            globalAlbedo_ = (globalAlbedo_ * globalDensity_ +
                             glm::dvec3(ref.albedo) * double(ref.densityScale)) /
                            std::max(globalDensity_ + ref.densityScale, 1e-20);
            globalAnisotropy_ = ref.anisotropy;
            globalDensity_ += ref.densityScale;
            continue;
        }
        VEIL_CHECK(g < grids.size() && grids[g], "CPU fog reference: no grid for volume '{}'",
                   ref.name);
        Volume v{&ref, grids[g++], glm::inverse(glm::dmat4(ref.transform)), {}, {}, {}, {}};
        gridWorldBox(*v.grid, ref.transform, v.lo, v.hi);
        if (scene.render.fogOctaveRadius > 0.0f && scene.render.fogOctaves > 1)
            v.neighbourhood = neighbourhoodMean(*v.grid);
        v.channel = loadEmissionChannel(ref);
        widenToEmission(ref, v.channel, v.lo, v.hi);
        volumes_.push_back(v);
    }
    for (std::size_t i = 0; i < scene.lights.size(); ++i)
        if (scene.lights[i].castShadows) {
            primaryLight_ = static_cast<int>(i);
            break;
        }
    if (primaryLight_ < 0 && !scene.lights.empty()) primaryLight_ = 0;
    if (scene.render.fogScatteredLight) {
        // The bake of volume/scattered_light_cache.cpp: same tracer settings, seed and grid.
        PathTracerSettings settings;
        settings.seed = scene.render.seed;
        const VolumePathTracer tracer(scene, grids, settings);
        glm::dvec3 lo, hi;
        tracer.worldBounds(lo, hi);
        scattered_ = tracer.scatteredLight(lo, hi, scatteredLightDims(scene, grids, lo, hi),
                                           scene.render.fogScatteredLightSamples);
    }
}

double CpuFogReference::densityOf(const Volume& v, const glm::dvec3& world) const {
    if (glm::any(glm::lessThan(world, v.lo)) || glm::any(glm::greaterThan(world, v.hi))) return 0.0;
    const glm::dvec3 o = glm::dvec3(v.worldToObject * glm::dvec4(world, 1.0));
    const openvdb::Vec3d idx = v.grid->worldToIndex(openvdb::Vec3d(o.x, o.y, o.z));
    const auto acc = v.grid->getConstAccessor();
    return openvdb::tools::BoxSampler::sample(acc, idx);
}

glm::dvec3 CpuFogReference::channelOf(const Volume& v, const glm::dvec3& world) const {
    if (v.channel.empty()) return glm::dvec3(0.0);
    if (glm::any(glm::lessThan(world, v.lo)) || glm::any(glm::greaterThan(world, v.hi)))
        return glm::dvec3(0.0);
    std::vector<openvdb::FloatGrid::ConstAccessor> acc;
    for (const auto& g : v.channel)
        acc.push_back(g->getConstAccessor());
    return sampleChannel(v.channel, acc, glm::dvec3(v.worldToObject * glm::dvec4(world, 1.0)));
}

double CpuFogReference::localDepth(const glm::dvec3& world) const {
    double sigma = 0.0;
    for (const auto& v : volumes_) {
        const glm::dvec3 o = glm::dvec3(v.worldToObject * glm::dvec4(world, 1.0));
        const openvdb::Vec3d idx = v.grid->worldToIndex(openvdb::Vec3d(o.x, o.y, o.z));
        sigma +=
            v.ref->densityScale * v.neighbourhood.sample(glm::dvec3(idx.x(), idx.y(), idx.z()));
    }
    return double(scene_.render.fogOctaveRadius) * sigma;
}

double CpuFogReference::extinction(const glm::dvec3& world) const {
    double sigma = globalDensity_;
    for (const auto& v : volumes_)
        sigma += v.ref->densityScale * densityOf(v, world);
    return sigma;
}

bool CpuFogReference::interval(const glm::dvec3& ro, const glm::dvec3& rd, double& t0,
                               double& t1) const {
    return rayBoxesInterval(ro, rd, volumes_, t0, t1);
}

double CpuFogReference::transmittanceToLight(const glm::dvec3& p, int light, int steps) const {
    const scene::Light& l = scene_.lights.at(static_cast<std::size_t>(light));
    glm::dvec3 dir;
    double distance;
    if (l.type == scene::LightType::Directional) {
        dir = -glm::normalize(glm::dvec3(l.direction));
        double t0, t1;
        distance = interval(p, dir, t0, t1) ? std::max(t1, 0.0) : 0.0;
    } else {
        const glm::dvec3 d = glm::dvec3(l.position) - p;
        distance = glm::length(d);
        dir = d / std::max(distance, 1e-300);
    }
    double tau = 0.0;
    if (!volumes_.empty() && light == primaryLight_) {
        const double dt = distance / steps;
        for (int s = 0; s < steps; ++s) {
            double sigma = 0.0;
            for (const auto& v : volumes_)
                sigma += v.ref->densityScale * densityOf(v, p + dir * ((s + 0.5) * dt));
            tau += sigma * dt;
        }
    }
    if (l.type != scene::LightType::Directional) tau += globalDensity_ * distance;
    return std::exp(-tau);
}

FogSample CpuFogReference::pixel(const scene::Camera& camera, int width, int height, double px,
                                 double py, int steps, double maxDistance) const {
    const glm::dmat4 vp =
        glm::dmat4(camera.projection(float(width) / float(height))) * glm::dmat4(camera.view());
    const glm::dmat4 inv = glm::inverse(vp);
    const double nx = px / width * 2.0 - 1.0, ny = 1.0 - py / height * 2.0;
    const glm::dvec4 a = inv * glm::dvec4(nx, ny, -1.0, 1.0),
                     b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
    const glm::dvec3 ro = glm::dvec3(a) / a.w, re = glm::dvec3(b) / b.w;
    double tEnd = glm::length(re - ro);
    const glm::dvec3 rd = (re - ro) / tEnd;
    if (maxDistance > 0.0) tEnd = std::min(tEnd, maxDistance);
    double t0 = 0.0, t1 = tEnd;
    if (globalDensity_ <= 0.0) {
        if (!interval(ro, rd, t0, t1)) return {};
        t0 = std::max(t0, 0.0);
        t1 = std::min(t1, tEnd);
        if (t0 >= t1) return {};
    }
    FogSample out;
    const double dt = (t1 - t0) / steps;
    const glm::dvec3 V = -rd;
    for (int s = 0; s < steps; ++s) {
        const glm::dvec3 P = ro + rd * (t0 + (s + 0.5) * dt);
        double sigma = globalDensity_;
        glm::dvec3 albedoSigma = globalAlbedo_ * globalDensity_, emitted(0.0);
        std::vector<double> sig(volumes_.size());
        for (std::size_t i = 0; i < volumes_.size(); ++i) {
            const double d = densityOf(volumes_[i], P);
            sig[i] = volumes_[i].ref->densityScale * d;
            sigma += sig[i];
            albedoSigma += glm::dvec3(volumes_[i].ref->albedo) * sig[i];
            emitted += emittedRadiance(*volumes_[i].ref, d, channelOf(volumes_[i], P));
        }
        if (sigma <= 0.0 && emitted == glm::dvec3(0.0)) continue;
        glm::dvec3 inscatter(0.0);
        if (scene_.render.fogScatteredLight) {
            // Light scattered before and the sky, from the cache (volume/path_tracer.h).
            for (std::size_t i = 0; i < volumes_.size(); ++i)
                inscatter += glm::dvec3(volumes_[i].ref->albedo) * sig[i] *
                             scattered_.inscattered(P, V, volumes_[i].ref->anisotropy);
        } else {
            inscatter =
                glm::dvec3(scene_.render.ambient) * albedoSigma * double(scene_.render.fogAmbient);
        }
        // Depth-aware octaves: octave n >= 1 also weighted by w^n.
        const double octaveWeight =
            scene_.render.fogOctaveRadius > 0.0f && scene_.render.fogOctaves > 1
                ? 1.0 - std::exp(-localDepth(P))
                : 1.0;
        for (std::size_t l = 0; l < scene_.lights.size() && l < 8; ++l) {
            const scene::Light& light = scene_.lights[l];
            glm::dvec3 L, e = glm::dvec3(light.color) * double(light.intensity);
            if (light.type == scene::LightType::Directional) {
                L = -glm::normalize(glm::dvec3(light.direction));
            } else {
                const glm::dvec3 d = glm::dvec3(light.position) - P;
                const double d2 = std::max(glm::dot(d, d), 1e-16);
                L = d / std::sqrt(d2);
                e /= d2;
                if (light.type == scene::LightType::Spot)
                    e *= smoothstep(std::cos(glm::radians(double(light.outerConeDegrees))),
                                    std::cos(glm::radians(double(light.innerConeDegrees))),
                                    glm::dot(-L, glm::normalize(glm::dvec3(light.direction))));
            }
            if (e == glm::dvec3(0.0)) continue;
            const double vis = transmittanceToLight(P, static_cast<int>(l));
            const double cosTheta = glm::dot(-L, V);
            // Octave n: transmittance to the light ^ a^n, scattering x b^n, g x c^n.
            const scene::RenderSettings& r = scene_.render;
            double an = 1.0, bn = 1.0, cn = 1.0;
            for (int n = 0; n < r.fogOctaves; ++n) {
                glm::dvec3 phaseAlbedo = globalAlbedo_ * globalDensity_ *
                                         henyeyGreenstein(cosTheta, cn * globalAnisotropy_);
                for (std::size_t i = 0; i < volumes_.size(); ++i)
                    phaseAlbedo += glm::dvec3(volumes_[i].ref->albedo) * sig[i] *
                                   henyeyGreenstein(cosTheta, cn * volumes_[i].ref->anisotropy);
                inscatter += e * (std::pow(vis, an) * bn) * phaseAlbedo;
                an *= r.fogOctaveExtinction;
                bn *= r.fogOctaveScattering * octaveWeight;
                cn *= r.fogOctaveAnisotropy;
            }
        }
        const double stepT = std::exp(-sigma * dt);
        const double integral = sigma > 1e-12 ? (1.0 - stepT) / sigma : dt;
        out.radiance += out.transmittance * (inscatter + emitted) * integral;
        out.transmittance *= stepT;
    }
    return out;
}

ImageF CpuFogReference::render(const scene::Camera& camera, int width, int height,
                               int steps) const {
    ImageF image(width, height, 4);
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            const FogSample s = pixel(camera, width, height, x + 0.5, y + 0.5, steps);
            for (int c = 0; c < 3; ++c)
                image.at(x, y, c) = static_cast<float>(s.radiance[c]);
            image.at(x, y, 3) = static_cast<float>(s.transmittance);
        }
    });
    return image;
}

} // namespace veil::volume
