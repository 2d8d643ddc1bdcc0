// Uploading a converted grid (gpu_volume.h; the conversion is grid_conversion.cpp).
#include "fog/gpu_volume.h"

#include "base/error.h"
#include "base/log.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace veil::volume {

gpu::Texture makeFilteredTexture3D(const glm::ivec3& size, GLenum internalFormat, GLenum format,
                                   const float* texels, GLenum wrap) {
    gpu::Texture t(GL_TEXTURE_3D);
    t.storage3D(1, internalFormat, size.x, size.y, size.z)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GLint(wrap))
        .parameter(GL_TEXTURE_WRAP_T, GLint(wrap))
        .parameter(GL_TEXTURE_WRAP_R, GLint(wrap));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(t.id(), 0, 0, 0, 0, size.x, size.y, size.z, format, GL_FLOAT, texels);
    return t;
}

namespace {

GLenum densityFormat(int components) { return components == 4 ? GL_RGBA16F : GL_R16F; }

// `t` kept when it is a 3D texture of `size` and `internalFormat`; else a new one, filtered
// (trilinear, clamped edges) or, with `nearest`, not.
void ensureTexture(gpu::Texture& t, const glm::ivec3& size, GLenum internalFormat,
                   bool nearest = false) {
    if (t && t.width() == size.x && t.height() == size.y && t.depth() == size.z &&
        t.format() == internalFormat)
        return;
    t = gpu::Texture(GL_TEXTURE_3D);
    const GLint filter = nearest ? GL_NEAREST : GL_LINEAR;
    t.storage3D(1, internalFormat, size.x, size.y, size.z)
        .parameter(GL_TEXTURE_MIN_FILTER, filter)
        .parameter(GL_TEXTURE_MAG_FILTER, filter);
    if (nearest) return;
    t.parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
}

// `texels` as half floats into `out`: the conversion's own (packHalf()) when it made them, else
// converted here.
void toHalf(const std::vector<float>& texels, const std::vector<std::uint16_t>& half,
            std::uint16_t* out) {
    if (half.size() == texels.size())
        std::memcpy(out, half.data(), half.size() * 2);
    else
        volume::toHalf(texels.data(), out, texels.size());
}

// The texels [0, size) of `t` from `pixels`: client memory, or an offset into the bound pixel
// unpack buffer.
void write(const gpu::Texture& t, const glm::ivec3& size, GLenum format, GLenum type,
           const void* pixels) {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(t.id(), 0, 0, 0, 0, size.x, size.y, size.z, format, type, pixels);
}

} // namespace

GpuVolume::GpuVolume(openvdb::FloatGrid::ConstPtr grid, const glm::mat4& objectToWorld,
                     const GpuVolumeOptions& options) {
    VEIL_CHECK(grid && grid->activeVoxelCount() > 0, "empty density grid");
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    upload(convertGrid(*grid, options, max3D), objectToWorld);
}

GpuVolume::GpuVolume(const GridConversion& converted, const glm::mat4& objectToWorld) {
    upload(converted, objectToWorld);
}

GpuVolume::~GpuVolume() {
    if (uploaded_) glDeleteSync(uploaded_);
}

glm::ivec3 GpuVolume::allocatedSize(const glm::ivec3& texels, bool atlas, int max3D) {
    // n units rounded up to a multiple of an eighth of its power of two, at least `least`.
    auto round = [max3D](int n, int unit, int least) {
        const int units = (n + unit - 1) / unit;
        int power = 1;
        while (power <= units / 2)
            power *= 2;
        const int step = std::max(least, power / 8);
        const int up = (units + step - 1) / step * step * unit;
        return max3D > 0 ? std::max(n, std::min(up, max3D / unit * unit)) : up;
    };
    if (atlas) return {texels.x, texels.y, round(texels.z, 10, 2)};
    return {round(texels.x, 1, 8), round(texels.y, 1, 8), round(texels.z, 1, 8)};
}

std::size_t GpuVolume::stage(const void* data, std::size_t bytes) {
    const std::size_t at = stagingUsed_;
    if (bytes > 0) std::memcpy(static_cast<char*>(stagingMap_) + at, data, bytes);
    stagingUsed_ += (bytes + 255) / 256 * 256; // offsets aligned for any texel type
    return at;
}

std::size_t GpuVolume::stageHalf(const std::vector<float>& texels,
                                 const std::vector<std::uint16_t>& half) {
    const std::size_t at = stagingUsed_;
    toHalf(texels, half, reinterpret_cast<std::uint16_t*>(static_cast<char*>(stagingMap_) + at));
    stagingUsed_ += (texels.size() * 2 + 255) / 256 * 256;
    return at;
}

