#include "grid/vdb_reply.h"

#include "base/error.h"

#include <openvdb/io/io.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <istream>
#include <ostream>
#include <streambuf>
#include <string>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

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

// An output stream buffer over a memfd mapped in this process: every write lands in the mapping
// (no put area: OpenVDB writes whole buffers through xsputn), which grows by doubling (ftruncate,
// then mremap: the pages written stay where they are).
class MemoryReplyBuf : public std::streambuf {
public:
    MemoryReplyBuf(int fd, std::size_t capacity) : fd_(fd) { grow(capacity); }
    ~MemoryReplyBuf() override { unmap(); }
    MemoryReplyBuf(const MemoryReplyBuf&) = delete;
    MemoryReplyBuf& operator=(const MemoryReplyBuf&) = delete;

    std::size_t used() const { return used_; }
    void unmap() {
        if (base_) ::munmap(base_, capacity_);
        base_ = nullptr;
    }

protected:
    std::streamsize xsputn(const char* s, std::streamsize n) override {
        const auto bytes = std::size_t(n);
        if (used_ + bytes > capacity_) grow(std::max(capacity_ * 2, used_ + bytes));
        std::memcpy(base_ + used_, s, bytes);
        used_ += bytes;
        return n;
    }
    int_type overflow(int_type c) override {
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        const char ch = traits_type::to_char_type(c);
        xsputn(&ch, 1);
        return c;
    }

private:
    void grow(std::size_t capacity) {
        VEIL_CHECK(::ftruncate(fd_, off_t(capacity)) == 0,
                   "the trial read's reply of {} bytes does not fit in shared memory ({})",
                   capacity, std::strerror(errno));
        void* p = base_ ? ::mremap(base_, capacity_, capacity, MREMAP_MAYMOVE)
                        : ::mmap(nullptr, capacity, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
        VEIL_CHECK(p != MAP_FAILED, "cannot map the trial read's reply of {} bytes ({})", capacity,
                   std::strerror(errno));
        base_ = static_cast<char*>(p);
        capacity_ = capacity;
    }

    int fd_;
    char* base_ = nullptr;
    std::size_t capacity_ = 0, used_ = 0;
};

// An input stream buffer over bytes in memory, seekable (OpenVDB's leaf reads ask tellg()).
class MemoryReadBuf : public std::streambuf {
public:
    MemoryReadBuf(const char* data, std::size_t size) {
        char* p = const_cast<char*>(data); // read only: the get area is never written
        setg(p, p, p + size);
    }

protected:
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
        const off_type at = dir == std::ios_base::beg   ? off
                            : dir == std::ios_base::cur ? off_type(gptr() - eback()) + off
                                                        : off_type(egptr() - eback()) + off;
        if (at < 0 || at > off_type(egptr() - eback())) return pos_type(off_type(-1));
        setg(eback(), eback() + at, egptr());
        return pos_type(at);
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }
};

constexpr unsigned kSeals = F_SEAL_WRITE | F_SEAL_GROW | F_SEAL_SHRINK;

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

int writeGridReplyToMemory(const openvdb::GridPtrVec& grids, std::uint64_t sizeHint,
                           std::uint64_t& size, int damage) {
    const int fd = ::memfd_create("veil-vdb-reply", MFD_CLOEXEC | MFD_ALLOW_SEALING);
    VEIL_CHECK(fd >= 0, "no shared memory for the trial read's reply ({})", std::strerror(errno));
    try {
        MemoryReplyBuf buf(fd, std::max<std::size_t>(std::size_t(sizeHint), 1u << 20));
        {
            std::ostream os(&buf);
            writeGridReply(os, grids);
            VEIL_CHECK(os, "the trial read's reply could not be written");
        }
        buf.unmap(); // sealing against writes needs no writable mapping left
        size = buf.used();
        if (damage == 1) size /= 2;
        VEIL_CHECK(::ftruncate(fd, off_t(size)) == 0 &&
                       (damage == 2 || ::fcntl(fd, F_ADD_SEALS, kSeals | F_SEAL_SEAL) == 0),
                   "cannot seal the trial read's reply ({})", std::strerror(errno));
    } catch (...) {
        ::close(fd);
        throw;
    }
    return fd;
}

openvdb::GridPtrVecPtr readGridReplyFromMemory(int fd, std::uint64_t size) {
    const int seals = ::fcntl(fd, F_GET_SEALS);
    VEIL_CHECK(seals >= 0 && (unsigned(seals) & kSeals) == kSeals,
               "the trial read's reply is not sealed shared memory");
    struct stat st {};
    VEIL_CHECK(::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && std::uint64_t(st.st_size) == size,
               "the trial read's reply is not of the {} bytes announced", size);
    VEIL_CHECK(size > 0, "the trial read's reply is empty");
    void* p = ::mmap(nullptr, std::size_t(size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
    VEIL_CHECK(p != MAP_FAILED, "cannot map the trial read's reply of {} bytes ({})", size,
               std::strerror(errno));
    struct Unmap {
        void* p;
        std::size_t n;
        ~Unmap() { ::munmap(p, n); }
    } unmap{p, std::size_t(size)};
    MemoryReadBuf buf(static_cast<const char*>(p), std::size_t(size));
    std::istream is(&buf);
    return readGridReply(is);
}

} // namespace veil::volume
