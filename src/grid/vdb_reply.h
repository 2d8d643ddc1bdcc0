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

#include <cstdint>
#include <iosfwd>

namespace veil::volume {

void writeGridReply(std::ostream& os, const openvdb::GridPtrVec& grids);

// Throws veil::Error when the reply is malformed (it is written by our own child, so only a
// bug or a dying child gets here).
openvdb::GridPtrVecPtr readGridReply(std::istream& is);

// The reply through shared memory instead of a byte stream (vdb_file.cpp passes the descriptor
// over the reader's socket): the child writes it straight into a memfd mapped in its address
// space (grown as it is written; `sizeHint` bytes reserved first, untouched pages cost
// nothing), then unmaps it and seals it against writing, growing and shrinking, so the parent
// parses bytes that the child can no longer change (a child whose heap a file damaged cannot
// alter the reply while the parent reads it). Returns the descriptor (the caller closes it) and
// the reply's size in `size`. Throws veil::Error. `damage` is for tests only: 1 cuts the reply
// to half its size, 2 leaves it unsealed.
int writeGridReplyToMemory(const openvdb::GridPtrVec& grids, std::uint64_t sizeHint,
                           std::uint64_t& size, int damage = 0);

// The parent's side: decodes the reply in `fd` (which it then owns no more than before: the
// caller closes it), refused unless it is a memfd sealed against writing, growing and shrinking
// of exactly `size` bytes; parsed in place from a read-only mapping (no copy). Throws
// veil::Error.
openvdb::GridPtrVecPtr readGridReplyFromMemory(int fd, std::uint64_t size);

} // namespace veil::volume
