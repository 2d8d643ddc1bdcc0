// The structural check of an OpenVDB file's header (vdb_file.cpp): every length and count the
// header gives is compared with the file's size before OpenVDB reads the file.
#pragma once

#include "base/error.h"
#include "grid/vdb_file.h"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

namespace veil::volume::detail {

namespace fs = std::filesystem;

// The header's strings and counts checked against the file size, before any OpenVDB code sees
// the file. OpenVDB allocates a string of the length a header gives (filled with spaces) and
// then reads into it, and reserves descriptors for the grid count it reads, so one corrupt
// 32-bit length in a 28 KB file cost 4 GB and 14-34 s
// (tests/fuzz/regressions/volume/grid-type-length-4g-timeout.vdb). The layout (OpenVDB
// io/Archive, file versions 222 and later): magic, version, library version, a has-offsets
// byte, a 36-byte UUID, the file metadata (count; per entry a name, a type name and a
// size-prefixed value), the grid count and per grid a descriptor (unique name, type name,
// instance parent name, then the grid, block and end offsets) followed at the grid offset by
// the grid's compression flags and its metadata. Strings are a 32-bit length and the bytes.
// Older versions are left to OpenVDB (in the child).
class HeaderCheck {
public:
    HeaderCheck(const fs::path& path, std::uint64_t size)
        : in_(path, std::ios::binary), file_(path.string()), size_(size) {}

    // A descriptor's grid, block and end offsets; `usable` when they are in order and in the
    // file (a file written by io::Stream has none).
    struct Offsets {
        std::int64_t grid = 0, block = 0, end = 0;
        bool usable = false;
    };

    // The file header, the file metadata and, at their offsets, every grid's descriptor and
    // grid header. known() tells afterwards whether the layout was one this check knows.
    void run() {
        char magic[8];
        if (!in_.read(magic, 8) || std::memcmp(magic, " BDV\0\0\0\0", 8) != 0) return;
        const std::uint32_t version = u32("the file version");
        if (version < 222 || version > 300) return; // not a layout this check knows
        u32("the library version");
        u32("the library version");
        char offsets = 0;
        need(1 + 36, "the header");
        in_.get(offsets);
        in_.ignore(36); // UUID
        metadata("the file metadata");
        const std::uint32_t grids = u32("the grid count");
        // A descriptor takes at least 3 lengths and 3 offsets.
        need(std::uint64_t(grids) * 36, fmt::format("{} grid descriptors", grids));
        known_ = true;
        offsets_ = offsets != 0;
        for (std::uint32_t i = 0; i < grids; ++i) {
            const std::string where = fmt::format("grid {} of {}", i + 1, grids);
            const Offsets o = descriptor(pos(), where);
            // Written by io::Stream: no offsets, the grids follow each other and only the
            // first one's header can be found without decoding its tree; the child's read
            // checks the others where it finds them.
            if (!o.usable) break;
            gridHeader(o.grid, where);
            in_.seekg(o.end);
        }
    }
    bool known() const { return known_; }

    // The grid descriptor at byte `at`: its three strings fit in the file. Throws if the file
    // has grid offsets and this descriptor's are out of order or past the end.
    Offsets descriptor(std::int64_t at, const std::string& where) {
        in_.clear();
        in_.seekg(at);
        skipString(where + "'s name");
        skipString(where + "'s type name");
        skipString(where + "'s instance parent name");
        Offsets o;
        o.grid = i64(where);
        o.block = i64(where);
        o.end = i64(where);
        o.usable = o.grid >= pos() && o.grid <= o.block && o.block <= o.end &&
                   std::uint64_t(o.end) <= size_;
        VEIL_CHECK(o.usable || !offsets_,
                   "cannot read OpenVDB file '{}' (truncated or corrupt?): {} has the offsets "
                   "{}, {}, {} (grid, blocks, end), out of order or past the end of the file "
                   "({} bytes)",
                   file_, where, o.grid, o.block, o.end, size_);
        return o;
    }

    // The grid header at byte `at`: compression flags, the grid's metadata and its transform's
    // map type name (io::Archive::readGrid reads them in this order before the tree).
    void gridHeader(std::int64_t at, const std::string& where) {
        in_.clear();
        in_.seekg(at);
        u32(where + "'s compression flags");
        metadata(where + "'s metadata");
        skipString(where + "'s transform type");
    }

private:
    std::int64_t pos() { return std::int64_t(in_.tellg()); }

