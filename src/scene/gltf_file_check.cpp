// glTF 2.0 / GLB checks before assimp reads the file (mesh_file_check.h). assimp 5.2's glTF2
// importer allocates what the file says before it reads it: a GLB chunk length of 0x80000254
// made it malloc 2 GiB for a 669-byte file
// (tests/fuzz/regressions/mesh/mesh-oom-2gib-malloc), and buffer, buffer view and accessor
// lengths are trusted the same way. Every length the file gives is bounded here by the bytes
// that back it: the file for GLB chunks, the BIN chunk, the external file or the data URI for
// a buffer, the buffer for a view, the view for an accessor. References to entities that do not
// exist are left to assimp, which reports them.
#include "scene/mesh_file_check.h"

#include "base/error.h"
#include "scene/json_text.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace veil::scene {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// An accessor without a buffer view is all zeros (glTF 2.0 §3.6.2.3 "sparse" / defaults), so
// no bytes bound its count; 16M elements is far above any mesh Veil renders in one primitive.
constexpr std::uint64_t kMaxUnbackedAccessorElements = std::uint64_t(1) << 24;

// assimp reads, converts, flattens (aiProcess_PreTransformVertices), validates and frees the
// node hierarchy by recursion, one stack frame or more per level: a chain of some thousand
// nodes overflowed the stack. Real models nest a few dozen levels.
constexpr std::size_t kMaxNodeDepth = 256;

// "%2e%2e" -> "..": glTF URIs are RFC 3986 references, so a reader that decodes them would
// see the decoded path.
std::string percentDecoded(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        const auto hex = [](char c) {
            return std::isdigit(static_cast<unsigned char>(c)) ? c - '0'
                   : (c >= 'a' && c <= 'f')                    ? c - 'a' + 10
                   : (c >= 'A' && c <= 'F')                    ? c - 'A' + 10
                                                               : -1;
        };
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += char(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// A URI naming an external file must stay inside the model's folder (glTF 2.0 §3.3.5 allows
// any relative path, but a model from elsewhere must not make Veil read /etc/passwd or
// ../../secret): no absolute path, no scheme but data:, no ".." above the folder, no symbolic
// link out of it; raw and percent-decoded forms alike.
fs::path checkedUriFile(const std::string& uri, const fs::path& path, const std::string& where,
                        const std::string& file) {
    const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::error_code ec;
    const fs::path realFolder = fs::weakly_canonical(fs::absolute(folder), ec);
    for (const std::string& form : {uri, percentDecoded(uri)}) {
        const fs::path rel = fs::u8path(form);
        const fs::path normal = rel.lexically_normal();
        const bool scheme = form.find(':') != std::string::npos;
        const fs::path real = fs::weakly_canonical(fs::absolute(folder / rel), ec);
        const fs::path inside = real.lexically_relative(realFolder);
        VEIL_CHECK(!rel.has_root_path() && !scheme && !normal.empty() && *normal.begin() != ".." &&
                       !ec && !inside.empty() && *inside.begin() != "..",
                   "mesh file '{}': glTF {} '{}' names a file outside the model's folder '{}' "
                   "(external files must lie inside it)",
                   file, where, describeJson(json(uri), 200), folder.string());
    }
    return folder / fs::u8path(uri);
}

// Every node is the child of at most one node, children exist, there is no cycle, and no
// chain is deeper than kMaxNodeDepth. Breadth first from the roots, without recursion.
void checkNodeHierarchy(const json& nodes, const std::string& file) {
    const std::size_t n = nodes.size();
    std::vector<std::size_t> parent(n, n);
    for (std::size_t i = 0; i < n; ++i) {
        if (!nodes[i].is_object()) continue; // assimp reports it
        const auto children = nodes[i].find("children");
        if (children == nodes[i].end()) continue;
        VEIL_CHECK(children->is_array(), "mesh file '{}': glTF nodes[{}].children is not an array",
                   file, i);
        for (const json& c : *children) {
            VEIL_CHECK(c.is_number_unsigned() && c.get<std::uint64_t>() < n,
                       "mesh file '{}': glTF nodes[{}].children holds {}, not a node index", file,
                       i, describeJson(c));
            const std::size_t child = c.get<std::size_t>();
            VEIL_CHECK(parent[child] == n && child != i,
                       "mesh file '{}': glTF nodes[{}] is a child of two nodes (or of itself)",
                       file, child);
            parent[child] = i;
        }
    }
    std::vector<std::size_t> depth(n, 0), queue;
    for (std::size_t i = 0; i < n; ++i)
        if (parent[i] == n) queue.push_back(i), depth[i] = 1;
    std::vector<std::vector<std::size_t>> kids(n);
    for (std::size_t i = 0; i < n; ++i)
        if (parent[i] != n) kids[parent[i]].push_back(i);
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const std::size_t at = queue[head];
        VEIL_CHECK(depth[at] <= kMaxNodeDepth,
                   "mesh file '{}': glTF node hierarchy is deeper than {} levels (at nodes[{}])",
                   file, kMaxNodeDepth, at);
        for (std::size_t k : kids[at]) {
            depth[k] = depth[at] + 1;
            queue.push_back(k);
        }
    }
    VEIL_CHECK(
        queue.size() == n, "mesh file '{}': glTF nodes form a cycle (nodes[{}] and {} more)", file,
        [&] {
            for (std::size_t i = 0; i < n; ++i)
                if (depth[i] == 0) return i;
            return n;
        }(),
        n - queue.size() - 1);
}

std::uint32_t readLe32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
           std::uint32_t(p[3]) << 24;
}

