// Mesh files through assimp: glTF 2.0, OBJ, PLY. Node transforms are baked into the vertices
// (aiProcess_PreTransformVertices) and file materials are mapped to veil::scene::Material as
// documented in docs/scene-format.md ("Materials from mesh files").
#include "scene/mesh.h"

#include "base/error.h"
#include "base/log.h"
#include "scene/mesh_file_check.h"

#include <assimp/GltfMaterial.h>
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <system_error>

namespace veil::scene {

namespace {

bool getFloat(const aiMaterial& m, const char* key, unsigned type, unsigned index, float& out) {
    ai_real v = 0;
    if (m.Get(key, type, index, v) != AI_SUCCESS) return false;
    out = float(v);
    return true;
}

bool getColor(const aiMaterial& m, const char* key, unsigned type, unsigned index, aiColor4D& out) {
    return m.Get(key, type, index, out) == AI_SUCCESS;
}

glm::vec3 rgb(const aiColor4D& c) { return {c.r, c.g, c.b}; }

float clampWarn(float v, float lo, float hi, const char* what, const std::string& material) {
    if (std::isfinite(v) && v >= lo && v <= hi) return v;
    float c = std::isfinite(v) ? std::clamp(v, lo, hi) : lo;
    log::warn("material '{}': {} {} outside [{}, {}], using {}", material, what, v, lo, hi, c);
    return c;
}

glm::vec3 nonNegative(glm::vec3 v) {
    for (int i = 0; i < 3; ++i)
        v[i] = std::isfinite(v[i]) ? std::max(v[i], 0.0f) : 0.0f;
    return v;
}

// glTF 2.0 mapping (assimp 5.2 keys). Only factors are read; textures are ignored.
Material convertMaterial(const aiMaterial& am, bool gltf) {
    Material mat;
    mat.name = am.GetName().C_Str();
    aiColor4D base(0.8f, 0.8f, 0.8f, 1.0f);
    bool haveBase =
        getColor(am, AI_MATKEY_BASE_COLOR, base) || getColor(am, AI_MATKEY_COLOR_DIFFUSE, base);
    if (haveBase) mat.baseColor = nonNegative(rgb(base));

    if (gltf) {
        // glTF: baseColorFactor alpha is coverage only with alphaMode BLEND; MASK is treated
        // as opaque (no per-texel cutout without textures) and OPAQUE ignores alpha.
        aiString mode;
        if (am.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS &&
            std::string(mode.C_Str()) == "BLEND") {
            mat.alpha = base.a;
        }
    } else {
        // OBJ 'd' / PLY: the format's opacity is the coverage alpha.
        float opacity = 1.0f;
        if (getFloat(am, AI_MATKEY_OPACITY, opacity)) mat.alpha = opacity;
    }
    getFloat(am, AI_MATKEY_ROUGHNESS_FACTOR, mat.roughness);
    getFloat(am, AI_MATKEY_METALLIC_FACTOR, mat.metalness);

    aiColor4D emissive(0, 0, 0, 1);
    if (getColor(am, AI_MATKEY_COLOR_EMISSIVE, emissive)) {
        float strength = 1.0f; // KHR_materials_emissive_strength
        getFloat(am, AI_MATKEY_EMISSIVE_INTENSITY, strength);
        mat.emission = nonNegative(rgb(emissive) * strength);
    }

    // KHR_materials_transmission: glTF tints transmitted light by the base color, so
    // T(lambda) = transmissionFactor * baseColor ([McGuire16 Eq. 2]'s per-wavelength transmission).
    float transmission = 0.0f;
    if (getFloat(am, AI_MATKEY_TRANSMISSION_FACTOR, transmission)) {
        transmission = std::clamp(std::isfinite(transmission) ? transmission : 0.0f, 0.0f, 1.0f);
        mat.transmission = glm::clamp(transmission * mat.baseColor, 0.0f, 1.0f);
    }
    getFloat(am, AI_MATKEY_REFRACTI, mat.ior); // KHR_materials_ior, OBJ Ni

    // KHR_materials_volume. glTF's default attenuationDistance is +infinity; ours is 0.
    aiColor4D attenuation(1, 1, 1, 1);
    if (getColor(am, AI_MATKEY_VOLUME_ATTENUATION_COLOR, attenuation))
        mat.attenuationColor = nonNegative(rgb(attenuation));
    float distance = 0.0f;
    if (getFloat(am, AI_MATKEY_VOLUME_ATTENUATION_DISTANCE, distance))
        mat.attenuationDistance = (std::isfinite(distance) && distance < 1e30f) ? distance : 0.0f;
    getFloat(am, AI_MATKEY_VOLUME_THICKNESS_FACTOR, mat.thickness);

    mat.alpha = clampWarn(mat.alpha, 0.0f, 1.0f, "alpha", mat.name);
    mat.roughness = clampWarn(mat.roughness, 0.0f, 1.0f, "roughness", mat.name);
    mat.metalness = clampWarn(mat.metalness, 0.0f, 1.0f, "metalness", mat.name);
    // OBJ files often write Ni 0 or 1 meaning "not set"; values below 1 become 1.
    mat.ior = clampWarn(mat.ior, 1.0f, 10.0f, "ior", mat.name);
    mat.attenuationDistance = std::max(mat.attenuationDistance, 0.0f);
    mat.thickness = clampWarn(mat.thickness, 0.0f, 1e30f, "thickness", mat.name);
    return mat;
}

// "ply" at the start of the file: the token assimp's PLY importer recognises by content.
bool startsWithPlyMagic(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[3] = {0, 0, 0};
    in.read(magic, 3);
    return in.gcount() == 3 && (magic[0] == 'p' || magic[0] == 'P') &&
           (magic[1] == 'l' || magic[1] == 'L') && (magic[2] == 'y' || magic[2] == 'Y');
}

} // namespace

std::vector<LoadedMesh> loadMeshFile(const std::filesystem::path& path) {
    std::error_code ec;
    VEIL_CHECK(std::filesystem::exists(path, ec), "mesh file '{}' does not exist", path.string());
    VEIL_CHECK(std::filesystem::is_regular_file(path, ec), "mesh file '{}' is not a regular file",
               path.string());
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    const bool gltf = ext == ".gltf" || ext == ".glb";
    // assimp hangs, aborts or crashes on some broken PLY files (mesh_file_check.h). It also
    // reads PLY content under other names when the named format's importer refuses the file
    // (a PLY named .gltf hung it: tests/fuzz/regressions/mesh), so the content decides.
    if (ext == ".ply" || startsWithPlyMagic(path)) checkPlyFile(path);
    // The glTF2 importer allocates file-given lengths before reading them; GLB content is
    // read as such under any name.
    else if (gltf || startsWithGlbMagic(path))
        checkGltfFile(path);

    Assimp::Importer importer;
    // Points and lines are dropped; the renderer only draws triangles.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    // ValidateDataStructure runs first and turns indices out of range into an error.
    const unsigned flags = aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                           aiProcess_GenSmoothNormals | aiProcess_JoinIdenticalVertices |
                           aiProcess_PreTransformVertices | aiProcess_SortByPType;
    const aiScene* scene = importer.ReadFile(path.string(), flags);
    // assimp gives no reason for some refusals (a GLB without meshes is "incomplete").
    const std::string reason = importer.GetErrorString();
    VEIL_CHECK(scene != nullptr && !(scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE),
               "cannot load mesh file '{}': {}", path.string(),
               !reason.empty() ? reason
               : scene == nullptr
                   ? std::string("assimp read nothing from it")
                   : fmt::format("assimp read it as incomplete ({} meshes; a file without "
                                 "meshes is incomplete)",
                                 scene->mNumMeshes));

    std::vector<LoadedMesh> out;
    std::size_t triangles = 0;
    for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
        const aiMesh& am = *scene->mMeshes[mi];
        if (!(am.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || am.mNumVertices == 0) continue;
        LoadedMesh lm;
        MeshData& m = lm.mesh;
        m.name = am.mName.length > 0 ? am.mName.C_Str() : fmt::format("mesh{}", mi);
        m.positions.resize(am.mNumVertices);
        m.normals.resize(am.mNumVertices, glm::vec3(0.0f, 1.0f, 0.0f));
        m.uvs.resize(am.mNumVertices, glm::vec2(0.0f));
        for (unsigned v = 0; v < am.mNumVertices; ++v) {
            const aiVector3D& p = am.mVertices[v];
            VEIL_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
                       "mesh file '{}': mesh '{}' has a NaN or infinite vertex position "
                       "(vertex {}: {} {} {})",
                       path.string(), m.name, v, p.x, p.y, p.z);
            VEIL_CHECK(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) <=
                           kMaxMeshCoordinate,
                       "mesh file '{}': mesh '{}' vertex {} ({} {} {}) lies beyond {:g}, the "
                       "largest coordinate Veil renders in float",
                       path.string(), m.name, v, p.x, p.y, p.z, kMaxMeshCoordinate);
            m.positions[v] = {p.x, p.y, p.z};
            if (am.mNormals) {
                glm::vec3 n(am.mNormals[v].x, am.mNormals[v].y, am.mNormals[v].z);
                float len = glm::length(n);
                // GenSmoothNormals leaves NaN on vertices used by no triangle.
                if (std::isfinite(len) && len > 0.0f) m.normals[v] = n / len;
            }
            if (am.mTextureCoords[0])
                m.uvs[v] = {am.mTextureCoords[0][v].x, am.mTextureCoords[0][v].y};
        }
        m.indices.reserve(std::size_t(am.mNumFaces) * 3);
        for (unsigned f = 0; f < am.mNumFaces; ++f) {
            const aiFace& face = am.mFaces[f];
            if (face.mNumIndices != 3) continue;
            for (unsigned k = 0; k < 3; ++k)
                VEIL_CHECK(face.mIndices[k] < am.mNumVertices,
                           "mesh file '{}': mesh '{}' face {} refers to vertex {} of {}",
                           path.string(), m.name, f, face.mIndices[k], am.mNumVertices);
            m.indices.insert(m.indices.end(),
                             {face.mIndices[0], face.mIndices[1], face.mIndices[2]});
        }
        if (m.indices.empty()) continue;
        triangles += m.triangleCount();

        if (am.mMaterialIndex < scene->mNumMaterials) {
            const aiMaterial& mat = *scene->mMaterials[am.mMaterialIndex];
            // assimp invents "DefaultMaterial" for files without materials (OBJ without
            // .mtl) and an unnamed one for PLY; neither is the file's, so the scene's default
            // applies. Unnamed glTF materials are real and get a generated name.
            std::string name = mat.GetName().C_Str();
            bool synthetic = name == AI_DEFAULT_MATERIAL_NAME || (!gltf && name.empty());
            if (!synthetic) {
                lm.material = convertMaterial(mat, gltf);
                if (lm.material->name.empty())
                    lm.material->name = fmt::format("material{}", am.mMaterialIndex);
            }
        }
        out.push_back(std::move(lm));
    }
    VEIL_CHECK(triangles > 0, "mesh file '{}' has no triangles", path.string());
    log::debug("loaded '{}': {} meshes, {} triangles", path.string(), out.size(), triangles);
    return out;
}

} // namespace veil::scene
