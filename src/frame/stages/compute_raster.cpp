#include "frame/stages/compute_raster.h"

#include "base/error.h"
#include "base/log.h"

#include "shaders/common/bindings.h"

#include <fmt/format.h>

#include <algorithm>

namespace veil::frame {

namespace {

std::uint64_t nextPowerOfTwo(std::uint64_t v) {
    std::uint64_t p = 1;
    while (p < v)
        p <<= 1;
    return p;
}

// Immutable storage of at least `bytes` (recreated when smaller).
void ensureBuffer(gpu::Buffer& buffer, std::size_t& have, std::size_t bytes) {
    bytes = std::max<std::size_t>(bytes, 16);
    if (have >= bytes) return;
    buffer = gpu::Buffer();
    buffer.setStorage(bytes, nullptr);
    have = bytes;
}

GLuint groups(std::uint64_t n, std::uint64_t size) {
    return static_cast<GLuint>((n + size - 1) / size);
}

constexpr GLbitfield kStorageBarrier = GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT;

} // namespace

std::string ComputeRaster::supportedNames() {
    std::string out;
    for (const oit::TechniqueInfo& info : oit::Registry::instance().all())
        if (info.computeRaster) out += (out.empty() ? "" : ", ") + info.name;
    return out;
}

ComputeRaster::ComputeRaster(gpu::ProgramManager& programs, const oit::Technique& technique,
                             const gpu::IncludeAliases& surface,
                             const std::vector<std::string>& surfaceDefines)
    : programs_(programs) {
    const oit::TechniqueInfo* info = oit::Registry::instance().find(technique.name());
    VEIL_CHECK(info && info->computeRaster,
               "render.oit_rasterizer = compute: OIT technique '{}' has no compute-raster "
               "emission (techniques on the compute rasterizer: {}); use "
               "render.oit_rasterizer = raster",
               technique.name(), supportedNames());
    using gpu::ProgramDesc;
    setup_ = programs_.add(ProgramDesc::compute("frame/compute_raster/setup.comp", {}, surface));
    count_ = programs_.add(ProgramDesc::compute("frame/compute_raster/bin.comp", {}, surface));
    fill_ = programs_.add(
        ProgramDesc::compute("frame/compute_raster/bin.comp", {"BIN_FILL 1"}, surface));
    scanBatches_ = programs_.add(ProgramDesc::compute("frame/compute_raster/scan_batches.comp"));
    scanTiles_ =
        programs_.add(ProgramDesc::compute("frame/compute_raster/scan_tiles.comp", {}, surface));
    for (int pass = 0; pass < technique.geometryPasses(); ++pass) {
        // The emit file in its compute form (OIT_COMPUTE: targets as images at oitPixel).
        std::vector<std::string> defines = {"OIT_COMPUTE 1", "OIT_PIXEL_COORD oitPixel"};
        for (std::string& d : technique.defines(pass))
            defines.push_back(std::move(d));
        defines.push_back(fmt::format("OIT_PASS {}", pass));
        defines.insert(defines.end(), surfaceDefines.begin(), surfaceDefines.end());
        gpu::IncludeAliases aliases = surface;
        aliases.push_back({"veil:oit_emit", technique.emitInclude()});
        fine_.push_back(programs_.add(
            ProgramDesc::compute("frame/compute_raster/fine.comp", std::move(defines), aliases)));
    }
    triangles_ = gpu::Buffer();
    attributes_ = gpu::Buffer();
    counters_ = gpu::Buffer();
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    maxBlockBytes_ = maxBlock > 0 ? static_cast<std::uint64_t>(maxBlock) : ~std::uint64_t(0);
    tileStarts_ = gpu::Buffer();
    binOffsets_ = gpu::Buffer();
    lists_ = gpu::Buffer();
}

void ComputeRaster::bindBuffers() const {
    triangles_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_RASTER_TRIANGLES);
    attributes_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_RASTER_ATTRIBUTES);
    counters_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_RASTER_COUNTERS);
    tileStarts_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_RASTER_TILE_STARTS);
    binOffsets_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_RASTER_BIN_OFFSETS);
    lists_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_RASTER_TILE_LISTS);
}