namespace {

// The texture bytes of `c`'s frame at its allocated sizes.
std::size_t frameBytes(const GridConversion& c, int max3D) {
    auto texels = [](const glm::ivec3& s) { return std::size_t(s.x) * s.y * s.z; };
    const std::size_t data = texels(GpuVolume::allocatedSize(c.dataSize, !c.stats.dense, max3D));
    std::size_t bytes = data * 2;
    if (!c.channel.empty()) bytes += data * 2 * std::size_t(c.channelComponents);
    if (!c.stats.dense) bytes += texels(GpuVolume::allocatedSize(c.tableSize, false, max3D)) * 4;
    if (!c.neighbourhood.mean.empty()) bytes += texels(c.neighbourhood.size) * 4;
    return bytes;
}

} // namespace

void GpuVolume::replace(const GridConversion& c, const glm::mat4& objectToWorld) {
    VEIL_CHECK(!c.values.empty(), "density grid conversion holds no data");
    if (!c.gpuKey.empty() && c.gpuHoldBytes > 0)
        for (const std::unique_ptr<Frame>& f : frames_)
            if (f->key == c.gpuKey) { // held: shown again without an upload
                ++reshown_;
                show(f.get(), objectToWorld);
                return;
            }
    // The texels go through the staging buffer: glTextureSubImage3D then returns at once and
    // the GPU copies them in order with the commands before and after (the previous frame's
    // render), instead of the driver copying (and converting) client memory before returning.
    auto aligned = [](std::size_t b) { return (b + 255) / 256 * 256; };
    const std::size_t bytes =
        aligned(c.values.size() * 2) + aligned(c.channel.size() * 2) + aligned(c.table.size() * 4);
    if (uploaded_) {
        // The previous upload has read the buffer (at once after a frame's glFinish).
        while (glClientWaitSync(uploaded_, GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000) ==
               GL_TIMEOUT_EXPIRED) {
        }
        glDeleteSync(uploaded_);
        uploaded_ = nullptr;
    }
    if (!staging_ || staging_.size() < bytes) {
        const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
        staging_ = gpu::Buffer(); // the old one is unmapped as it is deleted
        staging_.setStorage(bytes + bytes / 4, nullptr, flags);
        stagingMap_ = glMapNamedBufferRange(staging_.id(), 0, GLsizeiptr(staging_.size()), flags);
        VEIL_CHECK(stagingMap_, "cannot map a {:.1f} MiB volume staging buffer",
                   double(staging_.size()) / 1048576.0);
    }
    stagingUsed_ = 0;
    const std::size_t values = stageHalf(c.values, c.halfValues);
    const std::size_t channel = stageHalf(c.channel, c.halfChannel);
    const std::size_t table = stage(c.table.data(), c.table.size() * 4);
    Frame* f = frameFor(c);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, staging_.id());
    upload(*f, c, reinterpret_cast<const void*>(values), reinterpret_cast<const void*>(channel),
           reinterpret_cast<const void*>(table));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    uploaded_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    show(f, objectToWorld);
}

GpuVolume::Frame* GpuVolume::frameFor(const GridConversion& c) {
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    const std::size_t need = frameBytes(c, max3D), budget = c.gpuHoldBytes;
    // Frames nobody asks for again (no key) go first, then the least recently shown, until
    // the held bytes and the new frame's fit the budget.
    std::stable_sort(frames_.begin(), frames_.end(), [](const auto& a, const auto& b) {
        return std::make_pair(!a->key.empty(), a->lastShown) <
               std::make_pair(!b->key.empty(), b->lastShown);
    });
    std::size_t held = 0;
    for (const std::unique_ptr<Frame>& f : frames_)
        held += f->bytes;
    std::vector<std::unique_ptr<Frame>> dropped;
    std::size_t n = 0;
    for (; n < frames_.size() && (frames_[n]->key.empty() || held + need > budget); ++n) {
        held -= frames_[n]->bytes;
        dropped.push_back(std::move(frames_[n]));
    }
    frames_.erase(frames_.begin(), frames_.begin() + std::ptrdiff_t(n));
    // A dropped frame's textures are reused, one of the new data size where there is one.
    const glm::ivec3 size = allocatedSize(c.dataSize, !c.stats.dense, max3D);
    std::unique_ptr<Frame> f;
    for (std::unique_ptr<Frame>& d : dropped)
        if (!f && d->data && d->data.width() == size.x && d->data.height() == size.y &&
            d->data.depth() == size.z)
            f = std::move(d);
    for (std::unique_ptr<Frame>& d : dropped)
        if (!f && d) f = std::move(d);
    if (!f) f = std::make_unique<Frame>();
    f->key = !c.gpuKey.empty() && need <= budget ? c.gpuKey : std::string();
    f->bytes = need;
    frames_.push_back(std::move(f));
    shown_ = frames_.back().get(); // the shown frame may have been dropped
    return shown_;
}

