// Every technique of one kind rendered on one frame and compared with the reference technique
// (`veil render --oit all`: the OIT techniques; `--shadows all`: the shadow techniques with the
// OIT technique fixed, each at the reference's shadow map size, its other properties at their
// defaults), and what is made of it: a labelled contact sheet, an EXR with a layer per
// technique, the report's entries and the printed summary.
#pragma once

#include "capture/exr_output.h"
#include "capture/frame_capture.h"
#include "compare/compare.h"
#include "gpu/context.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace veil::compare {

// Renders the frame of `scene` with OIT technique `oit` and shadow technique `shadows` (empty:
// the caller's choice) with `shadowProperties` (null: the scene's); the caller keeps the
// context, the size, the camera and the progress display.
using FrameRender = std::function<capture::RenderedFrame(
    const scene::Scene& scene, const std::string& oit, const std::string& shadows,
    const nlohmann::json& shadowProperties)>;

enum class SweepKind { Oit, Shadows };

struct Sweep {
    SweepKind kind = SweepKind::Oit;
    std::vector<capture::RenderedFrame> frames; // the reference technique's first
    std::vector<ImageError> errors;             // frames[i] against frames[0]

    std::string name(std::size_t i) const;  // "wboit", or "shadows:pcf"
    std::string label(std::size_t i) const; // a tile's title: "wboit", or "shadows pcf"
    std::string layer(std::size_t i) const; // an EXR layer: "wboit", or "shadows-pcf"
};

// The reference technique of `kind` first, then every other one `info` has (`skipped` gets
// "skipping NAME (not available on RENDERER)" for the others), with OIT technique `oit` for
// a shadows sweep. A failing technique throws before anything is written.
Sweep runSweep(SweepKind kind, const scene::Scene& scene, const std::string& oit,
               const gpu::ContextInfo& info, const FrameRender& render,
               const std::function<void(const std::string&)>& skipped);

// The progress note while tile k (from 1) of n renders: "tile 2/7: wboit", or "tile 3/7:
// shadows moment" (base/progress.h: shown after the ticker's label).
std::string sweepTileNote(SweepKind kind, const std::string& technique, std::size_t k,
                          std::size_t n);

// The frames' tone-mapped images in rows, each labelled with its technique, its RMSE against
// the reference and its GPU time (compare::labelledContactSheet).
ImageF sweepContactSheet(const Sweep& sweep);

// The reference frame as R, G, B, A, Z with `metadata` (capture::makeExr), every other
// technique as a layer <layer>.R/.G/.B of the same size, listed in the veil:layers header.
io::ExrImage sweepExr(const Sweep& sweep, const capture::RenderMetadata& metadata, bool half);

// The report's "techniques": per frame oit, shadows, gpu_bytes, passes, total_ms, oit_stats,
// oit_properties and compare (errorJson against the reference).
nlohmann::json sweepTechniques(const Sweep& sweep);

// "  NAME vs reference: RMSE ..., PSNR ... (peak ...)" per frame, each line ending in '\n'.
std::string sweepSummary(const Sweep& sweep);

// An error as JSON for a report: against, rmse, peak, psnr_db ("inf" for an identical image:
// JSON has no infinity) and the metric's definition.
nlohmann::json errorJson(const std::string& against, const ImageError& e);

// "RMSE 0.0123, PSNR 38.21 dB (peak 1.2)".
std::string formatError(const ImageError& e);

} // namespace veil::compare
