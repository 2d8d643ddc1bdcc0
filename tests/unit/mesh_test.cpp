// Procedural shapes (winding, closure, area against the analytic surface) and mesh files
// loaded through assimp (triangle counts and material mapping of the third-party data).
#include "base/error.h"
#include "scene/mesh.h"
#include "support/test_support.h"

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <tuple>

namespace fs = std::filesystem;
using namespace veil::scene;
using veil::test::writeTextFile;

namespace {

const std::string kThirdParty = VEIL_DATA_DIR;
constexpr double kPi = glm::pi<double>();

fs::path outputDir() { return veil::test::outputSubdir("mesh_test"); }

glm::dvec3 corner(const MeshData& m, std::size_t t, int k) {
    return glm::dvec3(m.positions[m.indices[3 * t + k]]);
}
glm::dvec3 faceCross(const MeshData& m, std::size_t t) {
    return glm::cross(corner(m, t, 1) - corner(m, t, 0), corner(m, t, 2) - corner(m, t, 0));
}

double area(const MeshData& m) {
    double a = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t)
        a += 0.5 * glm::length(faceCross(m, t));
    return a;
}

// Signed volume by the divergence theorem; positive for a closed mesh with outward winding.
double volume(const MeshData& m) {
    double v = 0.0;
    for (std::size_t t = 0; t < m.triangleCount(); ++t)
        v += glm::dot(corner(m, t, 0), glm::cross(corner(m, t, 1), corner(m, t, 2))) / 6.0;
    return v;
}

// Closed: every edge (keyed by quantized positions, since seams duplicate vertices) is used
// by exactly two triangles, once in each direction.
bool isClosed(const MeshData& m) {
    using Key = std::tuple<long, long, long>;
    auto key = [](glm::dvec3 p) {
        return Key{std::lround(p.x * 1e4), std::lround(p.y * 1e4), std::lround(p.z * 1e4)};
    };
    std::map<std::pair<Key, Key>, int> directed;
    for (std::size_t t = 0; t < m.triangleCount(); ++t)
        for (int k = 0; k < 3; ++k)
            ++directed[{key(corner(m, t, k)), key(corner(m, t, (k + 1) % 3))}];
    for (const auto& [edge, count] : directed) {
        if (edge.first == edge.second) continue; // degenerate
        auto reverse = directed.find({edge.second, edge.first});
        if (count != 1 || reverse == directed.end() || reverse->second != 1) return false;
    }
    return true;
}

// Every vertex normal is unit length and every triangle's winding agrees with its normals.
void expectConsistentNormals(const MeshData& m) {
    ASSERT_EQ(m.normals.size(), m.positions.size());
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    for (const glm::vec3& n : m.normals)
        ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        glm::dvec3 avg(0.0);
        for (int k = 0; k < 3; ++k)
            avg += glm::dvec3(m.normals[m.indices[3 * t + k]]);
        ASSERT_GT(glm::dot(faceCross(m, t), avg), 0.0) << m.name << " triangle " << t;
    }
}

std::string loadError(const fs::path& path) {
    return veil::test::errorOf([&] { loadMeshFile(path); });
}

} // namespace

TEST(MeshTest, PlaneIsSubdividedAndFacesUp) {
    MeshData m = makePlane({4.0f, 2.0f}, 3);
    EXPECT_EQ(m.positions.size(), 16u);
    EXPECT_EQ(m.triangleCount(), 18u);
    EXPECT_NEAR(area(m), 8.0, 1e-5);
    expectConsistentNormals(m);
    for (std::size_t t = 0; t < m.triangleCount(); ++t)
        EXPECT_GT(faceCross(m, t).y, 0.0); // CCW seen from +y
    glm::vec3 lo, hi;
    m.bounds(lo, hi);
    EXPECT_EQ(lo, glm::vec3(-2.0f, 0.0f, -1.0f));
    EXPECT_EQ(hi, glm::vec3(2.0f, 0.0f, 1.0f));
}

