#include "integrators/medium.h"

#include "base/error.h"
#include "grid/density_grid.h"
#include "integrators/emission.h"
#include "integrators/ray_box.h"

#include <openvdb/tools/Interpolation.h>

namespace veil::volume {

LightArrival lightArrival(const scene::Light& light, const glm::dvec3& p) {
    LightArrival a;
    a.irradiance = glm::dvec3(light.color) * double(light.intensity);
    if (light.type == scene::LightType::Directional) {
        a.toLight = -glm::normalize(glm::dvec3(light.direction));
        return a;
    }
    const glm::dvec3 d = glm::dvec3(light.position) - p;
    const double d2 = std::max(glm::dot(d, d), 1e-16);
    a.distance = std::sqrt(d2);
    a.toLight = d / a.distance;
    a.irradiance /= d2;
    if (light.type == scene::LightType::Spot)
        a.irradiance *=
            smoothstep(std::cos(glm::radians(double(light.outerConeDegrees))),
                       std::cos(glm::radians(double(light.innerConeDegrees))),
                       glm::dot(-a.toLight, glm::normalize(glm::dvec3(light.direction))));
    return a;
}

CameraRay cameraRay(const scene::Camera& camera, int width, int height, double px, double py) {
    const glm::dmat4 vp =
        glm::dmat4(camera.projection(float(width) / float(height))) * glm::dmat4(camera.view());
    const glm::dmat4 inv = glm::inverse(vp);
    const double nx = px / width * 2.0 - 1.0, ny = 1.0 - py / height * 2.0;
    const glm::dvec4 a = inv * glm::dvec4(nx, ny, -1.0, 1.0),
                     b = inv * glm::dvec4(nx, ny, 1.0, 1.0);
    const glm::dvec3 ro = glm::dvec3(a) / a.w, re = glm::dvec3(b) / b.w;
    CameraRay ray;
    ray.origin = ro;
    ray.length = glm::length(re - ro);
    ray.direction = (re - ro) / ray.length;
    return ray;
}

std::vector<openvdb::FloatGrid::ConstPtr> loadMediumGrids(const scene::Scene& scene) {
    std::vector<openvdb::FloatGrid::ConstPtr> grids;
    for (const scene::VolumeRef& v : scene.volumes)
        if (v.procedural != "homogeneous") grids.push_back(loadVolume(v));
    return grids;
}

Medium::Medium(const scene::Scene& scene, std::vector<openvdb::FloatGrid::ConstPtr> grids,
               const std::string& integrator, bool allowHomogeneous) {
    std::size_t g = 0;
    for (const auto& ref : scene.volumes) {
        if (ref.procedural == "homogeneous") {
            VEIL_CHECK(allowHomogeneous,
                       "{}: volume '{}' is homogeneous fog filling all space, which paths never "
                       "leave (give it bounds: a box volume)",
                       integrator, ref.name);
            Homogeneous& h = homogeneous_;
            h.albedo = (h.albedo * h.density + glm::dvec3(ref.albedo) * double(ref.densityScale)) /
                       std::max(h.density + ref.densityScale, 1e-20);
            h.anisotropy = ref.anisotropy;
            h.density += ref.densityScale;
            continue;
        }
        VEIL_CHECK(g < grids.size() && grids[g], "{}: no grid for volume '{}'", integrator,
                   ref.name);
        Volume v{&ref, grids[g++], glm::inverse(glm::dmat4(ref.transform)), {}, {}, {}};
        gridWorldBox(*v.grid, ref.transform, v.lo, v.hi);
        v.channel = loadEmissionChannel(ref);
        widenToEmission(ref, v.channel, v.lo, v.hi);
        volumes_.push_back(v);
    }
}

Medium::Lookup Medium::lookup() const {
    Lookup lookup;
    for (const auto& v : volumes_) {
        lookup.density.push_back(v.grid->getConstAccessor());
        lookup.channel.emplace_back();
        for (const auto& g : v.channel)
            lookup.channel.back().push_back(g->getConstAccessor());
    }
    return lookup;
}

double Medium::density(Lookup& lookup, std::size_t volume, const glm::dvec3& world) const {
    const Volume& v = volumes_[volume];
    if (outside(v, world)) return 0.0;
    const glm::dvec3 o = glm::dvec3(v.worldToObject * glm::dvec4(world, 1.0));
    const openvdb::Vec3d idx = v.grid->worldToIndex(openvdb::Vec3d(o.x, o.y, o.z));
    return openvdb::tools::BoxSampler::sample(lookup.density[volume], idx);
}

Medium::Point Medium::sample(Lookup& lookup, std::size_t volume, const glm::dvec3& world) const {
    const Volume& v = volumes_[volume];
    Point p;
    if (outside(v, world)) return p;
    const glm::dvec3 o = glm::dvec3(v.worldToObject * glm::dvec4(world, 1.0));
    const openvdb::Vec3d idx = v.grid->worldToIndex(openvdb::Vec3d(o.x, o.y, o.z));
    p.density = openvdb::tools::BoxSampler::sample(lookup.density[volume], idx);
    if (!v.channel.empty()) p.channel = sampleChannel(v.channel, lookup.channel[volume], o);
    return p;
}

bool Medium::interval(const glm::dvec3& o, const glm::dvec3& d, double& t0, double& t1) const {
    return rayBoxesInterval(o, d, volumes_, t0, t1);
}

void Medium::worldBounds(glm::dvec3& lo, glm::dvec3& hi) const {
    lo = glm::dvec3(1e300);
    hi = glm::dvec3(-1e300);
    for (const auto& v : volumes_) {
        lo = glm::min(lo, v.lo);
        hi = glm::max(hi, v.hi);
    }
}

} // namespace veil::volume
