// Surface material parameters, shared by procedural scenes and files loaded through assimp.
// Kept apart from scene.h so mesh.h (LoadedMesh) can hold one by value.
#pragma once

#include <glm/glm.hpp>

#include <string>

namespace veil::scene {

// Surface material ([McGuire16 sec. 3] / [McGuire17 sec. 3] parameters for the transmissive part).
struct Material {
    std::string name = "default";
    glm::vec3 baseColor{0.8f};
    float roughness = 0.5f;
    float metalness = 0.0f;
    glm::vec3 emission{0.0f};
    float alpha = 1.0f;           // coverage alpha
    glm::vec3 transmission{0.0f}; // T(lambda): transmission at normal incidence, [McGuire16 Eq. 2]
    float collimation = 1.0f;     // c in [0,1], [McGuire16 sec. 3]
    float ior = 1.5f;             // eta
    // glTF KHR_materials_volume, kept for thickness-aware techniques (voxelize issue).
    glm::vec3 attenuationColor{1.0f};
    float attenuationDistance = 0.0f; // 0 = infinite
    float thickness = 0.0f;
    // Width, in UV units, of the filtered edge of a binary coverage mask (foliage cards): the
    // coverage is alpha x clamp(d / coverageEdge, 0, 1), d the UV distance to the nearest
    // border of [0,1]^2. Veil has no textures; this ramp stands for what MIP-mapping a binary
    // mask gives at its edge [McGuire17 sec. 6]. 0 = none.
    float coverageEdge = 0.0f;

    // Drawn in the transparent pass (coverage below one or any transmission).
    bool isTransparent() const;
    // [McGuire17 sec. 6] `baseMIPisBinary`: no transmission and binary coverage at the base level
    // (alpha 1 with a filtered edge). Such a material is drawn twice: its alpha = 1 interior in
    // the opaque pass (it writes depth, casts and receives AO) and its partial edge in the
    // transparent pass, where the OIT technique may infer AO [McGuire17 Listing 2].
    bool baseCoverageIsBinary() const;
};

} // namespace veil::scene
