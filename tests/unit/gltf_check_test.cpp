// The glTF/GLB length checks made before assimp reads a file (src/scene/gltf_file_check.cpp):
// a well-formed triangle loads, and every length the file gives that its bytes do not back is
// refused with a message naming the file and the entity, before assimp allocates it.
#include "base/error.h"
#include "scene/mesh.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using namespace veil::scene;

namespace {

fs::path outputDir() { return veil::test::outputSubdir("gltf_check_test"); }

void putLe32(std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i)
        out.push_back(char((v >> (8 * i)) & 0xff));
}

// Three float3 positions (0,0,0) (1,0,0) (0,1,0) then three uint16 indices and 2 bytes of
// padding: 44 bytes.
std::string triangleBin() {
    std::string bin;
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bin.append(reinterpret_cast<const char*>(pos), sizeof(pos));
    const std::uint16_t idx[4] = {0, 1, 2, 0};
    bin.append(reinterpret_cast<const char*>(idx), sizeof(idx));
    return bin;
}

// The glTF JSON of that triangle; the placeholders let a test change one length.
std::string
triangleJson(const std::string& buffer = R"({"byteLength":44})",
             const std::string& positionCount = "3",
             const std::string& indexView = R"({"buffer":0,"byteOffset":36,"byteLength":6})") {
    return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
           R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
           R"("buffers":[)" +
           buffer + R"(],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},)" + indexView +
           R"(],"accessors":[{"bufferView":0,"componentType":5126,"count":)" + positionCount +
           R"(,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
           R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
}

// GLB 2.0: header, JSON chunk padded with spaces to 4 bytes, BIN chunk.
std::string glb(std::string json, const std::string& bin) {
    while (json.size() % 4 != 0)
        json.push_back(' ');
    std::string out = "glTF";
    putLe32(out, 2);
    putLe32(out, std::uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    putLe32(out, std::uint32_t(json.size()));
    out += "JSON" + json;
    putLe32(out, std::uint32_t(bin.size()));
    out += std::string("BIN\0", 4) + bin;
    return out;
}

fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path path = outputDir() / name;
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    return path;
}

// The message of the veil::Error that loading `path` throws ("" when it loads).
std::string loadError(const fs::path& path) {
    try {
        (void)loadMeshFile(path);
    } catch (const veil::Error& e) {
        return e.what();
    }
    return "";
}

void expectRefused(const fs::path& path, const std::string& needle) {
    const std::string error = loadError(path);
    EXPECT_NE(error.find(path.filename().string()), std::string::npos) << error;
    EXPECT_NE(error.find(needle), std::string::npos) << "expected '" << needle << "' in: " << error;
}

} // namespace

TEST(GltfCheckTest, WellFormedTriangleLoadsAsGlbAndGltf) {
    const auto meshes = loadMeshFile(write("tri.glb", glb(triangleJson(), triangleBin())));
    ASSERT_EQ(meshes.size(), 1u);
    EXPECT_EQ(meshes[0].mesh.triangleCount(), 1u);

    write("tri.bin", triangleBin());
    const auto external =
        loadMeshFile(write("tri.gltf", triangleJson(R"({"byteLength":44,"uri":"tri.bin"})")));
    ASSERT_EQ(external.size(), 1u);
    EXPECT_EQ(external[0].mesh.triangleCount(), 1u);
}

// tests/fuzz/regressions/mesh/mesh-oom-2gib-malloc: the JSON chunk's length 0x80000254 made
// assimp malloc 2 GiB for a 669-byte file.
TEST(GltfCheckTest, GlbChunkLongerThanTheFileIsRefused) {
    std::string bytes = glb(triangleJson(), triangleBin());
    bytes[15] = char(0x80); // high byte of the JSON chunk length
    expectRefused(write("chunk.glb", bytes), "GLB chunk 0 at byte 12 claims 2147484");

    std::string header = glb(triangleJson(), triangleBin());
    header[9] = char(0x7f); // total length above the file size
    expectRefused(write("header.glb", header), "GLB header says");
}

TEST(GltfCheckTest, BufferLongerThanWhatBacksItIsRefused) {
    expectRefused(
        write("bin.glb", glb(triangleJson(R"({"byteLength":2000000000})"), triangleBin())),
        "buffers[0].byteLength is 2000000000 but only 44 bytes back it");

    write("short.bin", triangleBin().substr(0, 20));
    expectRefused(write("short.gltf", triangleJson(R"({"byteLength":44,"uri":"short.bin"})")),
                  "buffers[0].byteLength is 44 but only 20 bytes back it");

    // 8 base64 characters decode to 6 bytes.
    expectRefused(
        write("datauri.gltf",
              triangleJson(
                  R"({"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAA"})")),
        "buffers[0].byteLength is 44 but only 6 bytes back it");
}

TEST(GltfCheckTest, ViewsAndAccessorsOutsideTheirStorageAreRefused) {
    expectRefused(
        write("view.glb", glb(triangleJson(R"({"byteLength":44})", "3",
                                           R"({"buffer":0,"byteOffset":36,"byteLength":4000000})"),
                              triangleBin())),
        "bufferViews[1] (offset 36, 4000000 bytes) lies outside buffers[0] (44 bytes)");
    expectRefused(
        write("count.glb", glb(triangleJson(R"({"byteLength":44})", "1000000000"), triangleBin())),
        "accessors[0] needs 12000000000 bytes but its buffer view has 36");
    expectRefused(
        write("negative.glb", glb(triangleJson(R"({"byteLength":44})", "-3"), triangleBin())),
        "accessors[0].count must be a non-negative integer");
}

TEST(GltfCheckTest, AccessorWithoutViewIsBounded) {
    std::string json = triangleJson();
    const std::string view = R"("bufferView":0,"componentType":5126,"count":3)";
    json.replace(json.find(view), view.size(), R"("componentType":5126,"count":100000000)");
    expectRefused(write("unbacked.glb", glb(json, triangleBin())),
                  "accessors[0] has no buffer view and 100000000 elements");
}

TEST(GltfCheckTest, GlbContentUnderAnotherNameIsChecked) {
    std::string bytes = glb(triangleJson(), triangleBin());
    bytes[15] = char(0x80);
    expectRefused(write("renamed.obj", bytes), "GLB chunk 0");
}