void ComputeRaster::setup(const pass::Context& context) {
    const std::vector<std::uint32_t> counts = context.objectTriangles(pass::ObjectSet::Transparent);
    std::uint64_t total = 0;
    for (std::uint32_t c : counts)
        total += c;
    stats_.triangles = total;
    // Records are indexed with 28 bits (shaders/frame/compute_raster/raster.glsl).
    VEIL_CHECK(total < (std::uint64_t(1) << 27),
               "compute rasterizer: {} transparent triangles, more than 2^27", total);
    std::size_t countersNeed = 16 + counts.size() * 6 * 16;
    ensureBuffer(counters_, countersBytes_, countersNeed);
    // A power-of-two pixel span of the guard band: window coordinates within +-16384 pixels,
    // so fixed-point products stay below 2^47 (exact in double).
    const float guard =
        std::max(1.0f, 16384.0f / static_cast<float>(std::max(context.width, context.height)));
    for (int attempt = 0; attempt < 2; ++attempt) {
        const std::uint64_t records = total + extraCapacity_;
        if (records > triangleCapacity_) {
            const std::uint64_t n = std::max<std::uint64_t>(records, 64);
            VEIL_CHECK(n * kAttributeBytes <= maxBlockBytes_,
                       "compute rasterizer: {} triangle records need {:.1f} MiB of attributes, "
                       "more than this driver's shader storage block size ({:.1f} MiB); use "
                       "render.oit_rasterizer = raster or fewer transparent triangles",
                       n, double(n * kAttributeBytes) / 1048576.0,
                       double(maxBlockBytes_) / 1048576.0);
            triangles_ = gpu::Buffer();
            triangles_.setStorage(n * kTriangleBytes, nullptr);
            attributes_ = gpu::Buffer();
            attributes_.setStorage(n * kAttributeBytes, nullptr);
            triangleCapacity_ = n;
        }
        const GLuint zero = 0;
        glClearNamedBufferSubData(counters_.id(), GL_R32UI, 0, 16, GL_RED_INTEGER, GL_UNSIGNED_INT,
                                  &zero);
        bindBuffers();
        const gpu::Program& program = programs_.get(setup_);
        program.use();
        program.set("triangleCount", static_cast<unsigned>(total))
            .set("extraCapacity", static_cast<unsigned>(triangleCapacity_ - total))
            .set("viewportSize", glm::ivec2(context.width, context.height))
            .set("guardBand", guard);
        std::uint32_t base = 0;
        context.dispatchObjects(program, pass::ObjectSet::Transparent,
                                [&](std::uint32_t object, std::uint32_t triangles) {
                                    program.set("triangleBase", static_cast<unsigned>(base))
                                        .set("objectIndex", static_cast<unsigned>(object));
                                    glDispatchCompute(groups(std::max(triangles, 1u), 64), 1, 1);
                                    base += triangles;
                                });
        glMemoryBarrier(kStorageBarrier);
        GLuint extra = 0;
        glGetNamedBufferSubData(counters_.id(), 0, sizeof(GLuint), &extra);
        stats_.extraRecords = extra;
        if (extra <= triangleCapacity_ - total) return;
        // Clipping split more triangles than the extra region holds: grow it, set up again.
        extraCapacity_ = nextPowerOfTwo(extra);
        VEIL_CHECK(total + extraCapacity_ < (std::uint64_t(1) << 28),
                   "compute rasterizer: {} triangles and {} clipped subtriangles exceed 2^28 "
                   "records",
                   total, extra);
        log::info("compute rasterizer: {} clipped subtriangles, extra records grown to {}", extra,
                  extraCapacity_);
    }
}

