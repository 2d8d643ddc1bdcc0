#include "scene/value_properties.h"

namespace veil::scene {

namespace {

nlohmann::json vec(const glm::vec3& v) {
    return nlohmann::json::array({double(v.x), double(v.y), double(v.z)});
}

} // namespace

const PropertySchema& fogMarcherProperties() {
    static const PropertySchema schema = [] {
        const RenderSettings d;
        PropertySchema s;
        s.integer("fog_steps", d.fogSteps, 1, 4096,
                  "ray-march steps per ray through the volumes' bounds", "001 sec. 7.2")
            .integer("fog_resolution", d.fogResolution, 1, 4,
                     "marching resolution divisor: 1, 2 or 4 (3 is refused), joint-bilateral "
                     "upsampled on depth",
                     "000 sec. 5 (Upsample)")
            .boolean("fog_jitter", d.fogJitter,
                     "per-pixel random start offset of the march (seeded by render.seed)");
        return s;
    }();
    return schema;
}

const PropertySchema& renderOutputProperties() {
    static const PropertySchema schema = [] {
        const RenderSettings d;
        PropertySchema s;
        // The parser takes any exposure > 0; the widget's range is what a tone map can use.
        s.real("exposure", d.exposure, 1e-3, 1e3,
               "multiplies the linear radiance before the tone map")
            .color("ambient", d.ambient, "constant ambient irradiance (times the base colour)")
            .color("background", d.background, "radiance where nothing is drawn")
            .choice("tonemap", d.tonemap, {"aces", "clamp"},
                    "aces: Narkowicz's fit of the ACES filmic curve; clamp: none",
                    "Narkowicz 2015, ACES Filmic Tone Mapping Curve");
        return s;
    }();
    return schema;
}

const PropertySchema& volumeProperties() {
    static const PropertySchema schema = [] {
        const VolumeRef d;
        PropertySchema s;
        s.real("density_scale", d.densityScale, 0.0, 1e4,
               "extinction coefficient per unit density (sigma_t = scale x density)",
               "001 sec. 7.2")
            .color("albedo", d.albedo, "single-scattering albedo sigma_s / sigma_t, in [0, 1]")
            .real("anisotropy", d.anisotropy, -0.99, 0.99, "Henyey-Greenstein phase function g",
                  "Henyey & Greenstein 1941")
            .color("emission", d.emission, "emitted radiance per unit density");
        return s;
    }();
    return schema;
}

const PropertySchema& lightProperties(LightType type) {
    auto make = [](LightType t) {
        const Light d;
        PropertySchema s;
        s.color("color", d.color, "light colour (times intensity)")
            .real("intensity", d.intensity, 0.0, 1e6,
                  "directional: irradiance; spot/point: radiant intensity (falls off as 1/d^2)");
        if (t != LightType::Directional)
            s.vec3("position", d.position, -1e6, 1e6, "world position");
        if (t == LightType::Spot)
            s.real("inner_cone", d.innerConeDegrees, 0.0, 90.0,
                   "half-angle of full intensity, degrees")
                .real("outer_cone", d.outerConeDegrees, 0.0, 90.0,
                      "half-angle where the intensity reaches zero, degrees (>= inner_cone)");
        return s;
    };
    static const PropertySchema directional = make(LightType::Directional),
                                spot = make(LightType::Spot), point = make(LightType::Point);
    return type == LightType::Directional ? directional : type == LightType::Spot ? spot : point;
}

const PropertySchema& cameraProperties(CameraType type) {
    auto make = [](CameraType t) {
        const Camera d;
        PropertySchema s;
        if (t == CameraType::Perspective)
            s.real("fov_y", d.fovYDegrees, 1.0, 179.0, "full vertical field of view, degrees");
        else
            s.real("ortho_height", d.orthoHeight, 1e-4, 1e5,
                   "full height of the view volume, world units");
        s.real("near", d.nearPlane, 1e-5, 1e5, "near plane distance (< far)")
            .real("far", d.farPlane, 1e-4, 1e7, "far plane distance");
        return s;
    };
    static const PropertySchema perspective = make(CameraType::Perspective),
                                orthographic = make(CameraType::Orthographic);
    return type == CameraType::Perspective ? perspective : orthographic;
}

nlohmann::json fogMarcherValues(const RenderSettings& r) {
    return {{"fog_steps", r.fogSteps},
            {"fog_resolution", r.fogResolution},
            {"fog_jitter", r.fogJitter}};
}

nlohmann::json renderOutputValues(const RenderSettings& r) {
    return {{"exposure", double(r.exposure)},
            {"ambient", vec(r.ambient)},
            {"background", vec(r.background)},
            {"tonemap", r.tonemap}};
}

nlohmann::json volumeValues(const VolumeRef& v) {
    return {{"density_scale", double(v.densityScale)},
            {"albedo", vec(v.albedo)},
            {"anisotropy", double(v.anisotropy)},
            {"emission", vec(v.emission)}};
}

nlohmann::json lightValues(const Light& l) {
    nlohmann::json j = {{"color", vec(l.color)}, {"intensity", double(l.intensity)}};
    if (l.type != LightType::Directional) j["position"] = vec(l.position);
    if (l.type == LightType::Spot) {
        j["inner_cone"] = double(l.innerConeDegrees);
        j["outer_cone"] = double(l.outerConeDegrees);
    }
    return j;
}

nlohmann::json cameraValues(const Camera& c) {
    nlohmann::json j = {{"near", double(c.nearPlane)}, {"far", double(c.farPlane)}};
    if (c.type == CameraType::Perspective)
        j["fov_y"] = double(c.fovYDegrees);
    else
        j["ortho_height"] = double(c.orthoHeight);
    return j;
}

} // namespace veil::scene