// A member that must be a non-negative integer when present.
std::optional<std::uint64_t> unsignedMember(const json& object, const char* key,
                                            const std::string& where, const std::string& file) {
    const auto it = object.find(key);
    if (it == object.end()) return std::nullopt;
    VEIL_CHECK(it->is_number_unsigned() ||
                   (it->is_number_integer() && it->get<std::int64_t>() >= 0),
               "mesh file '{}': glTF {}.{} must be a non-negative integer, not {}", file, where,
               key, describeJson(*it));
    return it->get<std::uint64_t>();
}

const json& arrayMember(const json& doc, const char* key, const std::string& file) {
    static const json empty = json::array();
    const auto it = doc.find(key);
    if (it == doc.end()) return empty;
    VEIL_CHECK(it->is_array(), "mesh file '{}': glTF '{}' must be an array", file, key);
    return *it;
}

// Bytes a data URI's payload decodes to: 3 per 4 base64 characters ('=' padding and line
// breaks excluded), otherwise at most one per character.
std::uint64_t dataUriBytes(const std::string& uri) {
    const std::size_t comma = uri.find(',');
    if (comma == std::string::npos) return 0;
    const std::string_view payload = std::string_view(uri).substr(comma + 1);
    if (uri.substr(0, comma).find(";base64") == std::string::npos) return payload.size();
    std::uint64_t chars = 0;
    for (char c : payload)
        chars += c != '=' && c != '\r' && c != '\n';
    return chars * 3 / 4;
}

// What backs buffer `index`: the GLB BIN chunk, a data URI or a file beside the glTF.
std::uint64_t bufferCapacity(const json& buffer, std::size_t index, const fs::path& path,
                             std::optional<std::uint64_t> binChunk, const std::string& file) {
    const auto uri = buffer.find("uri");
    if (uri == buffer.end()) {
        VEIL_CHECK(index == 0 && binChunk.has_value(),
                   "mesh file '{}': glTF buffers[{}] has no uri and is not the GLB's BIN chunk",
                   file, index);
        return *binChunk;
    }
    VEIL_CHECK(uri->is_string(), "mesh file '{}': glTF buffers[{}].uri must be a string", file,
               index);
    const std::string& u = uri->get_ref<const std::string&>();
    if (u.rfind("data:", 0) == 0) return dataUriBytes(u);
    std::error_code ec;
    const fs::path external = checkedUriFile(u, path, fmt::format("buffers[{}].uri", index), file);
    const std::uint64_t size = fs::file_size(external, ec);
    VEIL_CHECK(!ec, "mesh file '{}': glTF buffers[{}] refers to '{}', which cannot be read ({})",
               file, index, external.string(), ec.message());
    return size;
}

