// Reading a .vdb file so that a corrupt one ends in a veil::Error naming the file, never in a
// crash of the calling process, a delayed decode error later, or an unbounded message.
//
// Containment: OpenVDB 10 does not validate what it decodes, and some damage corrupts the heap
// or dereferences garbage inside its reader, which no try/catch can contain. Of 450 damaged
// copies of torus01/sphere/grids.vdb (single bit flips and 64-byte random overwrites), 6 killed
// an eager in-process read (SIGSEGV, glibc "corrupted top size" / "double free" aborts); with
// delayed loading 5 of 24 byte flips of torus01.vdb did. So the file is first read in a forked
// child process (trial read) that decodes everything and walks every value; a crash, a kill or
// a timeout there becomes an error here. Only then does this process read the file itself.
// Reading is deterministic, so a file the child read completely is read the same way here.
// Validating the tree after an in-process read would come too late: the crash happens while
// reading. Measured on smoke.vdb (2.5 MB, 1.05 M voxels, 2 cores under load): the trial
// read takes 25-40 ms (fork, decode, value walk) against 7-12 ms for the read itself.
//
// Both reads are eager (no delayed loading), so OpenVDB's "Expected to decompress N bytes"
// cannot surface later without a file name, and go through io::Stream, which reports a file
// that ends early (io::File's eager path silently reads zeros there).
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>
#include <string>

namespace veil::volume {

// Every grid of the file, fully loaded. Throws veil::Error for a missing file, something that is
// not a regular file, or a truncated or corrupt file (naming the file and, where the header
// could be read, its grids; OpenVDB's own text is cut to a bounded length).
openvdb::GridPtrVecPtr readVdbFile(const std::filesystem::path& path);

// `text` on one line (control bytes replaced) and at most `limit` characters.
std::string boundedText(const std::string& text, std::size_t limit = 300);

} // namespace veil::volume