    // `n` more bytes must be in the file.
    void need(std::uint64_t n, const std::string& what) {
        const std::int64_t at = pos();
        VEIL_CHECK(in_ && at >= 0 && std::uint64_t(at) <= size_ && n <= size_ - std::uint64_t(at),
                   "cannot read OpenVDB file '{}' (truncated or corrupt?): {} at byte {} needs "
                   "{} bytes, past the end of the file ({} bytes)",
                   file_, what, at, n, size_);
    }
    std::uint32_t u32(const std::string& what) {
        need(4, what);
        unsigned char b[4];
        in_.read(reinterpret_cast<char*>(b), 4);
        return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 |
               std::uint32_t(b[3]) << 24;
    }
    std::int64_t i64(const std::string& what) {
        const std::uint64_t lo = u32(what), hi = u32(what);
        return std::int64_t(lo | hi << 32);
    }
    void skip(std::uint64_t n, const std::string& what) {
        need(n, what);
        in_.seekg(std::streamoff(n), std::ios::cur);
    }
    void skipString(const std::string& what) { skip(u32(what), what); }
    std::string readString(const std::string& what) {
        const std::uint32_t n = u32(what);
        need(n, what);
        std::string s(n, '\0');
        in_.read(s.data(), std::streamsize(n));
        return s;
    }
    // The value size OpenVDB reads for a metadata type whatever byte count the file gives: the
    // fixed-size TypedMetadata types openvdb::initialize() registers (TypedMetadata::readValue
    // reads sizeof(T)); 0 for the others (string, __delayedload, unregistered types), which read
    // the count.
    static std::uint32_t fixedValueSize(const std::string& type) {
        using namespace openvdb;
        static const std::map<std::string, std::uint32_t> sizes = [] {
            std::map<std::string, std::uint32_t> m;
            auto add = [&m]<typename M>(M) { m[M::staticTypeName()] = M().size(); };
            add(BoolMetadata()), add(Int32Metadata()), add(Int64Metadata());
            add(FloatMetadata()), add(DoubleMetadata());
            add(Vec2IMetadata()), add(Vec2SMetadata()), add(Vec2DMetadata());
            add(Vec3IMetadata()), add(Vec3SMetadata()), add(Vec3DMetadata());
            add(Vec4IMetadata()), add(Vec4SMetadata()), add(Vec4DMetadata());
            add(Mat4SMetadata()), add(Mat4DMetadata());
            return m;
        }();
        const auto it = sizes.find(type);
        return it == sizes.end() ? 0 : it->second;
    }
    // A metadata entry's value is a byte count and the bytes, but OpenVDB reads a value of a
    // fixed-size type (vec3i, mat4d, ...) as sizeof(T) bytes whatever the count says.
    // A fuzz finding (tests/fuzz/regressions/volume/metadata-type-vec3i-to-vec4i.vdb) changed one
    // type name from vec3i to vec4i: OpenVDB read 4 bytes too many, the next name's length came
    // from the letters "_bbo" (1.9 GB) and 8 GB of strings were allocated and filled (5-20 s,
    // mostly system time). So the count must be the size OpenVDB will read.
    void metadata(const std::string& what) {
        const std::uint32_t count = u32(what);
        need(std::uint64_t(count) * 12, fmt::format("{} ({} entries)", what, count));
        for (std::uint32_t i = 0; i < count; ++i) {
            const std::string entry = fmt::format("{}, entry {} of {}", what, i + 1, count);
            const std::string name = readString(entry + ", its name");
            const std::string type = readString(entry + ", its type name");
            const std::uint32_t bytes = u32(entry + ", its value");
            if (const std::uint32_t fixed = fixedValueSize(type)) {
                VEIL_CHECK(bytes == fixed,
                           "cannot read OpenVDB file '{}' (corrupt?): {} ('{}') is a {} value, "
                           "which is {} bytes, but the file gives {} bytes",
                           file_, entry, boundedText(name, 60), type, fixed, bytes);
            }
            skip(bytes, entry + ", its value");
        }
    }

    std::ifstream in_;
    std::string file_;
    std::uint64_t size_;
    bool known_ = false, offsets_ = false;
};

} // namespace veil::volume::detail