std::uint64_t componentBytes(std::uint64_t type) {
    switch (type) {
    case 5120: // BYTE
    case 5121: // UNSIGNED_BYTE
        return 1;
    case 5122: // SHORT
    case 5123: // UNSIGNED_SHORT
        return 2;
    case 5125: // UNSIGNED_INT
    case 5126: // FLOAT
        return 4;
    default:
        return 0;
    }
}

std::uint64_t componentCount(const std::string& type) {
    static const std::array<std::pair<const char*, std::uint64_t>, 7> kinds{{{"SCALAR", 1},
                                                                             {"VEC2", 2},
                                                                             {"VEC3", 3},
                                                                             {"VEC4", 4},
                                                                             {"MAT2", 4},
                                                                             {"MAT3", 9},
                                                                             {"MAT4", 16}}};
    for (const auto& [name, n] : kinds)
        if (type == name) return n;
    return 0;
}

// count elements of elementBytes at byteOffset with the view's stride must fit in the view.
void checkElementsFit(std::uint64_t count, std::uint64_t elementBytes, std::uint64_t byteOffset,
                      std::uint64_t stride, std::uint64_t viewBytes, const std::string& where,
                      const std::string& file) {
    if (count == 0) return;
    // (count - 1) * stride + elementBytes without overflow: long double holds 2^64 * 2^8.
    const long double needed =
        static_cast<long double>(byteOffset) +
        static_cast<long double>(count - 1) * static_cast<long double>(stride) +
        static_cast<long double>(elementBytes);
    VEIL_CHECK(needed <= static_cast<long double>(viewBytes),
               "mesh file '{}': glTF {} needs {:.0f} bytes but its buffer view has {}", file, where,
               double(needed), viewBytes);
}

