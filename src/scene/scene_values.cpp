// The declarations of the scene's plain values (scene_values.h says what reads them). To add a
// value: a field in scene.h and one line here; the parser, `--set`, the report and (with a
// group) the viewer's widgets follow. Keep the viewer's range inside the accepted range
// (ValuePropertiesTest sets every widget's ends in a document and parses it).
#include "scene/scene_values.h"

namespace veil::scene {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr AcceptedRange kNonNegative{0.0, kInf};
constexpr AcceptedRange kPositive{0.0, kInf, true};
constexpr AcceptedRange kUnit{0.0, 1.0};

// Declarations in parse order, with modifiers applying to the last one.
template <class S>
class Decls {
public:
    template <class F>
    Decls& integer(std::string key, F S::*field, long long lo, long long hi, std::string doc,
                   std::string citation = {}) {
        ValueDecl<S>& d =
            add(PropertyType::Int, std::move(key), field, std::move(doc), std::move(citation));
        d.accepted = {double(lo), double(hi)};
        d.widgetMin = double(lo);
        d.widgetMax = double(hi);
        return *this;
    }
    Decls& real(std::string key, float S::*field, AcceptedRange accepted, double widgetMin,
                double widgetMax, std::string doc, std::string citation = {}) {
        ValueDecl<S>& d =
            add(PropertyType::Float, std::move(key), field, std::move(doc), std::move(citation));
        d.accepted = accepted;
        d.widgetMin = widgetMin;
        d.widgetMax = widgetMax;
        return *this;
    }
    Decls& boolean(std::string key, bool S::*field, std::string doc, std::string citation = {}) {
        add(PropertyType::Bool, std::move(key), field, std::move(doc), std::move(citation));
        return *this;
    }
    // Non-negative RGB by default; a single number means grey.
    Decls& color(std::string key, glm::vec3 S::*field, std::string doc,
                 AcceptedRange accepted = kNonNegative) {
        ValueDecl<S>& d = add(PropertyType::Color, std::move(key), field, std::move(doc), {});
        d.accepted = accepted;
        d.scalarAllowed = true;
        return *this;
    }
    // Any three finite numbers.
    Decls& vec3(std::string key, glm::vec3 S::*field, double widgetMin, double widgetMax,
                std::string doc) {
        ValueDecl<S>& d = add(PropertyType::Vec3, std::move(key), field, std::move(doc), {});
        d.widgetMin = widgetMin;
        d.widgetMax = widgetMax;
        return *this;
    }
    // Any string (a name).
    Decls& text(std::string key, std::string S::*field, std::string doc) {
        add(PropertyType::String, std::move(key), field, std::move(doc), {});
        return *this;
    }
    Decls& choice(std::string key, std::string S::*field, std::vector<std::string> choices,
                  std::string doc, std::string citation = {}) {
        add(PropertyType::Enum, std::move(key), field, std::move(doc), std::move(citation))
            .choices = std::move(choices);
        return *this;
    }

    // The viewer edits the last value in the panel of `group`, for the types of `editedFor`.
    Decls& edited(ValueGroup group, unsigned editedFor = ~0u, int panelOrder = 0) {
        decls_.back().group = group;
        decls_.back().editedFor = editedFor;
        decls_.back().panelOrder = panelOrder;
        return *this;
    }
    // What the viewer redoes when it edits the last value (Rebuild unless given).
    Decls& onEdit(EditEffect effect) {
        decls_.back().edit = effect;
        return *this;
    }
    // Only the documents of these types accept the last key.
    Decls& acceptedBy(unsigned types) {
        decls_.back().acceptedBy = types;
        return *this;
    }
    Decls& refuse(long long value, std::string message) {
        decls_.back().refused = value;
        decls_.back().refusedMessage = std::move(message);
        return *this;
    }

    std::vector<ValueDecl<S>> done() { return std::move(decls_); }

private:
    ValueDecl<S>& add(PropertyType type, std::string key, typename ValueDecl<S>::Field field,
                      std::string doc, std::string citation) {
        ValueDecl<S> d;
        d.type = type;
        d.key = std::move(key);
        d.field = field;
        d.doc = std::move(doc);
        d.citation = std::move(citation);
        decls_.push_back(std::move(d));
        return decls_.back();
    }
    std::vector<ValueDecl<S>> decls_;
};

unsigned bit(LightType t) { return typeBit(int(t)); }
unsigned bit(CameraType t) { return typeBit(int(t)); }

} // namespace