TEST(MeshTest, BoxHasTwelveTrianglesAndIsClosed) {
    MeshData m = makeBox({1.0f, 2.0f, 3.0f});
    EXPECT_EQ(m.positions.size(), 24u);
    EXPECT_EQ(m.triangleCount(), 12u);
    EXPECT_TRUE(isClosed(m));
    expectConsistentNormals(m);
    EXPECT_NEAR(volume(m), 6.0, 1e-5);
    EXPECT_NEAR(area(m), 2.0 * (2.0 + 3.0 + 6.0), 1e-5);
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        glm::dvec3 centroid = (corner(m, t, 0) + corner(m, t, 1) + corner(m, t, 2)) / 3.0;
        EXPECT_GT(glm::dot(faceCross(m, t), centroid), 0.0); // outward for a convex shape
    }
}

TEST(MeshTest, SphereAreaNormalsAndClosure) {
    const double r = 1.5;
    MeshData m = makeSphere(float(r));
    EXPECT_EQ(m.triangleCount(), std::size_t(2 * 48 * 24 - 2 * 48));
    EXPECT_NEAR(area(m) / (4.0 * kPi * r * r), 1.0, 0.01);
    EXPECT_NEAR(volume(m) / (4.0 / 3.0 * kPi * r * r * r), 1.0, 0.02);
    EXPECT_TRUE(isClosed(m));
    expectConsistentNormals(m);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(m.positions[i]), r, 1e-5);
        EXPECT_GT(glm::dot(m.normals[i], glm::normalize(m.positions[i])), 0.9999f); // outward
    }
}

TEST(MeshTest, TorusAreaAndClosure) {
    const double R = 2.0, r = 0.5;
    MeshData m = makeTorus(float(R), float(r));
    EXPECT_EQ(m.triangleCount(), std::size_t(2 * 48 * 24));
    EXPECT_NEAR(area(m) / (4.0 * kPi * kPi * R * r), 1.0, 0.01);
    EXPECT_NEAR(volume(m) / (2.0 * kPi * kPi * R * r * r), 1.0, 0.02);
    EXPECT_TRUE(isClosed(m));
    expectConsistentNormals(m);
}

TEST(MeshTest, ParticleCloudIsDeterministicBillboards) {
    MeshData a = makeParticleCloud(500, 2.0f, 0.05f, 7);
    MeshData b = makeParticleCloud(500, 2.0f, 0.05f, 7);
    MeshData c = makeParticleCloud(500, 2.0f, 0.05f, 8);
    EXPECT_TRUE(a.billboard);
    EXPECT_EQ(a.positions.size(), 2000u);
    EXPECT_EQ(a.indices.size(), 3000u);
    EXPECT_EQ(a.billboardSize.size(), 2000u);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_NE(a.positions, c.positions);
    glm::dvec3 mean(0.0);
    for (std::size_t p = 0; p < 500; ++p) {
        const glm::vec3 centre = a.positions[4 * p];
        for (int k = 1; k < 4; ++k)
            ASSERT_EQ(a.positions[4 * p + k], centre);
        ASSERT_LE(glm::length(centre), 2.0f + 1e-5f);
        EXPECT_EQ(a.uvs[4 * p + 2], glm::vec2(1.0f, 1.0f));
        EXPECT_EQ(a.normals[4 * p], glm::vec3(0.0f, 0.0f, 1.0f));
        mean += glm::dvec3(centre);
    }
    mean /= 500.0;
    EXPECT_LT(glm::length(mean), 0.15); // centred
    glm::vec3 lo, hi;
    a.bounds(lo, hi);
    EXPECT_LE(hi.x, 2.05f + 1e-5f);
    glm::vec3 maxCentre(-1e9f);
    for (const glm::vec3& p : a.positions)
        maxCentre = glm::max(maxCentre, p);
    EXPECT_FLOAT_EQ(hi.x, maxCentre.x + 0.05f); // bounds include the particle size
}

TEST(MeshTest, BadShapeParametersThrow) {
    EXPECT_THROW(makeSphere(-1.0f), veil::Error);
    EXPECT_THROW(makeTorus(1.0f, 2.0f), veil::Error);
    EXPECT_THROW(makePlane({1.0f, 1.0f}, 0), veil::Error);
    EXPECT_THROW(makeParticleCloud(0, 1.0f, 0.1f, 1), veil::Error);
}

