// Checks on a mesh file made before assimp reads it, for inputs that assimp 5.2 does not turn
// into an error: a binary PLY cut short makes its PLY reader loop forever, an ASCII PLY cut
// short trips an ai_assert (abort) in TriangulateProcess, and PLY face indices that are
// negative or past the vertex count segfault in the post-processing steps that run before
// aiProcess_ValidateDataStructure could report them. Its glTF2 importer allocates the lengths a
// glTF or GLB file gives before reading them (2 GiB for a 669-byte GLB).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace veil::scene {

// Walks a PLY file's body as its header describes it (ASCII, binary little or big endian):
// every header line must start with a PLY keyword (assimp skips unknown lines, so a misspelt
// `property` shifted the body and made it abort), a binary body must have exactly the size its
// layout gives (checked against the file size before the walk where no list property makes it
// variable), every element instance must be complete and every face's vertex index in
// [0, vertex count). Throws veil::Error naming the file, the element or header line and the
// problem. Costs one sequential read of the file.
void checkPlyFile(const std::filesystem::path& path);

// True when the file starts with the GLB magic "glTF" (assimp reads it as binary glTF whatever
// its name).
bool startsWithGlbMagic(const std::filesystem::path& path);

// Bounds every length a glTF 2.0 (.gltf JSON) or GLB file gives by the bytes that back it:
// the GLB header and chunk lengths by the file size, buffers[].byteLength by the BIN chunk,
// the data URI or the external file, buffer views by their buffer, accessors (count, offset,
// stride, sparse parts) by their view; an accessor without a view is limited to 2^24
// elements. Throws veil::Error naming the file, the entity (e.g. "accessors[1]") and both
// sizes. Reads the file once; the JSON is parsed with the scene's bounded parser.
void checkGltfFile(const std::filesystem::path& path);

// The nodes of a glTF or GLB file whose transform collapses what they hold (a scale with a
// zero component, a matrix of determinant 0), each as "nodes[2] 'name' (scale [0,0,0])", for
// the message of a mesh that has no extent.
std::vector<std::string> gltfCollapsingNodes(const std::filesystem::path& path);

} // namespace veil::scene
