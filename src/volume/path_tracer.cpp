#include "volume/path_tracer.h"

#include "volume/density_grid.h"
#include "volume/emission.h"
#include "volume/ray_box.h"

#include "base/error.h"

#include <openvdb/tools/Count.h>
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

// Cosine between the travel directions before and after scattering, drawn from HG(g) by
// inverting its CDF (isotropic for |g| < 1e-4).
double sampleHgCos(double g, double u) {
    if (std::abs(g) < 1e-4) return 1.0 - 2.0 * u;
    const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    return std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

glm::dvec3 scatter(const glm::dvec3& d, double g, Pcg32& rng) {
    const double c = sampleHgCos(g, rng.uniform());
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double phi = 2.0 * kPi * rng.uniform();
    // Orthonormal basis around d (Duff et al.'s branchless construction).
    const double sign = std::copysign(1.0, d.z);
    const double a = -1.0 / (sign + d.z), b = d.x * d.y * a;
    const glm::dvec3 t(1.0 + sign * d.x * d.x * a, sign * b, -sign * d.x);
    const glm::dvec3 bt(b, sign + d.y * d.y * a, -d.y);
    return glm::normalize(s * std::cos(phi) * t + s * std::sin(phi) * bt + c * d);
}

double freePath(double majorant, Pcg32& rng) { return -std::log(1.0 - rng.uniform()) / majorant; }

double smoothstep(double e0, double e1, double x) {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Russian roulette on a weight: survives with probability q = min(max component, 1), so a
// weight of 1 (albedo 1) is never cut and energy is conserved path by path.
bool roulette(glm::dvec3& weight, Pcg32& rng) {
    const double q = std::min(1.0, std::max({weight.x, weight.y, weight.z}));
    if (q <= 0.0 || rng.uniform() >= q) return false;
    weight /= q;
    return true;
}

} // namespace

const PropertySchema& pathTracerSchema() {
    static const PropertySchema s = [] {
        const char* ref = "[Woodcock65, Novak14, Novak18]";
        PropertySchema p;
        p.integer("spp", 256, 1, 1 << 24, "samples per pixel", ref)
            .integer("max_bounces", 256, 1, 1 << 20,
                     "most scattering events per path (1 = single scattering)", ref)
            .integer("seed", 1, 0, std::numeric_limits<std::uint32_t>::max(),
                     "seed of the sample streams")
            .integer("roulette_depth", 8, 1, 1 << 20,
                     "scattering events before Russian roulette on the path weight", ref)
            .integer("batch", 16, 1, 1 << 16, "samples per pixel per progressive pass");
        return p;
    }();
    return s;
}

PathTracerSettings pathTracerSettings(const Properties& properties) {
    PathTracerSettings s;
    s.spp = properties.getInt("spp");
    s.maxBounces = properties.getInt("max_bounces");
    s.seed = static_cast<std::uint32_t>(properties.getDouble("seed"));
    s.rouletteDepth = properties.getInt("roulette_depth");
    s.batch = properties.getInt("batch");
    return s;
}

SlabTally traceSlab(double tau, double albedo, double g, std::uint64_t paths, std::uint32_t seed,
                    double majorantFactor) {
    VEIL_CHECK(tau > 0.0 && albedo >= 0.0 && albedo <= 1.0 && majorantFactor >= 1.0 && paths > 1,
               "traceSlab: bad arguments (tau {}, albedo {}, majorant factor {}, {} paths)", tau,
               albedo, majorantFactor, paths);
    const double majorant = majorantFactor; // extinction 1 in optical units
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    for (std::uint64_t i = 0; i < paths; ++i) {
        Pcg32 rng(mix64(seed ^ (i * 0x9e3779b97f4a7c15ULL)), mix64(i + 1));
        double z = 0.0;              // depth, 0 at the lit top
        glm::dvec3 d(0.0, 0.0, 1.0); // travel direction, +z into the slab
        glm::dvec3 weight(1.0);
        int scatterings = 0;
        double tally[3] = {0, 0, 0}; // reflected, diffusely transmitted, directly transmitted
        for (;;) {
            z += d.z * freePath(majorant, rng);
            if (z < 0.0) {
                tally[0] = weight.x;
                break;
            }
            if (z > tau) {
                tally[scatterings ? 1 : 2] = weight.x;
                break;
            }
            if (rng.uniform() * majorant >= 1.0) continue; // null collision
            weight *= albedo;
            if (weight.x <= 0.0) break;
            ++scatterings;
            if (scatterings >= 8 && !roulette(weight, rng)) break;
            d = scatter(d, g, rng);
        }
        for (int k = 0; k < 3; ++k) {
            sum[k] += tally[k];
            sum2[k] += tally[k] * tally[k];
        }
    }
    const double n = double(paths);
    auto mean = [&](int k) { return sum[k] / n; };
    auto error = [&](int k) {
        const double m = sum[k] / n;
        return std::sqrt(std::max(0.0, (sum2[k] / n - m * m) / (n - 1.0)));
    };
    return {mean(0), error(0), mean(1), error(1), mean(2), error(2)};
}

struct VolumePathTracer::Lookup {
    std::vector<openvdb::FloatGrid::ConstAccessor> accessors;
    std::vector<std::vector<openvdb::FloatGrid::ConstAccessor>> channels;
};

VolumePathTracer::VolumePathTracer(const scene::Scene& scene,
                                   std::vector<openvdb::FloatGrid::ConstPtr> grids,
                                   PathTracerSettings settings)
    : scene_(scene), settings_(settings) {
    std::size_t gi = 0;
    for (const auto& ref : scene.volumes) {
        VEIL_CHECK(ref.procedural != "homogeneous",
                   "path tracer: volume '{}' is homogeneous fog filling all space, which paths "
                   "never leave (give it bounds: a box volume)",
                   ref.name);
        VEIL_CHECK(gi < grids.size() && grids[gi], "path tracer: no grid for volume '{}'",
                   ref.name);
        Volume v{&ref, grids[gi++], glm::inverse(glm::dmat4(ref.transform)), {}, {}, {}};
        gridWorldBox(*v.grid, ref.transform, v.lo, v.hi);
        v.channel = loadEmissionChannel(ref);
        widenToEmission(ref, v.channel, v.lo, v.hi);
        const auto range = openvdb::tools::minMax(v.grid->tree());
        majorant_ += double(ref.densityScale) * std::max(0.0, double(range.max()));
        volumes_.push_back(v);
    }
}

VolumePathTracer::Medium VolumePathTracer::mediumAt(Lookup& lookup, const glm::dvec3& p,
                                                    std::vector<double>* perVolume) const {
    Medium m;
    for (std::size_t i = 0; i < volumes_.size(); ++i) {
        const Volume& v = volumes_[i];
        double density = 0.0;
        glm::dvec3 channel(0.0);
        if (!glm::any(glm::lessThan(p, v.lo)) && !glm::any(glm::greaterThan(p, v.hi))) {
            const glm::dvec3 o = glm::dvec3(v.worldToObject * glm::dvec4(p, 1.0));
            const openvdb::Vec3d idx = v.grid->worldToIndex(openvdb::Vec3d(o.x, o.y, o.z));
            density =
                std::max(0.0, double(openvdb::tools::BoxSampler::sample(lookup.accessors[i], idx)));
            if (!v.channel.empty()) channel = sampleChannel(v.channel, lookup.channels[i], o);
        }
        const double sigma = double(v.ref->densityScale) * density;
        if (perVolume) (*perVolume)[i] = sigma;
        m.sigma += sigma;
        if (density > 0.0 || channel != glm::dvec3(0.0))
            m.emission += emittedRadiance(*v.ref, density, channel);
    }
    return m;
}

bool VolumePathTracer::bounds(const glm::dvec3& o, const glm::dvec3& d, double& t0,
                              double& t1) const {
    if (!rayBoxesInterval(o, d, volumes_, t0, t1)) return false;
    t0 = std::max(t0, 0.0);
    return t0 < t1;
}

double VolumePathTracer::transmittance(Lookup& lookup, const glm::dvec3& o, const glm::dvec3& d,
                                       double tMax, Pcg32& rng) const {
    double t0, t1;
    if (majorant_ <= 0.0 || !bounds(o, d, t0, t1)) return 1.0;
    t1 = std::min(t1, tMax);
    double tr = 1.0, t = t0;
    for (;;) {
        t += freePath(majorant_, rng);
        if (t >= t1) return tr;
        tr *= 1.0 - mediumAt(lookup, o + d * t, nullptr).sigma / majorant_;
        if (tr < 0.1) {
            if (rng.uniform() >= 0.5) return 0.0;
            tr *= 2.0;
        }
    }
}

glm::dvec3 VolumePathTracer::trace(Lookup& lookup, glm::dvec3 o, glm::dvec3 d, double tMax,
                                   Pcg32& rng, bool escapeSeesAmbient) const {
    glm::dvec3 radiance(0.0), weight(1.0);
    std::vector<double> perVolume(volumes_.size());
    int events = 0;
    const auto& lights = scene_.lights;
    for (;;) {
        double t0 = 0.0, t1 = -1.0;
        bool inside = majorant_ > 0.0 && bounds(o, d, t0, t1);
        if (events == 0) t1 = std::min(t1, tMax);
        bool collided = false;
        double t = t0;
        while (inside) {
            t += freePath(majorant_, rng);
            if (t >= t1) break;
            const glm::dvec3 p = o + d * t;
            const Medium m = mediumAt(lookup, p, &perVolume);
            radiance += weight * m.emission / majorant_;
            if (rng.uniform() * majorant_ < m.sigma) {
                o = p;
                collided = true;
                break;
            }
        }
        if (!collided) {
            radiance +=
                weight * glm::dvec3(events == 0 && !escapeSeesAmbient ? scene_.render.background
                                                                      : scene_.render.ambient);
            return radiance;
        }
        if (events >= settings_.maxBounces) return radiance; // the path ends in the medium
        // The scattering volume, in proportion to its extinction at o.
        double total = 0.0;
        for (double s : perVolume)
            total += s;
        double pick = rng.uniform() * total;
        std::size_t vi = 0;
        while (vi + 1 < perVolume.size() && pick >= perVolume[vi])
            pick -= perVolume[vi++];
        const scene::VolumeRef& ref = *volumes_[vi].ref;
        weight *= glm::dvec3(ref.albedo);
        ++events;
        if (weight == glm::dvec3(0.0)) return radiance;
        // Next-event estimation toward every light.
        for (const scene::Light& light : lights) {
            glm::dvec3 toLight, e = glm::dvec3(light.color) * double(light.intensity);
            double distance = 1e300;
            if (light.type == scene::LightType::Directional) {
                toLight = -glm::normalize(glm::dvec3(light.direction));
            } else {
                const glm::dvec3 dl = glm::dvec3(light.position) - o;
                const double d2 = std::max(glm::dot(dl, dl), 1e-16);
                distance = std::sqrt(d2);
                toLight = dl / distance;
                e /= d2;
                if (light.type == scene::LightType::Spot)
                    e *=
                        smoothstep(std::cos(glm::radians(double(light.outerConeDegrees))),
                                   std::cos(glm::radians(double(light.innerConeDegrees))),
                                   glm::dot(-toLight, glm::normalize(glm::dvec3(light.direction))));
            }
            if (e == glm::dvec3(0.0)) continue;
            // The path runs backwards: light travels along -toLight, then along -d.
            const double phase = henyeyGreenstein(glm::dot(toLight, d), double(ref.anisotropy));
            radiance += weight * e * phase * transmittance(lookup, o, toLight, distance, rng);
        }
        if (events >= settings_.rouletteDepth && !roulette(weight, rng)) return radiance;
        d = scatter(d, double(ref.anisotropy), rng);
        tMax = 1e300;
    }
}

glm::dvec3 VolumePathTracer::sample(const scene::Camera& camera, int width, int height, double px,
                                    double py, std::uint64_t pixel, std::uint32_t index) const {
    const glm::dmat4 vp =
        glm::dmat4(camera.projection(float(width) / float(height))) * glm::dmat4(camera.view());
    const glm::dmat4 inv = glm::inverse(vp);
    const double nx = px / width * 2.0 - 1.0, ny = 1.0 - py / height * 2.0;
    const glm::dvec4 a = inv * glm::dvec4(nx, ny, -1.0, 1.0),
                     b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
    const glm::dvec3 ro = glm::dvec3(a) / a.w, re = glm::dvec3(b) / b.w;
    const double tEnd = glm::length(re - ro);
    Pcg32 rng(mix64((std::uint64_t(settings_.seed) << 32) ^ index), mix64(pixel + 1));
    Lookup lookup = makeLookup();
    return trace(lookup, ro, (re - ro) / tEnd, tEnd, rng);
}

VolumePathTracer::Lookup VolumePathTracer::makeLookup() const {
    Lookup lookup;
    for (const auto& v : volumes_) {
        lookup.accessors.push_back(v.grid->getConstAccessor());
        lookup.channels.emplace_back();
        for (const auto& g : v.channel)
            lookup.channels.back().push_back(g->getConstAccessor());
    }
    return lookup;
}

void VolumePathTracer::worldBounds(glm::dvec3& lo, glm::dvec3& hi) const {
    lo = glm::dvec3(1e300);
    hi = glm::dvec3(-1e300);
    for (const auto& v : volumes_) {
        lo = glm::min(lo, v.lo);
        hi = glm::max(hi, v.hi);
    }
}

ScatteredLight VolumePathTracer::scatteredLight(const glm::dvec3& lo, const glm::dvec3& hi,
                                                const glm::ivec3& dims, int samples) const {
    VEIL_CHECK(glm::all(glm::greaterThan(dims, glm::ivec3(0))) && samples > 0,
               "scattered-light cache: empty grid or no samples");
    ScatteredLight out;
    out.lo = lo;
    out.hi = hi;
    out.dims = dims;
    out.samples = samples;
    const std::size_t n = std::size_t(dims.x) * dims.y * dims.z;
    out.mean.assign(n, glm::vec4(0.0f));
    out.flux.assign(n, glm::vec4(0.0f));
    const glm::dvec3 lum(0.2126, 0.7152, 0.0722);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        const glm::ivec3 c(int(i % dims.x), int((i / dims.x) % dims.y),
                           int(i / (std::size_t(dims.x) * dims.y)));
        const glm::dvec3 x = lo + (glm::dvec3(c) + 0.5) / glm::dvec3(dims) * (hi - lo);
        Lookup lookup = makeLookup();
        glm::dvec3 sum(0.0), g(0.0);
        for (int k = 0; k < samples; ++k) {
            Pcg32 rng(mix64((std::uint64_t(settings_.seed) << 32) ^ std::uint64_t(k)),
                      mix64(std::uint64_t(i) + 0x5ca77e7ull));
            // Uniform direction on the sphere, the path's first direction away from x.
            const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi * rng.uniform();
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
            const glm::dvec3 l = trace(lookup, x, d, 1e300, rng, true);
            sum += l;
            g += glm::dot(l, lum) * -d; // the arriving light travels along -d
        }
        const glm::dvec3 mean = sum / double(samples);
        out.mean[i] = glm::vec4(glm::vec3(mean), float(glm::dot(mean, lum)));
        out.flux[i] = glm::vec4(glm::vec3(3.0 * g / double(samples)), 0.0f);
    });
    return out;
}

