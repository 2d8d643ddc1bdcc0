#include "scene/value_properties.h"

#include "scene/scene_values.h"

namespace veil::scene {

const PropertySchema& fogMarcherProperties() {
    static const PropertySchema s = groupSchema(renderValueDecls(), ValueGroup::FogMarcher);
    return s;
}

const PropertySchema& renderOutputProperties() {
    static const PropertySchema s = groupSchema(renderValueDecls(), ValueGroup::RenderOutput);
    return s;
}

const PropertySchema& volumeProperties() {
    static const PropertySchema s = groupSchema(volumeValueDecls(), ValueGroup::Volume);
    return s;
}

const PropertySchema& lightProperties(LightType type) {
    auto make = [](LightType t) {
        return groupSchema(lightValueDecls(), ValueGroup::Light, int(t));
    };
    static const PropertySchema directional = make(LightType::Directional),
                                spot = make(LightType::Spot), point = make(LightType::Point);
    return type == LightType::Directional ? directional : type == LightType::Spot ? spot : point;
}

const PropertySchema& cameraProperties(CameraType type) {
    auto make = [](CameraType t) {
        return groupSchema(cameraValueDecls(), ValueGroup::Camera, int(t));
    };
    static const PropertySchema perspective = make(CameraType::Perspective),
                                orthographic = make(CameraType::Orthographic);
    return type == CameraType::Perspective ? perspective : orthographic;
}

nlohmann::json fogMarcherValues(const RenderSettings& r) {
    return groupValues(renderValueDecls(), ValueGroup::FogMarcher, r);
}

nlohmann::json renderOutputValues(const RenderSettings& r) {
    return groupValues(renderValueDecls(), ValueGroup::RenderOutput, r);
}

nlohmann::json volumeValues(const VolumeRef& v) {
    return groupValues(volumeValueDecls(), ValueGroup::Volume, v);
}

nlohmann::json lightValues(const Light& l) {
    return groupValues(lightValueDecls(), ValueGroup::Light, l, int(l.type));
}

nlohmann::json cameraValues(const Camera& c) {
    return groupValues(cameraValueDecls(), ValueGroup::Camera, c, int(c.type));
}

} // namespace veil::scene