const std::vector<ValueDecl<RenderSettings>>& renderValueDecls() {
    using R = RenderSettings;
    static const std::vector<ValueDecl<R>> decls =
        Decls<R>()
            .integer("width", &R::width, 1, 16384, "image width in pixels")
            .integer("height", &R::height, 1, 16384, "image height in pixels")
            .integer("seed", &R::seed, 0, std::numeric_limits<std::uint32_t>::max(),
                     "seed of the frame's random choices (stochastic techniques, fog jitter)")
            .color("ambient", &R::ambient, "constant ambient irradiance (times the base colour)")
            .edited(ValueGroup::RenderOutput)
            .onEdit(EditEffect::Live)
            .color("background", &R::background, "radiance where nothing is drawn")
            .edited(ValueGroup::RenderOutput)
            .onEdit(EditEffect::Live)
            // The parser takes any exposure > 0; the widget's range is what a tone map can use.
            .real("exposure", &R::exposure, kPositive, 1e-3, 1e3,
                  "multiplies the linear radiance before the tone map")
            .edited(ValueGroup::RenderOutput, ~0u, -1)
            .onEdit(EditEffect::Live)
            .choice("oit_rasterizer", &R::oitRasterizer, {"raster", "compute"},
                    "who rasterizes the transparent pass: the hardware, or compute shaders "
                    "(blend, wboit, reference; docs/oit.md \"Compute rasterizer\")",
                    "[Laine11]")
            .choice("tonemap", &R::tonemap, {"aces", "clamp"},
                    "aces: Narkowicz's fit of the ACES filmic curve; clamp: none", "[Narkowicz16]")
            .edited(ValueGroup::RenderOutput)
            .onEdit(EditEffect::Live)
            .integer("fog_steps", &R::fogSteps, 1, 4096,
                     "ray-march steps per ray through the volumes' bounds", "[McGuire17 sec. 7.2]")
            .edited(ValueGroup::FogMarcher)
            .onEdit(EditEffect::ShadowMaps)
            .integer("fog_resolution", &R::fogResolution, 1, 4,
                     "marching resolution divisor: 1, 2 or 4 (3 is refused), joint-bilateral "
                     "upsampled on depth",
                     "[McGuire16 sec. 5] (Upsample)")
            .refuse(3, "must be 1, 2 or 4")
            .edited(ValueGroup::FogMarcher)
            .boolean("fog_jitter", &R::fogJitter,
                     "per-pixel random start offset of the march (seeded by render.seed)")
            .edited(ValueGroup::FogMarcher)
            .onEdit(EditEffect::ShadowMaps)
            .integer("fog_octaves", &R::fogOctaves, 1, 16,
                     "multiple-scattering octaves of the fog marcher (1 = single scattering)",
                     "[Wrenninge13], [Hillaire16]")
            .edited(ValueGroup::FogMarcher)
            .real("fog_octave_extinction", &R::fogOctaveExtinction, kUnit, 0.0, 1.0,
                  "a: octave n's extinction toward the light is a^n times the medium's",
                  "[Wrenninge13]")
            .edited(ValueGroup::FogMarcher)
            .real("fog_octave_scattering", &R::fogOctaveScattering, kUnit, 0.0, 1.0,
                  "b: octave n's scattering is b^n times the medium's", "[Wrenninge13]")
            .edited(ValueGroup::FogMarcher)
            .real("fog_octave_anisotropy", &R::fogOctaveAnisotropy, kUnit, 0.0, 1.0,
                  "c: octave n's Henyey-Greenstein g is c^n times the medium's", "[Wrenninge13]")
            .edited(ValueGroup::FogMarcher)
            .real("fog_octave_radius", &R::fogOctaveRadius, kNonNegative, 0.0, 1e6,
                  "depth-aware octaves: octave n >= 1 weighted by (1 - exp(-tau))^n, tau = this "
                  "radius (world units) x the extinction averaged over 8^3 voxels; 0 = off",
                  "docs/volumes.md")
            .edited(ValueGroup::FogMarcher)
            .boolean("fog_scattered_light", &R::fogScatteredLight,
                     "multiple scattering from a cache of the light scattered before (and the "
                     "sky), baked by the path tracer per light: P1 per texel (replaces "
                     "fog_octaves and fog_ambient)",
                     "docs/scattered-light.md")
            .edited(ValueGroup::FogMarcher)
            .integer("fog_scattered_light_samples", &R::fogScatteredLightSamples, 1, 1 << 16,
                     "paths traced per texel of the scattered-light cache")
            .edited(ValueGroup::FogMarcher)
            .integer("fog_scattered_light_surface_factor", &R::fogScatteredLightSurfaceFactor, 1,
                     64,
                     "the scattered-light cache's texels within a texel of an object's triangles "
                     "(which surfaces read with a small footprint) trace this many times "
                     "fog_scattered_light_samples paths (1: as many as the others)",
                     "docs/scattered-light.md")
            .edited(ValueGroup::FogMarcher)
            .real("fog_scattered_light_cell", &R::fogScatteredLightCell, {0.25, 64.0}, 0.25, 64.0,
                  "voxels per texel of the scattered-light cache (at most 128 texels per axis)")
            .edited(ValueGroup::FogMarcher)
            .choice("fog_scattered_light_bake", &R::fogScatteredLightBake, {"auto", "gpu", "cpu"},
                    "where the scattered-light cache is baked: a compute shader (gpu), the path "
                    "tracer (cpu) or auto (the GPU on hardware, the CPU on software renderers)")
            .edited(ValueGroup::FogMarcher)
            .real("fog_scattered_light_budget_ms", &R::fogScatteredLightBudgetMs, kNonNegative, 0.0,
                  100.0,
                  "the viewer's progressive bake: GPU milliseconds per frame for the scattered-"
                  "light cache after a light, ambient or volume edit, frames drawing with the "
                  "paths so far until all are in; 0 = the whole bake before the frame (veil "
                  "render and Python always bake it whole)")
            .edited(ValueGroup::FogMarcher)
            .onEdit(EditEffect::Live)
            .real("fog_scattered_light_frame_ms", &R::fogScatteredLightFrameMs, kNonNegative, 0.0,
                  1000.0,
                  "the viewer's progressive bake also takes what the previous frame's passes "
                  "left of a frame of this many milliseconds (25: 40 frames a second), so that "
                  "the cache converges as fast as that frame rate allows; 0 = the budget alone")
            .edited(ValueGroup::FogMarcher)
            .onEdit(EditEffect::Live)
            .real("fog_ambient", &R::fogAmbient, kNonNegative, 0.0, 4.0,
                  "scale of the fog's isotropic ambient (sky) in-scattering, render.ambient x "
                  "sigma_s x fog_ambient")
            .edited(ValueGroup::FogMarcher)
            .integer("volume_budget_mib", &R::volumeBudgetMiB, 1, 1 << 20,
                     "GPU memory for all volumes, MiB (larger grids: volume_over_budget)")
            .integer("sequence_gpu_cache_mib", &R::sequenceGpuCacheMiB, 0, 1 << 20,
                     "frame ranges, the viewer's timeline: GPU memory for volume frames kept "
                     "uploaded, shared by the grid volumes, MiB; a frame shown again uploads "
                     "nothing; 0 = none kept",
                     "docs/sequences.md")
            .choice("volume_over_budget", &R::volumeOverBudget, {"coarsen", "refuse"},
                    "what volumes over volume_budget_mib get: coarsened grids or an error")
            .integer("geometry_budget_mib", &R::geometryBudgetMiB, 1, 1 << 20,
                     "memory for procedural geometry (particle clouds), MiB; larger clouds are "
                     "refused before anything is allocated")
            .integer("fog_sample_limit", &R::fogSampleLimit, -1, 1LL << 50,
                     "fog marcher work limit in samples (pixels marched x steps): -1 automatic "
                     "(3e8 on software renderers, none on GPUs), 0 none")
            .done();
    return decls;
}

