#include "integrators/cpu_reference.h"

#include "base/progress.h"
#include "integrators/emission.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace veil::volume {

CpuFogReference::CpuFogReference(const scene::Scene& scene,
                                 std::vector<openvdb::FloatGrid::ConstPtr> grids)
    : scene_(scene), medium_(scene, grids, "CPU fog reference", true) {
    if (scene.render.fogOctaveRadius > 0.0f && scene.render.fogOctaves > 1)
        for (const Medium::Volume& v : medium_.volumes())
            neighbourhood_.push_back(neighbourhoodMean(*v.grid));
    for (std::size_t i = 0; i < scene.lights.size(); ++i)
        if (scene.lights[i].castShadows) {
            primaryLight_ = static_cast<int>(i);
            break;
        }
    if (primaryLight_ < 0 && !scene.lights.empty()) primaryLight_ = 0;
    if (scene.render.fogScatteredLight) {
        // The bake of fog/scattered_light_cache.cpp: same tracer settings, seed and grid.
        PathTracerSettings settings;
        settings.seed = scene.render.seed;
        const VolumePathTracer tracer(scene, grids, settings);
        glm::dvec3 lo, hi;
        tracer.worldBounds(lo, hi);
        const glm::ivec3 dims = scatteredLightDims(scene, grids, lo, hi);
        const ScatteredLightSurface surface = scatteredLightSurfaceTexels(scene, lo, hi, dims);
        scattered_ = tracer.scatteredLight(lo, hi, dims, scene.render.fogScatteredLightSamples, {},
                                           surface.texels, surface.samples);
    }
}

double CpuFogReference::localDepth(const glm::dvec3& world) const {
    double sigma = 0.0;
    for (std::size_t i = 0; i < medium_.volumes().size(); ++i) {
        const Medium::Volume& v = medium_.volumes()[i];
        const glm::dvec3 o = glm::dvec3(v.worldToObject * glm::dvec4(world, 1.0));
        const openvdb::Vec3d idx = v.grid->worldToIndex(openvdb::Vec3d(o.x, o.y, o.z));
        sigma +=
            v.ref->densityScale * neighbourhood_[i].sample(glm::dvec3(idx.x(), idx.y(), idx.z()));
    }
    return double(scene_.render.fogOctaveRadius) * sigma;
}

double CpuFogReference::extinction(const glm::dvec3& world) const {
    Medium::Lookup lookup = medium_.lookup();
    double sigma = medium_.homogeneous().density;
    for (std::size_t i = 0; i < medium_.volumes().size(); ++i)
        sigma += medium_.volumes()[i].ref->densityScale * medium_.density(lookup, i, world);
    return sigma;
}

double CpuFogReference::transmittanceToLight(const glm::dvec3& p, int light, int steps) const {
    Medium::Lookup lookup = medium_.lookup();
    return transmittanceToLight(lookup, p, light, steps);
}

double CpuFogReference::transmittanceToLight(Medium::Lookup& lookup, const glm::dvec3& p, int light,
                                             int steps) const {
    const scene::Light& l = scene_.lights.at(static_cast<std::size_t>(light));
    glm::dvec3 dir;
    double distance;
    if (l.type == scene::LightType::Directional) {
        dir = -glm::normalize(glm::dvec3(l.direction));
        double t0, t1;
        distance = medium_.interval(p, dir, t0, t1) ? std::max(t1, 0.0) : 0.0;
    } else {
        const glm::dvec3 d = glm::dvec3(l.position) - p;
        distance = glm::length(d);
        dir = d / std::max(distance, 1e-300);
    }
    const std::vector<Medium::Volume>& volumes = medium_.volumes();
    double tau = 0.0;
    if (!volumes.empty() && light == primaryLight_) {
        const double dt = distance / steps;
        for (int s = 0; s < steps; ++s) {
            double sigma = 0.0;
            for (std::size_t i = 0; i < volumes.size(); ++i)
                sigma += volumes[i].ref->densityScale *
                         medium_.density(lookup, i, p + dir * ((s + 0.5) * dt));
            tau += sigma * dt;
        }
    }
    if (l.type != scene::LightType::Directional) tau += medium_.homogeneous().density * distance;
    return std::exp(-tau);
}