// The cache's grid: fog_scattered_light_cell voxels of the finest volume per texel, over the
// union of the volumes' bounds, at most kScatteredLightMaxTexels per axis (a coarser cell where the
// bounds are larger).
glm::ivec3 scatteredLightDims(const scene::Scene& scene,
                              const std::vector<openvdb::FloatGrid::ConstPtr>& grids,
                              const glm::dvec3& lo, const glm::dvec3& hi) {
    double voxel = 1e300;
    std::size_t g = 0;
    for (const auto& ref : scene.volumes) {
        if (ref.procedural == "homogeneous" || g >= grids.size()) continue;
        const openvdb::Vec3d v = grids[g++]->voxelSize();
        const glm::dmat3 m(ref.transform);
        voxel = std::min({voxel, glm::length(m[0]) * v.x(), glm::length(m[1]) * v.y(),
                          glm::length(m[2]) * v.z()});
    }
    const double cell = std::max(voxel * double(scene.render.fogScatteredLightCell), 1e-12);
    const glm::dvec3 extent = hi - lo;
    return glm::clamp(glm::ivec3(glm::ceil(extent / cell)), glm::ivec3(2),
                      glm::ivec3(kScatteredLightMaxTexels));
}

glm::dvec3 ScatteredLight::inscattered(const glm::dvec3& world, const glm::dvec3& toEye,
                                       double g) const {
    if (mean.empty()) return glm::dvec3(0.0);
    const glm::dvec3 t = (world - lo) / (hi - lo) * glm::dvec3(dims) - 0.5;
    const glm::dvec3 f0 = glm::floor(t);
    const glm::dvec3 f = t - f0;
    glm::dvec4 m(0.0);
    glm::dvec3 fl(0.0);
    for (int k = 0; k < 8; ++k) {
        const glm::ivec3 o(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        const double w =
            (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
        const glm::ivec3 c = glm::clamp(glm::ivec3(f0) + o, glm::ivec3(0), dims - 1);
        const std::size_t i = (std::size_t(c.z) * dims.y + c.y) * dims.x + c.x;
        m += w * glm::dvec4(mean[i]);
        fl += w * glm::dvec3(flux[i]);
    }
    if (m.w <= 0.0) return glm::dvec3(m);
    return glm::dvec3(m) * std::max(0.0, 1.0 + g * glm::dot(fl, toEye) / m.w);
}

PathTracedImage VolumePathTracer::render(const scene::Camera& camera, int width, int height,
                                         const std::function<bool(int)>& progress) const {
    const std::size_t n = std::size_t(width) * height;
    std::vector<glm::dvec3> sum(n, glm::dvec3(0.0)), sum2(n, glm::dvec3(0.0));
    int done = 0;
    while (done < settings_.spp) {
        const int count = std::min(settings_.batch, settings_.spp - done);
        tbb::parallel_for(0, height, [&](int y) {
            for (int x = 0; x < width; ++x) {
                const std::size_t i = std::size_t(y) * width + x;
                for (int s = 0; s < count; ++s) {
                    const glm::dvec3 l =
                        sample(camera, width, height, x + 0.5, y + 0.5, i, std::uint32_t(done + s));
                    sum[i] += l;
                    sum2[i] += l * l;
                }
            }
        });
        done += count;
        if (progress && !progress(done)) break;
    }
    PathTracedImage out{ImageF(width, height, 3), ImageF(width, height, 3), done};
    const double m = done;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::size_t i = std::size_t(y) * width + x;
            for (int c = 0; c < 3; ++c) {
                const double mean = sum[i][c] / m;
                const double var =
                    m > 1 ? std::max(0.0, (sum2[i][c] / m - mean * mean)) / (m - 1) : 0.0;
                out.radiance.at(x, y, c) = float(mean);
                out.standardError.at(x, y, c) = float(std::sqrt(var));
            }
        }
    return out;
}

} // namespace veil::volume