const std::vector<ValueDecl<VolumeRef>>& volumeValueDecls() {
    using V = VolumeRef;
    static const std::vector<ValueDecl<V>> decls =
        Decls<V>()
            .real("density_scale", &V::densityScale, kNonNegative, 0.0, 1e4,
                  "extinction coefficient per unit density (sigma_t = scale x density)",
                  "[McGuire17 sec. 7.2]")
            .edited(ValueGroup::Volume)
            .onEdit(EditEffect::Relight)
            .color("albedo", &V::albedo, "single-scattering albedo sigma_s / sigma_t, in [0, 1]",
                   kUnit)
            .edited(ValueGroup::Volume)
            .onEdit(EditEffect::Relight)
            .real("anisotropy", &V::anisotropy, {-1.0, 1.0, true, true}, -0.99, 0.99,
                  "Henyey-Greenstein phase function g", "[Henyey41]")
            .edited(ValueGroup::Volume)
            .onEdit(EditEffect::Relight)
            .color("emission", &V::emission,
                   "emitted radiance per unit length per unit density (per unit of "
                   "emission_grid where one is named)")
            .edited(ValueGroup::Volume)
            .onEdit(EditEffect::Relight)
            .text("emission_grid", &V::emissionGrid,
                  "scalar or vec3 (RGB) grid of the volume's file whose value times emission is "
                  "the emitted radiance per unit length (instead of the density)")
            .text("temperature_grid", &V::temperatureGrid,
                  "scalar grid of the volume's file rendered as blackbody emission")
            .real("temperature_scale", &V::temperatureScale, {0.0, 1e5}, 0.0, 10000.0,
                  "kelvin per unit of temperature_grid (T = scale x value + offset)", "[CIE15]")
            .edited(ValueGroup::Volume)
            .real("temperature_offset", &V::temperatureOffset, {-1e5, 1e5}, -1000.0, 5000.0,
                  "kelvin added to temperature_scale x value")
            .edited(ValueGroup::Volume)
            .real("temperature_intensity", &V::temperatureIntensity, {0.0, 1e3}, 0.0, 10.0,
                  "blackbody emission per unit length = intensity x density_scale x density x "
                  "Planck radiance (kW m^-2 sr^-1, CIE 1931 to linear sRGB); 1 = physical")
            .edited(ValueGroup::Volume)
            .done();
    return decls;
}