TEST(MeshTest, LoadsTeapotObj) {
    auto meshes = loadMeshFile(kThirdParty + "/utah-teapot/teapot.obj");
    std::size_t triangles = 0;
    for (const LoadedMesh& lm : meshes) {
        triangles += lm.mesh.triangleCount();
        EXPECT_FALSE(lm.material.has_value()); // no .mtl: assimp's default is not kept
        expectConsistentNormals(lm.mesh);
    }
    EXPECT_EQ(triangles, 4032u);
    glm::vec3 lo, hi;
    meshes.at(0).mesh.bounds(lo, hi);
    EXPECT_NEAR(hi.x - lo.x, 1.0f, 1e-3f);
}

// A scanned-style PLY: vertices with extra per-vertex properties (like the Stanford scans'
// confidence and intensity) and no normals. Generated here from a procedural sphere, because
// the Stanford bunny's terms do not allow copying it into the repository.
TEST(MeshTest, LoadsPlyWithoutNormals) {
    const double r = 0.25;
    const MeshData sphere = makeSphere(float(r), 40, 20);
    fs::path path = outputDir() / "scan_sphere.ply";
    {
        std::ofstream out(path);
        out << "ply\nformat ascii 1.0\ncomment generated by mesh_test\n"
            << "element vertex " << sphere.positions.size() << "\n"
            << "property float x\nproperty float y\nproperty float z\n"
            << "property float confidence\nproperty float intensity\n"
            << "element face " << sphere.triangleCount() << "\n"
            << "property list uchar int vertex_indices\nend_header\n";
        out.precision(9);
        for (const glm::vec3& p : sphere.positions)
            out << p.x << ' ' << p.y + 0.1 << ' ' << p.z << " 1 0.5\n";
        for (std::size_t t = 0; t < sphere.triangleCount(); ++t)
            out << "3 " << sphere.indices[3 * t] << ' ' << sphere.indices[3 * t + 1] << ' '
                << sphere.indices[3 * t + 2] << '\n';
    }
    auto meshes = loadMeshFile(path);
    ASSERT_EQ(meshes.size(), 1u);
    const MeshData& m = meshes[0].mesh;
    EXPECT_EQ(m.triangleCount(), sphere.triangleCount());
    EXPECT_FALSE(meshes[0].material.has_value());
    expectConsistentNormals(m); // generated normals: unit length, agree with the winding
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        glm::dvec3 centroid = (corner(m, t, 0) + corner(m, t, 1) + corner(m, t, 2)) / 3.0;
        centroid.y -= 0.1;
        ASSERT_GT(glm::dot(faceCross(m, t), centroid), 0.0) << "triangle " << t; // outward
    }
    glm::vec3 lo, hi;
    m.bounds(lo, hi);
    EXPECT_NEAR(lo.y, 0.1 - r, 1e-5);
    EXPECT_NEAR(hi.y, 0.1 + r, 1e-5);
    EXPECT_NEAR(area(m), area(sphere), 1e-4);
}

TEST(MeshTest, GlassVaseMaterialsMapAlphaBlendAndTransmission) {
    auto meshes = loadMeshFile(kThirdParty + "/gltf-GlassVaseFlowers/GlassVaseFlowers.glb");
    std::map<std::string, Material> byName;
    for (const LoadedMesh& lm : meshes) {
        ASSERT_TRUE(lm.material.has_value()) << lm.mesh.name;
        byName[lm.material->name] = *lm.material;
    }
    ASSERT_TRUE(byName.count("GlassAlpha"));
    ASSERT_TRUE(byName.count("GlassTransmission"));
    ASSERT_TRUE(byName.count("Flowers"));
    const Material& alpha = byName["GlassAlpha"];
    EXPECT_NEAR(alpha.alpha, 0.3f, 1e-4f); // alphaMode BLEND
    EXPECT_EQ(alpha.transmission, glm::vec3(0.0f));
    EXPECT_TRUE(alpha.isTransparent());
    const Material& glass = byName["GlassTransmission"];
    EXPECT_EQ(glass.alpha, 1.0f);
    EXPECT_GT(glass.transmission.x, 0.0f);
    EXPECT_NEAR(glass.thickness, 0.075f, 1e-4f); // KHR_materials_volume
    EXPECT_TRUE(glass.isTransparent());
    EXPECT_EQ(byName["Flowers"].alpha, 1.0f); // alphaMode MASK is not coverage alpha
    EXPECT_FALSE(byName["Flowers"].isTransparent());
}

