#include "grid/vdb_reply.h"

#include "base/error.h"

#include <openvdb/io/io.h>

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>

namespace veil::volume {

namespace {

constexpr std::uint32_t kMaxGrids = 1u << 16;
constexpr std::uint32_t kMaxName = 1u << 20;

// The stream state OpenVDB's node I/O reads: this library's file format, plain values, and a
// metadata object (half-float flag per grid; leaf reads consult it).
openvdb::io::StreamMetadata::Ptr prepare(std::ios_base& s) {
    auto meta = std::make_shared<openvdb::io::StreamMetadata>();
    openvdb::io::setStreamMetadataPtr(s, meta, /*transfer=*/false);
    openvdb::io::setVersion(s,
                            openvdb::VersionId(openvdb::OPENVDB_LIBRARY_MAJOR_VERSION,
                                               openvdb::OPENVDB_LIBRARY_MINOR_VERSION),
                            openvdb::OPENVDB_FILE_VERSION);
    openvdb::io::setDataCompression(s, openvdb::io::COMPRESS_NONE);
    return meta;
}

void writeU32(std::ostream& os, std::uint32_t v) {
    os.write(reinterpret_cast<const char*>(&v), sizeof v);
}

std::uint32_t readU32(std::istream& is, std::uint32_t limit, const char* what) {
    std::uint32_t v = 0;
    is.read(reinterpret_cast<char*>(&v), sizeof v);
    VEIL_CHECK(is && v <= limit, "the trial read's reply is malformed ({})", what);
    return v;
}

void writeString(std::ostream& os, const std::string& s) {
    writeU32(os, static_cast<std::uint32_t>(s.size()));
    os.write(s.data(), std::streamsize(s.size()));
}

std::string readString(std::istream& is, const char* what) {
    std::string s(readU32(is, kMaxName, what), '\0');
    is.read(s.data(), std::streamsize(s.size()));
    VEIL_CHECK(is, "the trial read's reply is malformed ({})", what);
    return s;
}

} // namespace

void writeGridReply(std::ostream& os, const openvdb::GridPtrVec& grids) {
    const auto meta = prepare(os);
    writeU32(os, static_cast<std::uint32_t>(grids.size()));
    for (const openvdb::GridBase::Ptr& g : grids) {
        writeString(os, g->type());
        writeString(os, g->getName());
        os.put(g->saveFloatAsHalf() ? 1 : 0);
        meta->setHalfFloat(g->saveFloatAsHalf());
        openvdb::io::setHalfFloat(os, g->saveFloatAsHalf());
        openvdb::io::setGridClass(os, g->getGridClass());
        g->writeMeta(os);
        g->writeTransform(os);
        g->writeTopology(os);
        g->writeBuffers(os);
    }
}

openvdb::GridPtrVecPtr readGridReply(std::istream& is) {
    const auto meta = prepare(is);
    auto grids = std::make_shared<openvdb::GridPtrVec>();
    const std::uint32_t count = readU32(is, kMaxGrids, "grid count");
    for (std::uint32_t i = 0; i < count; ++i) {
        const std::string type = readString(is, "grid type");
        const std::string name = readString(is, "grid name");
        const int half = is.get();
        VEIL_CHECK(is && (half == 0 || half == 1) && openvdb::GridBase::isRegistered(type),
                   "the trial read's reply is malformed (grid {} '{}')", i + 1, name);
        openvdb::GridBase::Ptr g = openvdb::GridBase::createGrid(type);
        g->setSaveFloatAsHalf(half == 1);
        meta->setHalfFloat(half == 1);
        openvdb::io::setHalfFloat(is, half == 1);
        g->readMeta(is);
        openvdb::io::setGridClass(is, g->getGridClass());
        g->readTransform(is);
        g->readTopology(is);
        g->readBuffers(is);
        VEIL_CHECK(is, "the trial read's reply ends inside grid {} '{}'", i + 1, name);
        g->setName(name);
        grids->push_back(g);
    }
    return grids;
}

} // namespace veil::volume
