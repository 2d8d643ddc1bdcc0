// Reads every grid of a .vdb file through OpenVDB itself, for tests that check what Veil wrote.
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>

namespace veil::test {

inline openvdb::GridPtrVecPtr readVdbGrids(const std::filesystem::path& path) {
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.open();
    openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();
    return grids;
}

} // namespace veil::test