TEST(MeshTest, TransmissionIsTintedByBaseColorAndIorIsRead) {
    auto meshes =
        loadMeshFile(kThirdParty + "/gltf-TransmissionRoughnessTest/TransmissionRoughnessTest.glb");
    bool sawIor = false;
    for (const LoadedMesh& lm : meshes) {
        if (!lm.material || lm.material->name != "Mat_IOR_1.33") continue;
        sawIor = true;
        EXPECT_NEAR(lm.material->ior, 1.33f, 1e-4f);
        EXPECT_GT(lm.material->transmission.x, 0.0f);
        // transmission = factor * base color, so the channels keep the base color's ratios.
        EXPECT_NEAR(lm.material->transmission.z * lm.material->baseColor.x,
                    lm.material->transmission.x * lm.material->baseColor.z, 1e-5f);
    }
    EXPECT_TRUE(sawIor);
}

TEST(MeshTest, ObjWithoutNormalsGetsUnitNormals) {
    fs::path path = outputDir() / "tetra.obj";
    writeTextFile(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    auto meshes = loadMeshFile(path);
    ASSERT_EQ(meshes.size(), 1u);
    EXPECT_EQ(meshes[0].mesh.triangleCount(), 4u);
    for (const glm::vec3& n : meshes[0].mesh.normals)
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-4f);
}

TEST(MeshTest, MissingOrEmptyFilesThrowNamingTheFile) {
    std::string missing = loadError(outputDir() / "does_not_exist.obj");
    EXPECT_NE(missing.find("does_not_exist.obj"), std::string::npos) << missing;
    EXPECT_NE(missing.find("does not exist"), std::string::npos) << missing;

    fs::path lines = outputDir() / "lines_only.obj";
    writeTextFile(lines, "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
    std::string empty = loadError(lines);
    EXPECT_NE(empty.find("lines_only.obj"), std::string::npos) << empty;

    fs::path garbage = outputDir() / "garbage.glb";
    writeTextFile(garbage, "this is not a glTF file");
    std::string bad = loadError(garbage);
    EXPECT_NE(bad.find("garbage.glb"), std::string::npos) << bad;
}

namespace {

// A tetrahedron as PLY, ASCII or binary little endian, with the last face's indices given.
std::string tetraPly(bool binary, const std::array<int, 3>& lastFace) {
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {lastFace[0], lastFace[1], lastFace[2]}};
    std::string out = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
                      " 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
                      "end_header\n";
    auto append = [&out](const void* p, std::size_t n) {
        out.append(static_cast<const char*>(p), n); // the test machines are little endian
    };
    for (const auto& p : v) {
        if (binary)
            append(p, sizeof(p));
        else
            out += fmt::format("{} {} {}\n", p[0], p[1], p[2]);
    }
    for (const auto& t : f) {
        if (binary) {
            const unsigned char three = 3;
            append(&three, 1);
            append(t, sizeof(t));
        } else {
            out += fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
        }
    }
    return out;
}

void writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

} // namespace

TEST(MeshTest, PlyFaceIndicesOutOfRangeOrNegativeAreErrors) {
    // assimp 5.2 segfaults on these (in its post-processing, before validation runs).
    for (bool binary : {false, true}) {
        const fs::path ok = outputDir() / (binary ? "tetra_ok_bin.ply" : "tetra_ok_ascii.ply");
        writeBytes(ok, tetraPly(binary, {1, 2, 3}));
        ASSERT_EQ(loadError(ok), "");
        EXPECT_EQ(loadMeshFile(ok).at(0).mesh.triangleCount(), 4u);
    }
    for (bool binary : {false, true})
        for (int bad : {4, 1000000, -5}) {
            const fs::path p =
                outputDir() / fmt::format("bad_index_{}_{}.ply", binary ? "bin" : "ascii", bad);
            writeBytes(p, tetraPly(binary, {1, bad, 3}));
            const std::string msg = loadError(p);
            EXPECT_NE(msg.find(p.filename().string()), std::string::npos) << msg;
            EXPECT_NE(msg.find("refers to vertex"), std::string::npos) << msg;
        }
}