void ComputeRaster::bin(const pass::Context& context) {
    tiles_ = {(context.width + kTile - 1) / kTile, (context.height + kTile - 1) / kTile};
    const std::uint64_t tileCount = static_cast<std::uint64_t>(tiles_.x) * tiles_.y;
    const std::uint64_t batches =
        std::max<std::uint64_t>(1, (stats_.triangles + kBatch - 1) / kBatch);
    stats_.batches = static_cast<int>(batches);
    stats_.tiles = static_cast<int>(tileCount);
    const std::size_t binNeed = batches * tileCount * sizeof(GLuint);
    VEIL_CHECK(batches * tileCount < (std::uint64_t(1) << 32),
               "compute rasterizer: {} batches x {} tiles do not fit 32-bit offsets", batches,
               tileCount);
    VEIL_CHECK(binNeed <= maxBlockBytes_,
               "compute rasterizer: {} batches x {} tiles need {:.1f} MiB of bin offsets, more "
               "than this driver's shader storage block size ({:.1f} MiB); use "
               "render.oit_rasterizer = raster, a smaller image or fewer transparent triangles",
               batches, tileCount, double(binNeed) / 1048576.0, double(maxBlockBytes_) / 1048576.0);
    ensureBuffer(binOffsets_, binBytes_, binNeed);
    ensureBuffer(tileStarts_, tileStartBytes_, tileCount * sizeof(GLuint));
    if (listCapacity_ == 0) listCapacity_ = std::max<std::uint64_t>(4 * stats_.triangles, 65536);
    for (int attempt = 0; attempt < 2; ++attempt) {
        if (lists_.size() < listCapacity_ * sizeof(GLuint)) {
            lists_ = gpu::Buffer();
            lists_.setStorage(listCapacity_ * sizeof(GLuint), nullptr);
        }
        const GLuint zero = 0;
        glClearNamedBufferSubData(binOffsets_.id(), GL_R32UI, 0, binNeed, GL_RED_INTEGER,
                                  GL_UNSIGNED_INT, &zero);
        bindBuffers();
        const auto binPass = [&](gpu::ProgramHandle handle) {
            const gpu::Program& program = programs_.get(handle);
            program.use();
            program.set("triangleCount", static_cast<unsigned>(stats_.triangles))
                .set("tiles", tiles_)
                .set("listCapacity", static_cast<unsigned>(listCapacity_));
            glDispatchCompute(groups(std::max<std::uint64_t>(stats_.triangles, 1), 256), 1, 1);
            glMemoryBarrier(kStorageBarrier);
        };
        binPass(count_);
        const gpu::Program& scanB = programs_.get(scanBatches_);
        scanB.use();
        scanB.set("tileCount", static_cast<unsigned>(tileCount))
            .set("batches", static_cast<unsigned>(batches));
        glDispatchCompute(groups(tileCount, 256), 1, 1);
        glMemoryBarrier(kStorageBarrier);
        const gpu::Program& scanT = programs_.get(scanTiles_);
        scanT.use();
        scanT.set("tileCount", static_cast<unsigned>(tileCount));
        glDispatchCompute(1, 1, 1);
        glMemoryBarrier(kStorageBarrier);
        binPass(fill_);
        GLuint pairs = 0;
        glGetNamedBufferSubData(counters_.id(), sizeof(GLuint), sizeof(GLuint), &pairs);
        stats_.listEntries = pairs;
        if (pairs <= listCapacity_) return;
        // The lists need more entries than they hold: grow them, bin again.
        listCapacity_ =
            std::min<std::uint64_t>(nextPowerOfTwo(pairs), maxBlockBytes_ / sizeof(GLuint));
        VEIL_CHECK(pairs <= listCapacity_,
                   "compute rasterizer: {} tile-list entries exceed this driver's shader storage "
                   "block size ({:.1f} MiB)",
                   pairs, double(maxBlockBytes_) / 1048576.0);
        log::info("compute rasterizer: {} tile-list entries, lists grown to {}", pairs,
                  listCapacity_);
    }
}

void ComputeRaster::fine(oit::Technique& technique, const oit::Technique::GeometryHooks& hooks,
                         const pass::Context& context) {
    const glm::ivec4 region = oit::frameRegion(context);
    const glm::ivec2 first(region.x / kTile, region.y / kTile);
    const glm::ivec2 last((region.z - 1) / kTile, (region.w - 1) / kTile);
    for (int pass = 0; pass < technique.geometryPasses(); ++pass) {
        const gpu::Program& program = programs_.get(fine_[static_cast<std::size_t>(pass)]);
        program.use();
        if (context.prepareReceiver) context.prepareReceiver(program);
        technique.beginAccumulate(pass, context, program);
        if (hooks.beforeSurfaces) hooks.beforeSurfaces(context, pass);
        technique.prepareProgram(pass, program);
        technique.bindPerPixelEmit(pass, context);
        program.use();
        bindBuffers();
        context.depth->bind(VEIL_TEX_DEPTH);
        program.set("tiles", tiles_)
            .set("firstTile", first)
            .set("region", region)
            .set("batches", static_cast<unsigned>(stats_.batches));
        glDispatchCompute(static_cast<GLuint>(last.x - first.x + 1),
                          static_cast<GLuint>(last.y - first.y + 1), 1);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                        GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                        GL_TEXTURE_UPDATE_BARRIER_BIT);
        if (hooks.afterSurfaces) hooks.afterSurfaces(context, pass);
        technique.endAccumulate(pass);
        if (pass + 1 == technique.geometryPasses() && technique.repeatAccumulation()) pass = -1;
    }
}

std::vector<pass::Pass> ComputeRaster::passes(oit::Technique& technique,
                                              oit::Technique::GeometryHooks hooks) {
    std::vector<pass::Pass> out;
    pass::Pass setupPass{"transparent.setup",
                         {},
                         {"oit.raster.triangles"},
                         [this](const pass::Context& context) { setup(context); }};
    setupPass.scope = pass::Scope::Frame;
    out.push_back(std::move(setupPass));
    pass::Pass binPass{"transparent.bin",
                       {"oit.raster.triangles"},
                       {"oit.raster.tiles"},
                       [this](const pass::Context& context) { bin(context); }};
    binPass.scope = pass::Scope::Frame;
    out.push_back(std::move(binPass));
    std::vector<pass::Pass> own = technique.passes(hooks);
    for (pass::Pass& p : own) {
        if (p.name == "transparent") {
            p.reads.push_back("oit.raster.triangles");
            p.reads.push_back("oit.raster.tiles");
            p.execute = [this, &technique, hooks](const pass::Context& context) {
                fine(technique, hooks, context);
            };
        }
        out.push_back(std::move(p));
    }
    return out;
}

} // namespace veil::frame
