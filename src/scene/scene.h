// The scene: cameras, lights, materials, meshes, volume references and render settings,
// loaded from the JSON format documented in docs/scene-format.md.
#pragma once

#include "scene/material.h"
#include "scene/mesh.h"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace veil::scene {

enum class CameraType { Perspective, Orthographic };

struct Camera {
    std::string name = "default";
    CameraType type = CameraType::Perspective;
    glm::vec3 position{0.0f, 1.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovYDegrees = 45.0f; // perspective: full vertical field of view
    float orthoHeight = 2.0f;  // orthographic: full height of the view volume in world units
    float nearPlane = 0.05f;
    float farPlane = 100.0f;

    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const; // OpenGL clip space, depth -1..1
};

enum class LightType { Directional, Spot, Point };

// Units: a directional light's intensity is the irradiance it gives a surface facing it;
// point and spot intensities are radiant intensity, falling off with 1/d^2.
struct Light {
    std::string name;
    LightType type = LightType::Directional;
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    glm::vec3 position{0.0f, 5.0f, 0.0f}; // spot, point
    glm::vec3 direction{0.0f, -1.0f,
                        0.0f};      // directional, spot: direction light travels (normalized)
    float innerConeDegrees = 20.0f; // spot: half-angle of full intensity
    float outerConeDegrees = 30.0f; // spot: half-angle where intensity reaches zero
    bool castShadows = true;
};

struct Object {
    std::string name;
    std::uint32_t mesh = 0;     // index into Scene::meshes
    std::uint32_t material = 0; // index into Scene::materials
    glm::mat4 transform{1.0f};  // object to world
    bool castShadows = true;
};

// A density field referenced by the scene; loaded by src/grid, rendered by src/fog and the CPU
// integrators (src/integrators).
struct VolumeRef {
    std::string name;
    std::filesystem::path path; // absolute (resolved against the scene file's folder); or:
    // procedural field instead of a file: "box" (density 1 in a box of `size`), "sphere"
    // (density 1 in a ball of diameter size.x), "smoke-ball" (smooth radial falloff with
    // noise), "noise-cloud" (thresholded fractal noise in a box of `size`), or "homogeneous"
    // (global fog of density 1 filling all space; scaled by density_scale)
    std::string procedural;
    glm::vec3 size{1.0f};
    float voxelSize = 0.05f; // procedural grids
    std::uint32_t seed = 1;
    std::string grid = "density";
    glm::mat4 transform{1.0f};
    float densityScale = 1.0f;
    glm::vec3 albedo{0.8f};
    float anisotropy = 0.0f; // Henyey-Greenstein g in (-1,1)
    // Emitted radiance per unit length: emission x density, or emission x the value of
    // `emissionGrid` where one is named; plus, with a `temperatureGrid`, blackbody radiance
    // (integrators/blackbody.h) at T = temperatureScale x value + temperatureOffset (kelvin)
    // times temperatureIntensity x density_scale x density (docs/volumes.md "Emission"). The grids
    // are grids of the volume's file (at most one of the two; the emission grid may be RGB).
    glm::vec3 emission{0.0f};
    std::string emissionGrid;
    std::string temperatureGrid;
    float temperatureScale = 1.0f;
    float temperatureOffset = 0.0f;
    float temperatureIntensity = 1.0f;
};

struct RenderSettings {
    int width = 640;
    int height = 360;
    std::string camera;        // name; empty = first camera
    std::string oit = "blend"; // OIT technique name (registry of src/oit)
    // The technique's properties as written ("render": {"oit": {"type": NAME, ...}}, without
    // "type"; null for the plain string form). Validated against the technique's declared
    // properties when the frame creates it; oitWhere names the place for messages.
    nlohmann::json oitProperties;
    std::string oitWhere = "render.oit";
    // Who rasterizes the transparent pass: "raster" (the hardware) or "compute"
    // (src/frame/stages/compute_raster.*, the techniques that support it).
    std::string oitRasterizer = "raster";
    std::uint32_t seed = 1;
    glm::vec3 ambient{0.03f};   // constant ambient irradiance term (times base color)
    glm::vec3 background{0.0f}; // radiance where nothing is drawn
    float exposure = 1.0f;
    std::string tonemap = "aces"; // "aces" (Narkowicz fit) or "clamp"
    // Shadow technique (registry of src/shadows) and its properties, as for oit. The legacy
    // keys shadow_map_size, shadow_bias and pcf_radius are stored here as size, bias and
    // pcf_radius.
    std::string shadows = "opaque";
    nlohmann::json shadowProperties;
    std::string shadowsWhere = "render.shadows";
    // Screen-space ambient obscurance properties (src/frame/stages/ambient_occlusion.h; null =
    // defaults, off).
    nlohmann::json aoProperties;
    std::string aoWhere = "render.ao";
    // The volumetric path tracer's properties as written ("render": {"pathtraced": {...}}; null =
    // defaults), checked against its declared schema (src/integrators/path_tracer.h) when it
    // runs; pathtracedWhere names the place for messages.
    nlohmann::json pathtracedProperties;
    std::string pathtracedWhere = "render.pathtraced";
    // Fog marcher (src/fog): steps per ray through a volume's bounds, resolution divisor
    // (1 = full, 2 = half, 4 = quarter, joint-bilateral upsampled), jitter of the start.
    int fogSteps = 128;
    int fogResolution = 1;
    bool fogJitter = true;
    // Multiple scattering in the fog marcher by octaves [Wrenninge13, Hillaire16]:
    // octave n (0 .. fogOctaves-1) scatters light with extinction toward the light times a^n,
    // scattering times b^n and phase anisotropy times c^n; 1 octave = single scattering.
    int fogOctaves = 1;
    float fogOctaveExtinction = 0.5f; // a
    float fogOctaveScattering = 0.5f; // b
    float fogOctaveAnisotropy = 0.5f; // c
    // Depth-aware octaves (Veil's addition, docs/volumes.md): octave n >= 1 is weighted by
    // (1 - exp(-tau))^n, tau = radius x the extinction averaged over the point's 8^3-voxel
    // neighbourhood (grid/neighbourhood.h); 0 = off (the octaves of [Wrenninge13]).
    float fogOctaveRadius = 0.0f;
    // Scattered-light cache (docs/scattered-light.md): the marcher adds to its single scattering
    // the light that has scattered before (and the sky), baked by the path tracer on a grid of
    // fogScatteredLightCell voxels per texel, fogScatteredLightSamples paths per texel.
    bool fogScatteredLight = false;
    int fogScatteredLightSamples = 64;
    // Texels that surfaces read with a small footprint (within a texel of an object's triangles)
    // trace this many times fogScatteredLightSamples paths (1: as many as the others).
    int fogScatteredLightSurfaceFactor = 8;
    float fogScatteredLightCell = 4.0f;
    // Where the cache is baked: "gpu" (compute shader), "cpu" (the path tracer) or "auto".
    std::string fogScatteredLightBake = "auto";
    // The viewer's progressive bake: GPU milliseconds per frame (0: the whole bake before the
    // frame). `veil render` and Python bake the whole cache before the frame whatever it says.
    float fogScatteredLightBudgetMs = 2.0f;
    // ... and at most this frame time (ms): the bake also takes what the previous frame's
    // passes left of it (fog/scattered_light_cache.h progressiveBakeMs). 0: the budget alone.
    float fogScatteredLightFrameMs = 25.0f;
    float fogAmbient = 1.0f; // scale of the isotropic ambient (sky) in-scattering
    // GPU memory budget for all volumes (MiB); larger grids are coarsened or refused.
    int volumeBudgetMiB = 1024;
    // Frame ranges: GPU memory for the grid volumes' frames held on the GPU (MiB, shared
    // equally by the grid volumes; fog/gpu_volume.h): a frame shown again is not uploaded.
    // 0: none held.
    int sequenceGpuCacheMiB = 1024;
    // Memory for procedural geometry (particle clouds): larger clouds are refused before
    // anything is allocated, with the estimate in the message.
    int geometryBudgetMiB = 2048;
    // Fog marcher work limit in samples (pixels marched x steps), checked before the first
    // frame; -1 = automatic: 3e8 on software renderers (llvmpipe marches about 1e5-1e6
    // samples per second), none on GPUs; 0 = no limit.
    long long fogSampleLimit = -1;
    std::string volumeOverBudget = "coarsen"; // "coarsen" or "refuse"
};

struct Scene {
    std::filesystem::path sourcePath;
    std::vector<Camera> cameras;
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<MeshData> meshes;
    std::vector<Object> objects;
    std::vector<VolumeRef> volumes;
    RenderSettings render;