TEST(MeshTest, TruncatedPlyIsAnError) {
    // Cut binary: assimp's reader loops forever; cut ASCII: an ai_assert aborts the process.
    for (bool binary : {false, true}) {
        const std::string full = tetraPly(binary, {1, 2, 3});
        const std::size_t header = full.find("end_header\n") + 11;
        for (std::size_t cut : {header + (full.size() - header) / 2, full.size() - 3}) {
            const fs::path p =
                outputDir() / fmt::format("cut_{}_{}.ply", binary ? "bin" : "ascii", cut);
            writeBytes(p, full.substr(0, cut));
            const std::string msg = loadError(p);
            EXPECT_NE(msg.find(p.filename().string()), std::string::npos) << msg;
            EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
        }
    }
}

// assimp skips unknown header lines, so a misspelt `property` shifts the binary body and
// TriangulateProcess aborts the process (tests/fuzz/regressions/mesh/ply-misspelt-*); in ASCII
// it leaked on assimp's error path (regressions/mesh/ply-error-leak). The pre-check refuses
// the keyword, naming the line.
TEST(MeshTest, PlyUnknownHeaderKeywordIsRefusedNamingTheLine) {
    for (bool binary : {false, true}) {
        std::string bytes = tetraPly(binary, {1, 2, 3});
        bytes.replace(bytes.find("property float y"), 8, "prnperty");
        const fs::path p = outputDir() / fmt::format("misspelt_{}.ply", binary ? "bin" : "ascii");
        writeBytes(p, bytes);
        const std::string msg = loadError(p);
        EXPECT_NE(msg.find(p.filename().string()), std::string::npos) << msg;
        EXPECT_NE(msg.find("line 5"), std::string::npos) << msg;
        EXPECT_NE(msg.find("unknown keyword 'prnperty'"), std::string::npos) << msg;
    }
    // The leak finding: assimp reported an error and leaked 1380 bytes; now the pre-check
    // refuses it before assimp runs (its first byte is the fuzz target's extension choice).
    std::ifstream in(fs::path(VEIL_SOURCE_DIR) / "tests/fuzz/regressions/mesh/ply-error-leak",
                     std::ios::binary);
    const std::string leak((std::istreambuf_iterator<char>(in)), {});
    ASSERT_GT(leak.size(), 1u);
    const fs::path p = outputDir() / "ply-error-leak.ply";
    writeBytes(p, leak.substr(1));
    const std::string msg = loadError(p);
    EXPECT_NE(msg.find("line 6 of the PLY header has the unknown keyword 'propertyz'"),
              std::string::npos)
        << msg;
}

// A binary body must have the size its header gives it: bytes left over or missing mean
// values read at the wrong offsets.
TEST(MeshTest, BinaryPlyBodyMustMatchItsHeaderSize) {
    const std::string tetra = tetraPly(true, {1, 2, 3});
    const fs::path extra = outputDir() / "tetra_extra_bytes.ply";
    writeBytes(extra, tetra + "junk");
    std::string msg = loadError(extra);
    EXPECT_NE(msg.find("tetra_extra_bytes.ply"), std::string::npos) << msg;
    EXPECT_NE(msg.find("4 bytes follow the last element"), std::string::npos) << msg;

    // Points only (no list): the size is fixed by the header, checked before the walk.
    std::string points = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
                         "property float x\nproperty float y\nproperty float z\nend_header\n";
    points.append(36, '\0');
    const fs::path shortBody = outputDir() / "points_short.ply";
    writeBytes(shortBody, points.substr(0, points.size() - 4));
    msg = loadError(shortBody);
    EXPECT_NE(msg.find("points_short.ply"), std::string::npos) << msg;
    EXPECT_NE(msg.find("binary body of 36 bytes, but the file has 32"), std::string::npos) << msg;
    const fs::path longBody = outputDir() / "points_long.ply";
    writeBytes(longBody, points + std::string(8, '\0'));
    msg = loadError(longBody);
    EXPECT_NE(msg.find("binary body of 36 bytes, but the file has 44"), std::string::npos) << msg;

    // A count of billions in a file of bytes is refused at once, not walked.
    std::string huge = tetra;
    huge.replace(huge.find("element vertex 4"), 16, "element vertex 4000000000");
    const fs::path hugePath = outputDir() / "tetra_huge_count.ply";
    writeBytes(hugePath, huge);
    msg = loadError(hugePath);
    EXPECT_NE(msg.find("tetra_huge_count.ply"), std::string::npos) << msg;
    EXPECT_NE(msg.find("at least 48000000004 bytes"), std::string::npos) << msg;
}