const std::vector<ValueDecl<Light>>& lightValueDecls() {
    const unsigned spot = bit(LightType::Spot), placed = spot | bit(LightType::Point);
    static const std::vector<ValueDecl<Light>> decls =
        Decls<Light>()
            .color("color", &Light::color, "light colour (times intensity)")
            .edited(ValueGroup::Light)
            .onEdit(EditEffect::Relight)
            .real("intensity", &Light::intensity, kNonNegative, 0.0, 1e6,
                  "directional: irradiance; spot/point: radiant intensity (falls off as 1/d^2)")
            .edited(ValueGroup::Light)
            .onEdit(EditEffect::Relight)
            // Which lights have shadow maps: a new renderer.
            .boolean("shadows", &Light::castShadows, "whether the light casts shadows")
            .vec3("position", &Light::position, -1e6, 1e6, "world position")
            .edited(ValueGroup::Light, placed)
            .onEdit(EditEffect::Relight)
            .real("inner_cone", &Light::innerConeDegrees, {0.0, 90.0}, 0.0, 90.0,
                  "half-angle of full intensity, degrees")
            .acceptedBy(spot)
            .edited(ValueGroup::Light, spot)
            .onEdit(EditEffect::Relight)
            .real("outer_cone", &Light::outerConeDegrees, {0.0, 90.0}, 0.0, 90.0,
                  "half-angle where the intensity reaches zero, degrees (>= inner_cone)")
            .acceptedBy(spot)
            .edited(ValueGroup::Light, spot)
            .onEdit(EditEffect::Relight)
            .done();
    return decls;
}

const std::vector<ValueDecl<Camera>>& cameraValueDecls() {
    const unsigned perspective = bit(CameraType::Perspective),
                   orthographic = bit(CameraType::Orthographic);
    static const std::vector<ValueDecl<Camera>> decls =
        Decls<Camera>()
            .vec3("position", &Camera::position, -1e6, 1e6, "eye position")
            .vec3("target", &Camera::target, -1e6, 1e6, "point looked at")
            .vec3("up", &Camera::up, -1.0, 1.0, "up direction (not parallel to the view)")
            .real("near", &Camera::nearPlane, kPositive, 1e-5, 1e5, "near plane distance (< far)")
            .edited(ValueGroup::Camera)
            .real("far", &Camera::farPlane, kPositive, 1e-4, 1e7, "far plane distance")
            .edited(ValueGroup::Camera)
            .real("fov_y", &Camera::fovYDegrees, {0.0, 180.0, true, true}, 1.0, 179.0,
                  "full vertical field of view, degrees")
            .acceptedBy(perspective)
            .edited(ValueGroup::Camera, perspective, -1)
            .real("ortho_height", &Camera::orthoHeight, kPositive, 1e-4, 1e5,
                  "full height of the view volume, world units")
            .acceptedBy(orthographic)
            .edited(ValueGroup::Camera, orthographic, -1)
            .done();
    return decls;
}

const std::vector<ValueDecl<TimeSettings>>& timeValueDecls() {
    static const std::vector<ValueDecl<TimeSettings>> decls =
        Decls<TimeSettings>()
            .real("fps", &TimeSettings::fps, {0.0, 1000.0, true, false}, 1.0, 120.0,
                  "frames per second of playback and of encoded video")
            .integer("frame", &TimeSettings::frame, -(1LL << 30), 1LL << 30,
                     "the frame a still render, the viewer and regression cases show (default: "
                     "the first of the scene's frames)")
            .integer("prefetch_budget_mib", &TimeSettings::prefetchBudgetMiB, 1, 1 << 20,
                     "frame ranges: memory for the grids of frames read ahead of the one "
                     "rendered, MiB (the next frame is always read)")
            .done();
    return decls;
}