void GpuVolume::show(Frame* f, const glm::mat4& objectToWorld) {
    shown_ = f;
    f->lastShown = ++shownCount_;
    indexToWorld_ = objectToWorld * f->gridToWorld;
    worldToIndex_ = glm::inverse(indexToWorld_);
    voxelSize_ = std::max({glm::length(glm::vec3(indexToWorld_[0])),
                           glm::length(glm::vec3(indexToWorld_[1])),
                           glm::length(glm::vec3(indexToWorld_[2]))});
    stats_ = f->stats;
    stats_.heldFrames = frames_.size();
    stats_.heldBytes = 0;
    for (const std::unique_ptr<Frame>& h : frames_)
        stats_.heldBytes += h->bytes;
    stats_.uploads = uploads_;
    stats_.uploadedBytes = uploadedBytes_;
    stats_.reshown = reshown_;
}

void GpuVolume::upload(const GridConversion& c, const glm::mat4& objectToWorld) {
    VEIL_CHECK(!c.values.empty(), "density grid conversion holds no data");
    std::vector<std::uint16_t> values(c.values.size()), channel(c.channel.size());
    toHalf(c.values, c.halfValues, values.data());
    toHalf(c.channel, c.halfChannel, channel.data());
    Frame* f = frameFor(c);
    upload(*f, c, values.data(), channel.data(), c.table.data());
    show(f, objectToWorld);
}

void GpuVolume::upload(Frame& f, const GridConversion& c, const void* values, const void* channel,
                       const void* table) {
    if (c.stats.coarsened > 0)
        log::warn("grid '{}': {}; coarsened to voxel size x{} ({:.1f} MiB)", c.name,
                  c.coarsenedBecause, 1 << c.stats.coarsened, c.stats.gpuBytes / 1048576.0);
    ++uploads_;
    uploadedBytes_ += c.values.size() * 2 + c.channel.size() * 2 + c.table.size() * 4 +
                      c.neighbourhood.mean.size() * 4;
    f.stats = c.stats;
    f.gridToWorld = c.indexToWorld;
    f.indexMin = c.indexMin;
    f.indexMax = c.indexMax;
    f.leafOrigin = c.leafOrigin;
    f.bricksPerAxis = c.bricksPerAxis;
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    const glm::ivec3 size = allocatedSize(c.dataSize, !c.stats.dense, max3D);
    ensureTexture(f.data, size, GL_R16F);
    write(f.data, c.dataSize, GL_RED, GL_HALF_FLOAT, values);
    f.channelComponents = c.channel.empty() ? 0 : c.channelComponents;
    if (f.channelComponents > 0) {
        ensureTexture(f.channel, size, densityFormat(f.channelComponents));
        write(f.channel, c.dataSize, f.channelComponents == 4 ? GL_RGBA : GL_RED, GL_HALF_FLOAT,
              channel);
    } else {
        f.channel = gpu::Texture(gpu::NoCreate);
    }
    // GL's default border colour is 0: cells outside the array read 0, so its size is exact.
    f.neighbourhood = gpu::Texture(gpu::NoCreate);
    if (!c.neighbourhood.mean.empty()) {
        GLint unpack = 0;
        glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        f.neighbourhood = makeFilteredTexture3D(c.neighbourhood.size, GL_R32F, GL_RED,
                                                c.neighbourhood.mean.data(), GL_CLAMP_TO_BORDER);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(unpack));
        f.neighbourhoodOrigin = c.neighbourhood.origin;
    }
    if (c.stats.dense) {
        f.indirection = gpu::Texture(gpu::NoCreate);
        return;
    }
    // Entries past the table are never fetched: the marcher tests indexMin/indexMax first.
    ensureTexture(f.indirection, allocatedSize(c.tableSize, false, max3D), GL_R32UI, true);
    write(f.indirection, c.tableSize, GL_RED_INTEGER, GL_UNSIGNED_INT, table);
}

void GpuVolume::worldBounds(glm::vec3& lo, glm::vec3& hi) const {
    lo = glm::vec3(1e30f);
    hi = glm::vec3(-1e30f);
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 p((c & 1) ? indexMax().x : indexMin().x,
                          (c & 2) ? indexMax().y : indexMin().y,
                          (c & 4) ? indexMax().z : indexMin().z);
        const glm::vec3 w = glm::vec3(indexToWorld_ * glm::vec4(p, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
}

} // namespace veil::volume