// Two ways to give assimp a face without indices, which aborts the process in
// TriangulateProcess (ai_assert): a list count of 0, and an ASCII vertex count smaller than the
// vertex lines, which assimp reads one instance per line, so that faces start on vertex lines
// (the fuzz finding tests/fuzz/regressions/mesh/ply-ascii-vertex-count-short-*).
TEST(MeshTest, PlyFacesAssimpWouldReadWithoutIndicesAreRefused) {
    std::string bin = tetraPly(true, {1, 2, 3});
    bin.resize(bin.size() - 13); // the last face: count 3 and three ints
    bin.push_back('\0');
    const fs::path empty = outputDir() / "face_without_indices.ply";
    writeBytes(empty, bin);
    std::string msg = loadError(empty);
    EXPECT_NE(msg.find("face_without_indices.ply"), std::string::npos) << msg;
    EXPECT_NE(msg.find("face 3 has no vertex indices"), std::string::npos) << msg;

    std::string ascii = tetraPly(false, {1, 2, 3});
    ascii.replace(ascii.find("element vertex 4"), 16, "element vertex 2");
    const fs::path shifted = outputDir() / "vertex_count_short.ply";
    writeBytes(shifted, ascii);
    msg = loadError(shifted);
    EXPECT_NE(msg.find("vertex_count_short.ply"), std::string::npos) << msg;
    EXPECT_NE(msg.find("face 0 has no vertex indices"), std::string::npos) << msg; // "0 1 0"

    std::string fewer = tetraPly(false, {1, 2, 3});
    fewer.replace(fewer.find("\n3 0 2 1\n"), 9, "\n3 0 2\n");
    const fs::path shorter = outputDir() / "face_line_short.ply";
    writeBytes(shorter, fewer);
    msg = loadError(shorter);
    EXPECT_NE(msg.find("face_line_short.ply"), std::string::npos) << msg;
    EXPECT_NE(msg.find("line 14 (face 0) has 3 values, fewer than"), std::string::npos) << msg;

    std::string extra = tetraPly(false, {1, 2, 3});
    extra.replace(extra.find("\n3 0 2 1\n"), 9, "\n3 0 2 1 7\n");
    const fs::path longer = outputDir() / "face_line_too_long.ply";
    writeBytes(longer, extra);
    msg = loadError(longer);
    EXPECT_NE(msg.find("face_line_too_long.ply"), std::string::npos) << msg;
    EXPECT_NE(msg.find("has 5 values, but the header's properties of 'face' give 4"),
              std::string::npos)
        << msg;
}

TEST(MeshTest, ObjWithNanOrInfiniteVerticesIsRefused) {
    for (const char* bad : {"nan", "inf", "-inf"}) {
        const fs::path p = outputDir() / fmt::format("nonfinite_{}.obj", bad);
        writeTextFile(p, fmt::format("o spiky\nv 0 0 0\nv 1 0 0\nv 0 {} 0\nv 0 0 1\nf 1 3 2\nf 1 2 "
                                     "4\nf 1 4 3\nf 2 3 4\n",
                                     bad));
        const std::string msg = loadError(p);
        EXPECT_NE(msg.find(p.filename().string()), std::string::npos) << msg;
        EXPECT_NE(msg.find("spiky"), std::string::npos) << msg;
        EXPECT_NE(msg.find("NaN or infinite"), std::string::npos) << msg;
    }
}

TEST(MeshTest, DirectoryOrDeviceIsNotARegularFile) {
    for (const fs::path& p : {outputDir(), fs::path("/dev/null")}) {
        const std::string msg = loadError(p);
        EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
        EXPECT_NE(msg.find("is not a regular file"), std::string::npos) << msg;
    }
}