const std::vector<ValueDecl<SequenceValues>>& sequenceValueDecls() {
    using Q = SequenceValues;
    static const std::vector<ValueDecl<Q>> decls =
        Decls<Q>()
            .integer("frame_offset", &Q::frameOffset, -(1 << 30), 1 << 30,
                     "file frame = scene frame + frame_offset")
            .choice("before", &Q::before, {"hold", "loop", "blank"},
                    "before the first frame: hold it, loop the range, or no volume")
            .choice("after", &Q::after, {"hold", "loop", "blank"},
                    "after the last frame: hold it, loop the range, or no volume")
            .choice("missing", &Q::missing, {"error", "hold"},
                    "a missing file inside the range: an error naming it, or hold the nearest "
                    "earlier (else later) frame")
            .done();
    return decls;
}

const std::vector<ValueDecl<Material>>& materialValueDecls() {
    using M = Material;
    static const std::vector<ValueDecl<M>> decls =
        Decls<M>()
            // The shading values are edited in place; alpha and transmission can change the
            // shadow technique's caster classes (a new renderer).
            .color("base_color", &M::baseColor, "diffuse albedo (metals: specular colour)")
            .onEdit(EditEffect::ShadowMaps)
            .real("roughness", &M::roughness, kUnit, 0.0, 1.0, "perceptual GGX roughness")
            .onEdit(EditEffect::ShadowMaps)
            .real("metalness", &M::metalness, kUnit, 0.0, 1.0, "0 dielectric, 1 metal")
            .onEdit(EditEffect::ShadowMaps)
            .color("emission", &M::emission, "emitted radiance")
            .onEdit(EditEffect::ShadowMaps)
            .real("alpha", &M::alpha, kUnit, 0.0, 1.0, "coverage alpha", "[McGuire16 Eq. 2]")
            .color("transmission", &M::transmission,
                   "transmission T at normal incidence: lets 1 - alpha + alpha T through", kUnit)
            .real("collimation", &M::collimation, kUnit, 0.0, 1.0,
                  "how much transmitted light keeps its direction (0: fully diffused)",
                  "[McGuire16 sec. 3]")
            .real("ior", &M::ior, {1.0, kInf}, 1.0, 3.0, "index of refraction")
            .color("attenuation_color", &M::attenuationColor,
                   "glTF KHR_materials_volume attenuation colour")
            .real("attenuation_distance", &M::attenuationDistance, kNonNegative, 0.0, 1e4,
                  "distance at which attenuation_color is reached (0: infinite)")
            .real("thickness", &M::thickness, kNonNegative, 0.0, 1e4,
                  "glTF KHR_materials_volume thickness")
            .real("coverage_edge", &M::coverageEdge, {0.0, 0.5}, 0.0, 0.5,
                  "width in UV units of a binary coverage mask's filtered edge (0: none)",
                  "[McGuire17 sec. 6]")
            .done();
    return decls;
}

namespace {

template <class S>
nlohmann::json allValues(const std::vector<ValueDecl<S>>& decls, const S& s, int typeIndex) {
    nlohmann::json out = nlohmann::json::object();
    for (const ValueDecl<S>& d : decls)
        if (d.acceptedBy & typeBit(typeIndex)) out[d.key] = valueJson(d, s);
    return out;
}

} // namespace

nlohmann::json sceneValues(const Scene& scene) {
    nlohmann::json out = {{"render", allValues(renderValueDecls(), scene.render, 0)},
                          {"cameras", nlohmann::json::array()},
                          {"lights", nlohmann::json::array()},
                          {"materials", nlohmann::json::object()},
                          {"volumes", nlohmann::json::array()}};
    for (const Camera& c : scene.cameras)
        out["cameras"].push_back(allValues(cameraValueDecls(), c, int(c.type)));
    for (const Light& l : scene.lights)
        out["lights"].push_back(allValues(lightValueDecls(), l, int(l.type)));
    for (const Material& m : scene.materials)
        out["materials"][m.name] = allValues(materialValueDecls(), m, 0);
    for (const VolumeRef& v : scene.volumes)
        out["volumes"].push_back(allValues(volumeValueDecls(), v, 0));
    return out;
}

} // namespace veil::scene