void checkDocument(const json& doc, const fs::path& path, std::optional<std::uint64_t> binChunk,
                   const std::string& file) {
    VEIL_CHECK(doc.is_object(), "mesh file '{}': glTF JSON is not an object", file);
    checkNodeHierarchy(arrayMember(doc, "nodes", file), file);
    const json& images = arrayMember(doc, "images", file);
    for (std::size_t i = 0; i < images.size(); ++i) {
        const auto uri = images[i].is_object() ? images[i].find("uri") : images[i].end();
        if (uri != images[i].end() && uri->is_string() &&
            uri->get_ref<const std::string&>().rfind("data:", 0) != 0)
            checkedUriFile(uri->get<std::string>(), path, fmt::format("images[{}].uri", i), file);
    }
    const json& buffers = arrayMember(doc, "buffers", file);
    std::vector<std::uint64_t> bufferBytes;
    for (std::size_t i = 0; i < buffers.size(); ++i) {
        const std::string where = fmt::format("buffers[{}]", i);
        VEIL_CHECK(buffers[i].is_object(), "mesh file '{}': glTF {} is not an object", file, where);
        const std::uint64_t length =
            unsignedMember(buffers[i], "byteLength", where, file).value_or(0);
        const std::uint64_t capacity = bufferCapacity(buffers[i], i, path, binChunk, file);
        VEIL_CHECK(length <= capacity,
                   "mesh file '{}': glTF {}.byteLength is {} but only {} bytes back it", file,
                   where, length, capacity);
        bufferBytes.push_back(length);
    }

    const json& views = arrayMember(doc, "bufferViews", file);
    std::vector<std::pair<std::uint64_t, std::uint64_t>> viewBytesStride; // length, stride
    for (std::size_t i = 0; i < views.size(); ++i) {
        const std::string where = fmt::format("bufferViews[{}]", i);
        VEIL_CHECK(views[i].is_object(), "mesh file '{}': glTF {} is not an object", file, where);
        const std::uint64_t buffer = unsignedMember(views[i], "buffer", where, file).value_or(0);
        VEIL_CHECK(buffer < bufferBytes.size(), "mesh file '{}': glTF {}.buffer {} does not exist",
                   file, where, buffer);
        const std::uint64_t offset =
            unsignedMember(views[i], "byteOffset", where, file).value_or(0);
        const std::uint64_t length =
            unsignedMember(views[i], "byteLength", where, file).value_or(0);
        const std::uint64_t stride =
            unsignedMember(views[i], "byteStride", where, file).value_or(0);
        VEIL_CHECK(stride <= 252, "mesh file '{}': glTF {}.byteStride {} is above 252", file, where,
                   stride);
        VEIL_CHECK(
            offset <= bufferBytes[buffer] && length <= bufferBytes[buffer] - offset,
            "mesh file '{}': glTF {} (offset {}, {} bytes) lies outside buffers[{}] ({} bytes)",
            file, where, offset, length, buffer, bufferBytes[buffer]);
        viewBytesStride.emplace_back(length, stride);
    }

    const json& accessors = arrayMember(doc, "accessors", file);
    for (std::size_t i = 0; i < accessors.size(); ++i) {
        const std::string where = fmt::format("accessors[{}]", i);
        const json& a = accessors[i];
        VEIL_CHECK(a.is_object(), "mesh file '{}': glTF {} is not an object", file, where);
        const std::uint64_t count = unsignedMember(a, "count", where, file).value_or(0);
        const std::uint64_t component =
            componentBytes(unsignedMember(a, "componentType", where, file).value_or(0));
        const auto type = a.find("type");
        const std::uint64_t components =
            type != a.end() && type->is_string() ? componentCount(type->get<std::string>()) : 0;
        VEIL_CHECK(component != 0 && components != 0,
                   "mesh file '{}': glTF {} has an unknown componentType or type", file, where);
        const std::uint64_t elementBytes = component * components;
        const auto view = unsignedMember(a, "bufferView", where, file);
        if (view) {
            VEIL_CHECK(*view < viewBytesStride.size(),
                       "mesh file '{}': glTF {}.bufferView {} does not exist", file, where, *view);
            const auto [viewBytes, viewStride] = viewBytesStride[*view];
            checkElementsFit(count, elementBytes,
                             unsignedMember(a, "byteOffset", where, file).value_or(0),
                             viewStride != 0 ? viewStride : elementBytes, viewBytes, where, file);
        } else {
            VEIL_CHECK(count <= kMaxUnbackedAccessorElements,
                       "mesh file '{}': glTF {} has no buffer view and {} elements (at most {})",
                       file, where, count, kMaxUnbackedAccessorElements);
        }
        const auto sparse = a.find("sparse");
        if (sparse == a.end()) continue;
        VEIL_CHECK(sparse->is_object(), "mesh file '{}': glTF {}.sparse is not an object", file,
                   where);
        const std::string swhere = where + ".sparse";
        const std::uint64_t scount = unsignedMember(*sparse, "count", swhere, file).value_or(0);
        VEIL_CHECK(scount <= count, "mesh file '{}': glTF {}.count {} exceeds the accessor's {}",
                   file, swhere, scount, count);
        for (const auto& [key, bytes] :
             {std::pair<const char*, std::uint64_t>{"indices", 0}, {"values", elementBytes}}) {
            const auto part = sparse->find(key);
            if (part == sparse->end() || !part->is_object()) continue;
            const std::string pwhere = swhere + "." + key;
            const std::uint64_t partBytes =
                bytes != 0 ? bytes
                           : componentBytes(
                                 unsignedMember(*part, "componentType", pwhere, file).value_or(0));
            VEIL_CHECK(partBytes != 0, "mesh file '{}': glTF {} has an unknown componentType", file,
                       pwhere);
            const std::uint64_t pview =
                unsignedMember(*part, "bufferView", pwhere, file).value_or(0);
            VEIL_CHECK(pview < viewBytesStride.size(),
                       "mesh file '{}': glTF {}.bufferView {} does not exist", file, pwhere, pview);
            checkElementsFit(scount, partBytes,
                             unsignedMember(*part, "byteOffset", pwhere, file).value_or(0),
                             partBytes, viewBytesStride[pview].first, pwhere, file);
        }
    }
}

std::string readAll(const fs::path& path, const std::string& file) {
    std::ifstream in(path, std::ios::binary);
    VEIL_CHECK(in.good(), "cannot open mesh file '{}'", file);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    VEIL_CHECK(!in.bad(), "cannot read mesh file '{}'", file);
    return bytes;
}

} // namespace

bool startsWithGlbMagic(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {0, 0, 0, 0};
    in.read(magic, 4);
    return in.gcount() == 4 && std::string_view(magic, 4) == "glTF";
}

