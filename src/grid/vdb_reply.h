// How a trial read's child hands the grids it read to the parent (grid/vdb_file.cpp): the grid
// count, then per grid its type, name and half-float flag, and what OpenVDB's archive holds of a
// grid (metadata, transform, topology, buffers) written by the grid's own methods with every
// value plain (COMPRESS_NONE: no zip, blosc or mask coding to decode here).
//
// Not io::Stream's writer: Archive::writeGrid computes delayed-load metadata with TBB, and TBB
// used in a child forked while other threads of the parent ran TBB work waits for ever (a fork
// copies TBB's scheduler state but only the forking thread). Seen with two prefetch workers on
// 16 cores: one converting a grid with TBB while the other forked. Writing a grid's parts does
// not use TBB.
#pragma once

#include <openvdb/openvdb.h>

#include <iosfwd>

namespace veil::volume {

void writeGridReply(std::ostream& os, const openvdb::GridPtrVec& grids);

// Throws veil::Error when the reply is malformed (it is written by our own child, so only a
// bug or a dying child gets here).
openvdb::GridPtrVecPtr readGridReply(std::istream& is);

} // namespace veil::volume
