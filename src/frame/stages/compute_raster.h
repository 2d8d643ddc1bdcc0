// The transparent pass rasterized and shaded in compute (render.oit_rasterizer = "compute";
// docs/oit.md "Compute rasterizer"), after [Laine11]: the same triangles, coverage rule,
// interpolation and depth test as the hardware path, each covered pixel handed to the
// technique's own oitEmit() (its emit file with OIT_COMPUTE: targets as images), so no
// technique has a second copy of its math. Stages, each a pass of its own (and a GPU timer):
//   transparent.setup  scope Frame: per object of ObjectSet::Transparent (drawing order), the
//                      vertex transform of frame/mesh.vert, near-plane and guard-band
//                      clipping, snapping to 8 sub-pixel bits, pixel bounds
//                      (shaders/frame/compute_raster/setup.comp)
//   transparent.bin    scope Frame: per (batch of 256 input triangles, 16 x 16 tile) counts,
//                      two scans, per-tile lists (bin.comp, scan_batches.comp, scan_tiles.comp)
//   transparent        scope Pixels: fine rasterization, one workgroup per tile, the tile's
//                      lists back in submission order (fine.comp), between the technique's
//                      beginAccumulate() and endAccumulate() like the hardware pass (with the
//                      same fog hooks)
//   resolve            the technique's own
// Techniques opt in (Technique::computeRaster()): blend (exact in-order blending: a pixel's
// fragments come in submission order), wboit (order-independent sums), reference (nodes in
// the same per-pixel lists). Others are refused with an error naming them.
// Storage: 80 + 108 bytes per input triangle (and per further subtriangle of clipped ones), 4 bytes
// per (batch, tile) pair, 4 bytes per (tile, triangle) list entry; the extra records and the
// lists grow by powers of two when a frame needs more (read back after their stage).
#pragma once

#include "oit/technique.h"

#include <cstdint>
#include <string>
#include <vector>

namespace veil::frame {

class ComputeRaster {
public:
    static constexpr int kTile = 16;
    static constexpr int kBatch = 256;
    static constexpr std::size_t kTriangleBytes = 80;   // a record's screen-space part
    static constexpr std::size_t kAttributeBytes = 108; // its vertices' 27 attributes

    // Throws veil::Error naming `technique` when it has no compute-raster emission. `surface`:
    // the frame's "veil:raster_setup", "veil:raster_surface", "veil:raster_layout" and
    // "veil:light_visibility"; `surfaceDefines`: more defines of the fine stage's shading
    // (the shadow technique's receiver defines, shadows::Technique::receivers, and
    // kSurfaceScatteredLightDefine where the frame has a scattered-light cache).
    ComputeRaster(gpu::ProgramManager& programs, const oit::Technique& technique,
                  const gpu::IncludeAliases& surface,
                  const std::vector<std::string>& surfaceDefines = {});
    // The techniques that run on the compute rasterizer, for messages.
    static std::string supportedNames();

    // The technique's passes with its transparent pass rasterized here (see above).
    std::vector<pass::Pass> passes(oit::Technique& technique, oit::Technique::GeometryHooks hooks);

    struct Stats {
        std::uint64_t triangles = 0, extraRecords = 0, listEntries = 0;
        int batches = 0, tiles = 0;
    };
    const Stats& stats() const { return stats_; }

private:
    void setup(const pass::Context& context);
    void bin(const pass::Context& context);
    void fine(oit::Technique& technique, const oit::Technique::GeometryHooks& hooks,
              const pass::Context& context);
    void bindBuffers() const;

    gpu::ProgramManager& programs_;
    gpu::ProgramHandle setup_, count_, fill_, scanBatches_, scanTiles_;
    std::vector<gpu::ProgramHandle> fine_; // per geometry pass
    gpu::Buffer triangles_{gpu::NoCreate}, attributes_{gpu::NoCreate}, counters_{gpu::NoCreate},
        tileStarts_{gpu::NoCreate}, binOffsets_{gpu::NoCreate}, lists_{gpu::NoCreate};
    std::uint64_t triangleCapacity_ = 0, extraCapacity_ = 1024, listCapacity_ = 0;
    std::uint64_t maxBlockBytes_ = 0; // GL_MAX_SHADER_STORAGE_BLOCK_SIZE
    std::size_t countersBytes_ = 0, binBytes_ = 0, tileStartBytes_ = 0;
    glm::ivec2 tiles_{0};
    Stats stats_;
};

} // namespace veil::frame
