// Reading a .vdb file so that a corrupt one ends in a veil::Error naming the file, never in a
// crash of the calling process, a delayed decode error later, or an unbounded message.
//
// Containment: OpenVDB 10 does not validate what it decodes, and some damage corrupts the heap
// or dereferences garbage inside its reader, which no try/catch can contain. Of 450 damaged
// copies of torus01/sphere/grids.vdb (single bit flips and 64-byte random overwrites), 6 killed
// an eager in-process read (SIGSEGV, glibc "corrupted top size" / "double free" aborts); with
// delayed loading 5 of 24 byte flips of torus01.vdb did. So the file is read in a forked child
// process (trial read) that decodes everything; a crash, a kill or a timeout there becomes an
// error here. Validating the tree after an in-process read would come too late: the crash
// happens while reading. Not every corruption crashes, though: a blosc block claiming more
// bytes than its buffer overflowed the heap silently. So this process never parses the file's
// bytes with OpenVDB: the child sends the grids it read back re-encoded by io::Stream (plain
// values, no decompressor) and only that is decoded here (vdb_file.cpp says why).
// Before the child, the header's string lengths, counts and grid offsets are checked against
// the file size, so a corrupt length is refused at once instead of allocating gigabytes; the
// child checks each grid's descriptor and header again where it reads them, and that each
// grid ends where its descriptor says.
//
// One child per reading thread serves all of that thread's reads (a frame range's worker reads
// file after file) instead of a fork per file. A crash, a hang or a
// failed read ends that child, the error names the file, and the next read starts a fresh one;
// a child is also replaced after about 512 MiB of grids read (it keeps what it read). What a
// file did to a child's heap can therefore reach the next files that child reads only when
// OpenVDB read the damaged file without noticing (the silent blosc overflow above): then the
// values those later files give may be wrong, but this process still decodes nothing but
// plain re-encoded values.
//
// The child's read is eager (no delayed loading), so OpenVDB's "Expected to decompress N bytes"
// cannot surface later without a file name, and goes through io::Stream, which reports a file
// that ends early (io::File's eager path silently reads zeros there).
#pragma once

#include <openvdb/openvdb.h>

#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace veil::volume {

// Every grid of the file, fully loaded. Throws veil::Error for a missing file, something that is
// not a regular file, or a truncated or corrupt file (naming the file and, where the header
// could be read, its grids; OpenVDB's own text is cut to a bounded length).
openvdb::GridPtrVecPtr readVdbFile(const std::filesystem::path& path);

// While one is alive on a thread, readVdbFile() there of a file it read already in the scope
// (same path, size and modification time) returns the same grids instead of reading it again:
// a frame's density and its emission channel (two grids of one file) come from one read.
class VdbReadScope {
public:
    VdbReadScope();
    ~VdbReadScope();
    VdbReadScope(const VdbReadScope&) = delete;
    VdbReadScope& operator=(const VdbReadScope&) = delete;

    struct Entry {
        std::filesystem::path path;
        std::uint64_t size = 0;
        std::filesystem::file_time_type time;
        openvdb::GridPtrVecPtr grids;
    };

private:
    std::vector<Entry> entries_;
    VdbReadScope* previous_;
    friend openvdb::GridPtrVecPtr readVdbFile(const std::filesystem::path& path);
};

// Called in this process after the child's reply arrived and before it is decoded (tests:
// replacing the file there shows that this process does not read it again). Empty: none.
void setAfterTrialReadHookForTesting(std::function<void()> hook);

// Tests: reader children started so far (in this process, all threads), and a file name (no
// folder) whose read makes the reader child crash with SIGSEGV (empty: none).
int readerStartsForTesting();
void setReaderCrashForTesting(const std::string& fileName);
// Tests: a file name (no folder) whose reply the reader child damages (`kind` 1: cut to half
// its size; 2: left unsealed; empty name: none).
void setReplyDamageForTesting(const std::string& fileName, int kind);

// OpenVDB guards its type registries (grids, metadata, maps) with mutexes of its own, taken for
// every grid and metadata item a read creates. A trial read's child forked while another thread
// of this process held one of them would wait on it for ever (the child has only the forking
// thread). So the fork, the decoding of a child's reply and every OpenVDB read or write of this
// process that can run beside another thread's read (the prefetch workers, the viewer's frame
// cache) hold this lock.
std::mutex& openVdbIoMutex();

// `text` on one line (control bytes replaced) and at most `limit` characters.
std::string boundedText(const std::string& text, std::size_t limit = 300);

} // namespace veil::volume
