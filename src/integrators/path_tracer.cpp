#include "integrators/path_tracer.h"

#include "base/error.h"
#include "integrators/emission.h"
#include "integrators/majorant_grid.h"

#include <openvdb/tools/Count.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <numbers>

namespace veil::volume {

namespace {

// The travel direction after scattering at anisotropy g (medium.h's Henyey-Greenstein sampling).
glm::dvec3 scatter(const glm::dvec3& d, double g, Pcg32& rng) {
    const double c = sampleHenyeyGreensteinCos(g, rng.uniform());
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double phi = 2.0 * std::numbers::pi * rng.uniform();
    // Orthonormal basis around d (Duff et al.'s branchless construction).
    const double sign = std::copysign(1.0, d.z);
    const double a = -1.0 / (sign + d.z), b = d.x * d.y * a;
    const glm::dvec3 t(1.0 + sign * d.x * d.x * a, sign * b, -sign * d.x);
    const glm::dvec3 bt(b, sign + d.y * d.y * a, -d.y);
    return glm::normalize(s * std::cos(phi) * t + s * std::sin(phi) * bt + c * d);
}

double freePath(double majorant, Pcg32& rng) { return -std::log(1.0 - rng.uniform()) / majorant; }

// Tentative collisions along o + t d on [0, tMax) against the majorant grid's piecewise-constant
// majorants [Novak18]: a DDA through the cells [Amanatides87] spends an exponential optical
// depth over them, so the collisions are those of a Poisson process whose rate is each cell's
// majorant (empty cells are crossed at once). One uniform per collision, as one global majorant.
class MajorantWalk {
public:
    // Over the part of [0, tMax) inside the grid's box.
    MajorantWalk(const MajorantGrid& grid, const glm::dvec3& o, const glm::dvec3& d, double tMax)
        : t(0.0), values_(grid.values.data()), t1_(tMax) {
        double inv[3];
        for (int a = 0; a < 3; ++a) {
            inv[a] = 1.0 / d[a]; // +-inf along an axis the ray does not move on
            double ta = (grid.lo[a] - o[a]) * inv[a], tb = (grid.hi[a] - o[a]) * inv[a];
            if (d[a] == 0.0) {
                ta = o[a] < grid.lo[a] || o[a] > grid.hi[a] ? 1e300 : -1e300;
                tb = -ta;
            }
            t = std::max(t, std::min(ta, tb));
            t1_ = std::min(t1_, std::max(ta, tb));
        }
        if (!(t < t1_)) {
            t1_ = -1.0; // misses the box: next() is false
            return;
        }
        const glm::dvec3 size = (grid.hi - grid.lo) / glm::dvec3(grid.dims);
        const glm::ivec3 cell = glm::clamp(glm::ivec3(glm::floor((o + d * t - grid.lo) / size)),
                                           glm::ivec3(0), grid.dims - 1);
        const std::ptrdiff_t stride[3] = {1, grid.dims.x,
                                          std::ptrdiff_t(grid.dims.x) * grid.dims.y};
        index_ = cell.x + cell.y * stride[1] + cell.z * stride[2];
        for (int a = 0; a < 3; ++a) {
            if (d[a] == 0.0) continue; // never leaves the cell along this axis
            const bool up = d[a] > 0.0;
            step_[a] = up ? stride[a] : -stride[a];
            left_[a] = up ? grid.dims[a] - 1 - cell[a] : cell[a];
            next_[a] = (grid.lo[a] + (cell[a] + (up ? 1 : 0)) * size[a] - o[a]) * inv[a];
            delta_[a] = size[a] * std::abs(inv[a]);
        }
    }

    // Moves t to the next tentative collision (majorant: its cell's); false past t1.
    bool next(Pcg32& rng) {
        if (t1_ < 0.0) return false;
        double tau = -std::log(1.0 - rng.uniform());
        for (;;) {
            const double m = values_[index_];
            const int a =
                next_[0] < next_[1] ? (next_[0] < next_[2] ? 0 : 2) : (next_[1] < next_[2] ? 1 : 2);
            const double exit = std::min(next_[a], t1_);
            const double length = std::max(0.0, exit - t);
            if (m > 0.0 && tau < m * length) {
                t += tau / m;
                majorant = m;
                return true;
            }
            tau -= m * length;
            t = std::max(t, exit);
            if (exit >= t1_ || left_[a]-- == 0) return false; // past t1 or out of the grid
            index_ += step_[a];
            next_[a] += delta_[a];
        }
    }