FogSample CpuFogReference::pixel(const scene::Camera& camera, int width, int height, double px,
                                 double py, int steps, double maxDistance) const {
    const CameraRay ray = cameraRay(camera, width, height, px, py);
    const glm::dvec3 ro = ray.origin, rd = ray.direction;
    double tEnd = ray.length;
    if (maxDistance > 0.0) tEnd = std::min(tEnd, maxDistance);
    const Medium::Homogeneous& fog = medium_.homogeneous();
    const std::vector<Medium::Volume>& volumes = medium_.volumes();
    double t0 = 0.0, t1 = tEnd;
    if (fog.density <= 0.0) {
        if (!medium_.interval(ro, rd, t0, t1)) return {};
        t0 = std::max(t0, 0.0);
        t1 = std::min(t1, tEnd);
        if (t0 >= t1) return {};
    }
    Medium::Lookup lookup = medium_.lookup();
    FogSample out;
    const double dt = (t1 - t0) / steps;
    const glm::dvec3 V = -rd;
    for (int s = 0; s < steps; ++s) {
        const glm::dvec3 P = ro + rd * (t0 + (s + 0.5) * dt);
        double sigma = fog.density;
        glm::dvec3 albedoSigma = fog.albedo * fog.density, emitted(0.0);
        std::vector<double> sig(volumes.size());
        for (std::size_t i = 0; i < volumes.size(); ++i) {
            const Medium::Point m = medium_.sample(lookup, i, P);
            sig[i] = volumes[i].ref->densityScale * m.density;
            sigma += sig[i];
            albedoSigma += glm::dvec3(volumes[i].ref->albedo) * sig[i];
            emitted += emittedRadiance(*volumes[i].ref, m.density, m.channel);
        }
        if (sigma <= 0.0 && emitted == glm::dvec3(0.0)) continue;
        glm::dvec3 inscatter(0.0);
        if (scene_.render.fogScatteredLight) {
            // Light scattered before and the sky, from the cache (integrators/path_tracer.h).
            for (std::size_t i = 0; i < volumes.size(); ++i)
                inscatter += glm::dvec3(volumes[i].ref->albedo) * sig[i] *
                             scattered_.inscattered(P, V, volumes[i].ref->anisotropy);
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
            const LightArrival arrival = lightArrival(scene_.lights[l], P);
            const glm::dvec3& e = arrival.irradiance;
            if (e == glm::dvec3(0.0)) continue;
            const double vis = transmittanceToLight(lookup, P, static_cast<int>(l), 256);
            const double cosTheta = glm::dot(-arrival.toLight, V);
            // Octave n: transmittance to the light ^ a^n, scattering x b^n, g x c^n.
            const scene::RenderSettings& r = scene_.render;
            double an = 1.0, bn = 1.0, cn = 1.0;
            for (int n = 0; n < r.fogOctaves; ++n) {
                glm::dvec3 phaseAlbedo =
                    fog.albedo * fog.density * henyeyGreenstein(cosTheta, cn * fog.anisotropy);
                for (std::size_t i = 0; i < volumes.size(); ++i)
                    phaseAlbedo += glm::dvec3(volumes[i].ref->albedo) * sig[i] *
                                   henyeyGreenstein(cosTheta, cn * volumes[i].ref->anisotropy);
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
    // The progress line's note (base/progress.h): the rows done, so it shows a percentage
    // and the time left.
    ProgressNote note(fmt::format("marching {}x{} pixels, {} steps per ray", width, height, steps));
    std::atomic<int> rowsDone{0};
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            const FogSample s = pixel(camera, width, height, x + 0.5, y + 0.5, steps);
            for (int c = 0; c < 3; ++c)
                image.at(x, y, c) = static_cast<float>(s.radiance[c]);
            image.at(x, y, 3) = static_cast<float>(s.transmittance);
        }
        note.set(double(rowsDone.fetch_add(1) + 1) / height);
    });
    return image;
}

ImageF CpuFogReference::renderOverBackground(const scene::Camera& camera, int width, int height,
                                             int steps) const {
    const ImageF fog = render(camera, width, height, steps);
    ImageF out(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                out.at(x, y, c) = fog.at(x, y, c) + fog.at(x, y, 3) * scene_.render.background[c];
    return out;
}

} // namespace veil::volume