    const Camera& camera(const std::string& name = {}) const; // throws if not found
    // World-space bounds of all objects.
    void bounds(glm::vec3& lo, glm::vec3& hi) const;
};

// Applies "key=value" overrides (key is a dotted JSON path such as render.width or
// lights.0.intensity; value is parsed as JSON, else taken as a string) to the document.
void applyOverrides(nlohmann::json& doc, const std::vector<std::string>& overrides);

// Parses a scene document. Relative file paths are resolved against baseDir. Unknown keys
// and bad values throw veil::Error naming the JSON path (e.g. "/objects/2/material").
Scene parseScene(const nlohmann::json& doc, const std::filesystem::path& baseDir);

// Techniques chosen on the command line (`--oit NAME`, `--shadows NAME`; empty: the scene's).
// Applied to the document before the overrides, so `--shadows moment --set
// render.shadows.storage=quantized16` sets a property of the chosen technique and an unknown
// key is the technique's error. The document's properties are kept when it already names the
// same technique and dropped when it names another (they are that technique's).
struct TechniqueChoice {
    std::string oit, shadows;
};
void applyTechniqueChoice(nlohmann::json& doc, const TechniqueChoice& choice);

// Reads and parses a scene file, applying the technique choice and the overrides first.
Scene loadScene(const std::filesystem::path& path, const std::vector<std::string>& overrides = {},
                const TechniqueChoice& choice = {});

} // namespace veil::scene