    double t, majorant = 0.0;

private:
    const float* values_;
    double t1_;
    std::ptrdiff_t index_ = 0, step_[3] = {0, 0, 0};
    int left_[3] = {0, 0, 0}; // cells left along each axis's direction
    double next_[3] = {1e300, 1e300, 1e300}, delta_[3] = {1e300, 1e300, 1e300};
};

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
        p.integer("spp", 256, 2, 1 << 24,
                  "samples per pixel (at least 2: the standard error needs two)", ref)
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

PathTracerSettings pathTracerSettings(const scene::Scene& scene) {
    return pathTracerSettings(pathTracerSchema().resolve(
        scene.render.pathtracedProperties, scene.render.pathtracedWhere, "the path tracer"));
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

VolumePathTracer::VolumePathTracer(const scene::Scene& scene,
                                   std::vector<openvdb::FloatGrid::ConstPtr> grids,
                                   PathTracerSettings settings)
    : scene_(scene), settings_(settings), medium_(scene, std::move(grids), "path tracer", false) {
    for (const Medium::Volume& v : medium_.volumes()) {
        const auto range = openvdb::tools::minMax(v.grid->tree());
        majorant_ += double(v.ref->densityScale) * std::max(0.0, double(range.max()));
        dense_.emplace_back(*v.grid, v.worldToObject);
    }
    buildMajorants();
}

void VolumePathTracer::buildMajorants() {
    medium_.worldBounds(majorants_.lo, majorants_.hi);
    if (medium_.volumes().empty() || majorant_ <= 0.0 || !settings_.localMajorants) {
        majorants_.dims = glm::ivec3(1); // one majorant for all space
        majorants_.values.assign(1, float(majorant_));
        return;
    }
    std::vector<openvdb::FloatGrid::ConstPtr> grids;
    for (const Medium::Volume& v : medium_.volumes())
        grids.push_back(v.grid);
    majorants_.dims = majorantDims(scene_, grids, majorants_.lo, majorants_.hi, 4.0);
    const std::size_t n = std::size_t(majorants_.dims.x) * majorants_.dims.y * majorants_.dims.z;
    std::vector<double> sum(n, 0.0);
    for (const Medium::Volume& v : medium_.volumes()) {
        const double scale = std::max(0.0, double(v.ref->densityScale));
        // One voxel of margin: the CPU samples the grid itself, trilinearly (majorant_grid.h).
        std::vector<float> m = gridMajorants(*v.grid, v.ref->transform, majorants_.lo,
                                             majorants_.hi, majorants_.dims, 1.0);
        // Tighter where the dense copy holds every voxel a cell's samples read: the largest of
        // those voxels rather than of their leaf nodes.
        const DenseGrid& dense = dense_[std::size_t(&v - medium_.volumes().data())];
        const glm::dvec3 size = (majorants_.hi - majorants_.lo) / glm::dvec3(majorants_.dims);
        tbb::parallel_for(0, majorants_.dims.z, [&](int z) {
            for (int y = 0; y < majorants_.dims.y; ++y)
                for (int x = 0; x < majorants_.dims.x; ++x) {
                    const glm::dvec3 a = majorants_.lo + glm::dvec3(x, y, z) * size;
                    float tight;
                    float& c = m[(std::size_t(z) * majorants_.dims.y + y) * majorants_.dims.x + x];
                    if (c > 0.0f && dense.maxOver(a, a + size, tight)) c = std::min(c, tight);
                }
        });
        for (std::size_t i = 0; i < n; ++i)
            sum[i] += scale * std::max(0.0, double(m[i]));
        if (v.channel.empty()) continue;
        // An emission grid emits where the density may be 0: the cells of the volume's box keep
        // 1/20 of the one global majorant, so the null-collision estimator samples its emission.
        const glm::ivec3 c0 = majorants_.cellOf(v.lo), c1 = majorants_.cellOf(v.hi);
        for (int z = c0.z; z <= c1.z; ++z)
            for (int y = c0.y; y <= c1.y; ++y)
                for (int x = c0.x; x <= c1.x; ++x) {
                    double& c =
                        sum[(std::size_t(z) * majorants_.dims.y + y) * majorants_.dims.x + x];
                    c = std::max(c, 0.05 * majorant_);
                }
    }
    // Rounded up to float: a cell's value bounds every sample in it.
    majorants_.values.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float f = float(sum[i]);
        majorants_.values[i] = double(f) < sum[i] ? std::nextafter(f, 1e30f) : f;
    }
}

VolumePathTracer::Local VolumePathTracer::localAt(Medium::Lookup& lookup, const glm::dvec3& p,
                                                  std::vector<double>* perVolume) const {
    Local m;
    const std::vector<Medium::Volume>& volumes = medium_.volumes();
    for (std::size_t i = 0; i < volumes.size(); ++i) {
        const Medium::Volume& v = volumes[i];
        Medium::Point point;
        if (!v.channel.empty() || !dense_[i].valid())
            point = medium_.sample(lookup, i, p);
        else if (!glm::any(glm::lessThan(p, v.lo)) && !glm::any(glm::greaterThan(p, v.hi)))
            point.density = dense_[i].sample(p, lookup.density[i]); // Medium::sample's density
        const double density = std::max(0.0, point.density);
        const double sigma = double(volumes[i].ref->densityScale) * density;
        if (perVolume) (*perVolume)[i] = sigma;
        m.sigma += sigma;
        if (density > 0.0 || point.channel != glm::dvec3(0.0))
            m.emission += emittedRadiance(*volumes[i].ref, density, point.channel);
    }
    return m;
}

double VolumePathTracer::transmittance(Medium::Lookup& lookup, const glm::dvec3& o,
                                       const glm::dvec3& d, double tMax, Pcg32& rng) const {
    if (majorant_ <= 0.0) return 1.0;
    MajorantWalk walk(majorants_, o, d, tMax);
    double tr = 1.0;
    for (;;) {
        if (!walk.next(rng)) return tr;
        tr *= 1.0 - localAt(lookup, o + d * walk.t, nullptr).sigma / walk.majorant;
        if (tr < 0.1) {
            if (rng.uniform() >= 0.5) return 0.0;
            tr *= 2.0;
        }
    }
}

glm::dvec3 VolumePathTracer::trace(Medium::Lookup& lookup, glm::dvec3 o, glm::dvec3 d, double tMax,
                                   Pcg32& rng, bool escapeSeesAmbient) const {
    glm::dvec3 radiance(0.0), weight(1.0);
    std::vector<double> perVolume(medium_.volumes().size());
    int events = 0;
    const auto& lights = scene_.lights;
    for (;;) {
        bool collided = false;
        MajorantWalk walk(majorants_, o, d, events == 0 ? tMax : 1e300);
        while (majorant_ > 0.0 && walk.next(rng)) {
            const glm::dvec3 p = o + d * walk.t;
            const Local m = localAt(lookup, p, &perVolume);
            radiance += weight * m.emission / walk.majorant;
            if (rng.uniform() * walk.majorant < m.sigma) {
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
        const scene::VolumeRef& ref = *medium_.volumes()[vi].ref;
        weight *= glm::dvec3(ref.albedo);
        ++events;
        if (weight == glm::dvec3(0.0)) return radiance;
        // Next-event estimation toward every light.
        for (const scene::Light& light : lights) {
            const LightArrival a = lightArrival(light, o);
            if (a.irradiance == glm::dvec3(0.0)) continue;
            // The path runs backwards: light travels along -toLight, then along -d.
            const double phase = henyeyGreenstein(glm::dot(a.toLight, d), double(ref.anisotropy));
            radiance += weight * a.irradiance * phase *
                        transmittance(lookup, o, a.toLight, a.distance, rng);
        }
        if (events >= settings_.rouletteDepth && !roulette(weight, rng)) return radiance;
        d = scatter(d, double(ref.anisotropy), rng);
        tMax = 1e300;
    }
}

glm::dvec3 VolumePathTracer::sample(const scene::Camera& camera, int width, int height, double px,
                                    double py, std::uint64_t pixel, std::uint32_t index) const {
    const CameraRay ray = cameraRay(camera, width, height, px, py);
    Pcg32 rng(mix64((std::uint64_t(settings_.seed) << 32) ^ index), mix64(pixel + 1));
    Medium::Lookup lookup = medium_.lookup();
    return trace(lookup, ray.origin, ray.direction, ray.length, rng);
}

void VolumePathTracer::worldBounds(glm::dvec3& lo, glm::dvec3& hi) const {
    medium_.worldBounds(lo, hi);
}

ScatteredLight VolumePathTracer::scatteredLight(const glm::dvec3& lo, const glm::dvec3& hi,
                                                const glm::ivec3& dims, int samples,
                                                const std::function<void(double)>& progress,
                                                const std::vector<std::uint32_t>& surfaceTexels,
                                                int surfaceSamples) const {
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
    std::atomic<std::size_t> done{0};
    const std::size_t every = std::max<std::size_t>(1, n / 1000);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        const glm::ivec3 c(int(i % dims.x), int((i / dims.x) % dims.y),
                           int(i / (std::size_t(dims.x) * dims.y)));
        const glm::dvec3 x = lo + (glm::dvec3(c) + 0.5) / glm::dvec3(dims) * (hi - lo);
        Medium::Lookup lookup = medium_.lookup();
        glm::dvec3 sum(0.0), g(0.0);
        const int n =
            std::binary_search(surfaceTexels.begin(), surfaceTexels.end(), std::uint32_t(i))
                ? std::max(samples, surfaceSamples)
                : samples;
        for (int k = 0; k < n; ++k) {
            Pcg32 rng(mix64((std::uint64_t(settings_.seed) << 32) ^ std::uint64_t(k)),
                      mix64(std::uint64_t(i) + 0x5ca77e7ull));
            // Uniform direction on the sphere, the path's first direction away from x.
            const double z = 1.0 - 2.0 * rng.uniform(),
                         phi = 2.0 * std::numbers::pi * rng.uniform();
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
            const glm::dvec3 l = trace(lookup, x, d, 1e300, rng, true);
            sum += l;
            g += glm::dot(l, lum) * -d; // the arriving light travels along -d
        }
        const glm::dvec3 mean = sum / double(n);
        out.mean[i] = glm::vec4(glm::vec3(mean), float(glm::dot(mean, lum)));
        out.flux[i] = glm::vec4(glm::vec3(3.0 * g / double(n)), 0.0f);
        if (const std::size_t k = ++done; progress && k % every == 0) progress(double(k) / n);
    });
    return out;
}

glm::dvec3 VolumePathTracer::surfaceIrradiance(const glm::dvec3& p, const glm::dvec3& n,
                                               int samples, std::uint64_t key,
                                               glm::dvec3* standardError) const {
    VEIL_CHECK(samples > 1, "surface irradiance: at least 2 samples ({})", samples);
    // An orthonormal basis around n (as scatter()).
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    const glm::dvec3 t(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    const glm::dvec3 bt(b, sign + n.y * n.y * a, -n.y);
    Medium::Lookup lookup = medium_.lookup();
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int k = 0; k < samples; ++k) {
        Pcg32 rng(mix64((std::uint64_t(settings_.seed) << 32) ^ std::uint64_t(k)),
                  mix64(key + 0x5e7face5ull));
        // Cosine-weighted (Malley's method): pdf cos / pi, so E = pi x mean(L).
        const double r = std::sqrt(rng.uniform()), phi = 2.0 * std::numbers::pi * rng.uniform();
        const double z = std::sqrt(std::max(0.0, 1.0 - r * r));
        const glm::dvec3 d = glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * bt + z * n);
        const glm::dvec3 l = trace(lookup, p, d, 1e300, rng, true);
        sum += l;
        sum2 += l * l;
    }
    const double m = samples;
    const glm::dvec3 mean = sum / m;
    if (standardError)
        *standardError = std::numbers::pi *
                         glm::sqrt(glm::max(glm::dvec3(0.0), sum2 / m - mean * mean) / (m - 1.0));
    return std::numbers::pi * mean;
}

// The cache's grid: fog_scattered_light_cell voxels of the finest volume per texel, over the
// union of the volumes' bounds, at most kScatteredLightMaxTexels per axis (a coarser cell where the
// bounds are larger).
double finestVoxelSize(const scene::Scene& scene,
                       const std::vector<openvdb::FloatGrid::ConstPtr>& grids) {
    double voxel = 1e300;
    std::size_t g = 0;
    for (const auto& ref : scene.volumes) {
        if (ref.procedural == "homogeneous" || g >= grids.size()) continue;
        const openvdb::Vec3d v = grids[g++]->voxelSize();
        const glm::dmat3 m(ref.transform);
        voxel = std::min({voxel, glm::length(m[0]) * v.x(), glm::length(m[1]) * v.y(),
                          glm::length(m[2]) * v.z()});
    }
    return voxel;
}

glm::ivec3 scatteredLightDims(const scene::Scene& scene,
                              const std::vector<openvdb::FloatGrid::ConstPtr>& grids,
                              const glm::dvec3& lo, const glm::dvec3& hi) {
    const double voxel = finestVoxelSize(scene, grids);
    const double cell = std::max(voxel * double(scene.render.fogScatteredLightCell), 1e-12);
    const glm::dvec3 extent = hi - lo;
    return glm::clamp(glm::ivec3(glm::ceil(extent / cell)), glm::ivec3(2),
                      glm::ivec3(kScatteredLightMaxTexels));
}

ScatteredLightSurface scatteredLightSurfaceTexels(const scene::Scene& scene, const glm::dvec3& lo,
                                                  const glm::dvec3& hi, const glm::ivec3& dims) {
    ScatteredLightSurface out;
    const int factor = scene.render.fogScatteredLightSurfaceFactor,
              samples = scene.render.fogScatteredLightSamples;
    if (factor <= 1) return out;
    const glm::dvec3 cell = (hi - lo) / glm::dvec3(dims);
    const std::size_t cells = std::size_t(dims.x) * dims.y * dims.z;
    std::vector<std::uint8_t> listed(cells, 0);
    // Texel c's cell [c, c + 1] grown to [c - 1, c + 2] (in texels from lo) meets [a, b].
    const auto mark = [&](const glm::dvec3& a, const glm::dvec3& b) {
        const glm::dvec3 first = glm::ceil((a - lo) / cell - 2.0),
                         last = glm::floor((b - lo) / cell + 1.0);
        if (glm::any(glm::greaterThan(first, glm::dvec3(dims - 1))) ||
            glm::any(glm::lessThan(last, glm::dvec3(0.0))))
            return;
        const glm::ivec3 c0(glm::max(first, glm::dvec3(0.0))),
            c1(glm::min(last, glm::dvec3(dims - 1)));
        for (int z = c0.z; z <= c1.z; ++z)
            for (int y = c0.y; y <= c1.y; ++y)
                for (int x = c0.x; x <= c1.x; ++x)
                    listed[(std::size_t(z) * dims.y + y) * dims.x + x] = 1;
    };
    for (const scene::Object& o : scene.objects) {
        if (o.mesh >= scene.meshes.size()) continue;
        const scene::MeshData& m = scene.meshes[o.mesh];
        const auto world = [&](const glm::vec3& p) {
            return glm::dvec3(o.transform * glm::vec4(p, 1.0f));
        };
        if (m.billboard || m.indices.empty()) { // the whole object's bounds
            if (m.positions.empty()) continue;
            glm::vec3 mlo, mhi;
            m.bounds(mlo, mhi);
            glm::dvec3 a(1e300), b(-1e300);
            for (int corner = 0; corner < 8; ++corner) {
                const glm::dvec3 w =
                    world({(corner & 1) ? mhi.x : mlo.x, (corner & 2) ? mhi.y : mlo.y,
                           (corner & 4) ? mhi.z : mlo.z});
                a = glm::min(a, w);
                b = glm::max(b, w);
            }
            mark(a, b);
            continue;
        }
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            const glm::dvec3 p0 = world(m.positions[m.indices[t]]),
                             p1 = world(m.positions[m.indices[t + 1]]),
                             p2 = world(m.positions[m.indices[t + 2]]);
            mark(glm::min(p0, glm::min(p1, p2)), glm::max(p0, glm::max(p1, p2)));
        }
    }
    for (std::size_t i = 0; i < cells; ++i)
        if (listed[i]) out.texels.push_back(std::uint32_t(i));
    if (out.texels.empty()) return out;
    // At most as many more paths as the bake's others: the factor for a few texels near a
    // floor, less where surfaces cross much of the grid.
    const std::size_t most = 1 + cells / out.texels.size();
    out.samples = samples * int(std::min<std::size_t>(std::size_t(factor), most));
    if (out.samples <= samples) out.texels.clear();
    return out;
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
