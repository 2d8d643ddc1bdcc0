// The progressive refinement of frame::Renderer (Renderer::beginRefinement(), refineStep()):
// its scheduler (Refiner) and state (Refinement).
//
// Progressive refinement (the viewer on slow drivers, docs/viewer.md "Slow drivers"): the
// same frame as render(), bit for bit, split over several calls so that none takes much
// longer than the frame's per-pixel passes over one tile. beginRefinement() runs the
// per-frame passes (shadow maps, AO, opaque) once; while the fog's light transmittance
// volumes are not valid each refineStep() computes kRefineLightSlabTexels z slices of one
// of them (the fog pass's prepare step); then each refineStep() runs the per-pixel passes
// (fog march, transparent, resolve, tonemap) for the next screen tile plus refineMarginPx()
// around it (the OIT technique's: what its resolve reads around a pixel; scissor box of the
// state tracker, region of the compute dispatches; the fog marches the texels its
// upsampling reads) and keeps the tile; it returns true once every tile is done, and the
// frame targets then hold the frame. The tiles: the frame's tilePx x tilePx grid in rows
// from the top left; a step given maxTilePx > 0 first halves the next tile (in each side
// over maxTilePx, quadrants in the same order) until it fits, so the caller can shrink the
// work of a step when a step took too long (the viewer's time budget,
// viewer/session/view_session.h). Until then hdrTexture()/ldrTexture() hold partial work: show the
// last complete image. The camera and scene must not change between the calls (begin again instead:
// that cancels). The passes run by scope (pass::Scope): Lights and Frame once, the prepare steps of
// the Pixels passes (pass::Pass::prepareStep) one per call, then the Pixels passes per tile over
// pass::Context::region (hdr outside it keeps earlier tiles' work, and each tile starts from the
// opaque image). When the shadow maps are to be drawn (not kept by reuse) and the shadow technique
// has passes in bands of rows (pass::Pass::executeRows), the first steps draw them:
// beginRefinement() only begins the frame, then each refineStep() runs one band of
// about kRefineShadowBandTexels texels per map layer (rows = that / map size) of a banded
// pass, or one unbanded pass whole; then one step runs the other per-frame passes (AO,
// opaque); then the light slabs and the tiles follow.
#pragma once

#include "gpu/objects.h"

#include <glm/glm.hpp>

#include <vector>

namespace veil::frame {

class Renderer;

struct Refinement {
    bool active = false;
    int tilePx = 0, columns = 0, tiles = 0; // the grid: tiles = columns x rows
    int done = 0;                           // tile steps run (a split tile counts its parts)
    long long pixels = 0, pixelsDone = 0;   // of the frame, and in the tiles done
    glm::ivec4 lastTile{0};                 // pixels kept by the last tile step, x0 y0 x1 y1
    glm::ivec4 lastRegion{0}; // pixels of the last tile's per-pixel passes (tile + margin)
    // What the last refineStep() ran.
    enum class Step { None, ShadowBand, PerFrame, LightSlab, Tile } lastStep = Step::None;
    int lightSlabs = 0;  // light transmittance slabs computed by refineStep()
    int shadowSteps = 0; // shadow bands (and unbanded shadow passes) run by refineStep()
    // The shadow passes in progress: the next pass (-1: none left) and its next row; the
    // per-frame passes after them still to run.
    int shadowPass = -1, shadowRow = 0;
    bool perFramePending = false;
    // The tiles left, the next one last.
    std::vector<glm::ivec4> pending;
};

// Runs a renderer's passes in refinement steps (what Renderer::beginRefinement() and
// refineStep() do, above).
class Refiner {
public:
    static constexpr int kShadowBandTexels = 131072; // 64 rows of a 2048^2 map
    explicit Refiner(Renderer& renderer) : r_(renderer) {}
    void begin(int tilePx);
    bool step(int maxTilePx);
    void cancel() { state_.active = false; }
    const Refinement& state() const { return state_; }
    // The opaque image of the whole frame while tiles run (pass::Context::opaqueColor).
    const gpu::Texture& opaqueImage() const { return opaqueHdr_; }

private:
    void runPerFramePasses(bool lights); // (Lights and) Frame passes, then keep opaque
    void shadowStep();                   // one band or unbanded pass of the shadow maps

    Renderer& r_;
    Refinement state_;
    gpu::Texture opaqueHdr_{gpu::NoCreate}, refinedHdr_{gpu::NoCreate}, refinedLdr_{gpu::NoCreate};
};

} // namespace veil::frame