namespace {

// The JSON of a .gltf file or of a GLB's first chunk, and the BIN chunk's length.
json gltfJson(const std::filesystem::path& path, std::optional<std::uint64_t>& binChunk) {
    const std::string file = path.string();
    const std::string bytes = readAll(path, file);
    if (bytes.size() < 4 || bytes.compare(0, 4, "glTF") != 0) return parseJsonText(bytes, file);
    // GLB (glTF 2.0 §4.4): a 12-byte header (magic, version, length), then chunks of
    // (length, type, data); the first is JSON, an optional second one BIN.
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    VEIL_CHECK(bytes.size() >= 20,
               "mesh file '{}': GLB file of {} bytes is shorter than its "
               "header and first chunk header (20 bytes)",
               file, bytes.size());
    const std::uint32_t version = readLe32(p + 4);
    const std::uint32_t total = readLe32(p + 8);
    VEIL_CHECK(version == 2, "mesh file '{}': GLB version {} (only 2 is read)", file, version);
    VEIL_CHECK(total <= bytes.size(),
               "mesh file '{}': GLB header says {} bytes but the file has {}", file, total,
               bytes.size());
    std::optional<std::string_view> jsonChunk;
    std::uint64_t at = 12;
    for (int chunk = 0; at + 8 <= total; ++chunk) {
        const std::uint64_t length = readLe32(p + at);
        const std::uint32_t type = readLe32(p + at + 4);
        VEIL_CHECK(length <= total - at - 8,
                   "mesh file '{}': GLB chunk {} at byte {} claims {} bytes but only {} follow",
                   file, chunk, at, length, total - at - 8);
        if (chunk == 0) {
            VEIL_CHECK(type == 0x4E4F534Au, "mesh file '{}': the first GLB chunk is not JSON",
                       file);
            jsonChunk = std::string_view(bytes).substr(at + 8, length);
        } else if (chunk == 1 && type == 0x004E4942u) {
            binChunk = length;
        }
        at += 8 + length;
    }
    VEIL_CHECK(jsonChunk.has_value(), "mesh file '{}': GLB without a JSON chunk", file);
    return parseJsonText(*jsonChunk, file);
}

// The number at `v` when it is one.
std::optional<double> number(const json& v) {
    if (!v.is_number()) return std::nullopt;
    return v.get<double>();
}

} // namespace

void checkGltfFile(const std::filesystem::path& path) {
    std::optional<std::uint64_t> binChunk;
    const json doc = gltfJson(path, binChunk);
    checkDocument(doc, path, binChunk, path.string());
}

std::vector<std::string> gltfCollapsingNodes(const std::filesystem::path& path) {
    std::optional<std::uint64_t> binChunk;
    const json doc = gltfJson(path, binChunk);
    std::vector<std::string> out;
    const auto nodes = doc.find("nodes");
    if (nodes == doc.end() || !nodes->is_array()) return out;
    for (std::size_t i = 0; i < nodes->size(); ++i) {
        const json& node = (*nodes)[i];
        if (!node.is_object()) continue;
        std::string why;
        if (const auto scale = node.find("scale"); scale != node.end() && scale->is_array())
            for (const json& c : *scale)
                if (number(c) == 0.0) why = "scale " + scale->dump();
        if (const auto m = node.find("matrix");
            m != node.end() && m->is_array() && m->size() == 16) {
            double a[9];
            bool numbers = true;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) {
                    const std::optional<double> v = number((*m)[std::size_t(c * 4 + r)]);
                    numbers = numbers && v.has_value();
                    a[r * 3 + c] = v.value_or(0.0);
                }
            const double det = a[0] * (a[4] * a[8] - a[5] * a[7]) -
                               a[1] * (a[3] * a[8] - a[5] * a[6]) +
                               a[2] * (a[3] * a[7] - a[4] * a[6]);
            if (numbers && det == 0.0) why = "a matrix of determinant 0";
        }
        if (why.empty()) continue;
        const auto name = node.find("name");
        out.push_back(fmt::format("nodes[{}]{} ({})", i,
                                  name != node.end() && name->is_string()
                                      ? " '" + name->get<std::string>() + "'"
                                      : std::string(),
                                  why));
    }
    return out;
}

} // namespace veil::scene
