// Technique sweeps (sweep.h).
#include "compare/sweep.h"

#include "base/progress.h"
#include "oit/technique.h"
#include "shadows/technique.h"

#include <fmt/format.h>

#include <cmath>

namespace veil::compare {

std::string Sweep::name(std::size_t i) const {
    return kind == SweepKind::Shadows ? "shadows:" + frames[i].shadows : frames[i].oit;
}

std::string Sweep::label(std::size_t i) const {
    return kind == SweepKind::Shadows ? "shadows " + frames[i].shadows : frames[i].oit;
}

std::string Sweep::layer(std::size_t i) const {
    return kind == SweepKind::Shadows ? "shadows-" + frames[i].shadows : frames[i].oit;
}

namespace {

// Every technique of `registry` but the reference, unless `info` lacks it.
template <class Registry>
std::vector<std::string> available(const Registry& registry, const gpu::ContextInfo& info,
                                   const std::string& prefix,
                                   const std::function<void(const std::string&)>& skipped) {
    std::vector<std::string> names;
    for (const auto& t : registry.all()) {
        if (t.name == "reference") continue;
        if (t.isAvailable && !t.isAvailable(info)) {
            if (skipped)
                skipped(fmt::format("skipping {}{} (not available on {})", prefix, t.name,
                                    info.renderer));
            continue;
        }
        names.push_back(t.name);
    }
    return names;
}

} // namespace

std::string sweepTileNote(SweepKind kind, const std::string& technique, std::size_t k,
                          std::size_t n) {
    return fmt::format("tile {}/{}: {}{}", k, n, kind == SweepKind::Shadows ? "shadows " : "",
                       technique);
}

Sweep runSweep(SweepKind kind, const scene::Scene& scene, const std::string& oit,
               const gpu::ContextInfo& info, const FrameRender& render,
               const std::function<void(const std::string&)>& skipped) {
    Sweep sweep;
    sweep.kind = kind;
    const bool shadows = kind == SweepKind::Shadows;
    std::vector<std::string> names = {"reference"};
    for (std::string& n : shadows
                              ? available(shadows::Registry::instance(), info, "shadows ", skipped)
                              : available(oit::Registry::instance(), info, "", skipped))
        names.push_back(std::move(n));
    for (std::size_t i = 0; i < names.size(); ++i) {
        // The progress line names the tile: "tile 3/7: shadows moment".
        const ProgressNote note(sweepTileNote(kind, names[i], i + 1, names.size()));
        if (!shadows) {
            sweep.frames.push_back(render(scene, names[i], {}, {}));
        } else if (i == 0) {
            sweep.frames.push_back(render(scene, oit, "reference", {}));
        } else {
            // Every technique at the reference's map size (other properties at their defaults).
            const nlohmann::json size = {
                {"size", sweep.frames.front().shadowProperties.at("size")}};
            sweep.frames.push_back(render(scene, oit, names[i], size));
        }
    }
    for (const capture::RenderedFrame& f : sweep.frames)
        sweep.errors.push_back(compareLinear(f.hdr, sweep.frames.front().hdr));
    return sweep;
}

ImageF sweepContactSheet(const Sweep& sweep) {
    std::vector<ImageF> tiles;
    std::vector<std::vector<std::string>> labels;
    for (std::size_t i = 0; i < sweep.frames.size(); ++i) {
        tiles.push_back(sweep.frames[i].ldr);
        labels.push_back({sweep.label(i),
                          i == 0 ? std::string("RMSE 0 (exact)")
                                 : fmt::format("RMSE {:.4f}", sweep.errors[i].rmse),
                          fmt::format("GPU {:.1f} ms", sweep.frames[i].totalMs)});
    }
    return labelledContactSheet(tiles, labels);
}

io::ExrImage sweepExr(const Sweep& sweep, const capture::RenderMetadata& metadata, bool half) {
    const capture::RenderedFrame& main = sweep.frames.front();
    io::ExrImage exr = capture::makeExr(main.hdr, main.extras, metadata, half);
    std::string layers = "R,G,B,A,Z: " + sweep.layer(0);
    for (std::size_t i = 1; i < sweep.frames.size(); ++i) {
        capture::addRgbLayer(exr, sweep.layer(i), sweep.frames[i].hdr);
        layers += "; " + sweep.layer(i) + ".R,G,B: " + sweep.layer(i);
    }
    exr.strings.emplace_back("veil:layers", layers);
    return exr;
}

nlohmann::json sweepTechniques(const Sweep& sweep) {
    nlohmann::json techniques = nlohmann::json::array();
    const std::string against =
        sweep.kind == SweepKind::Shadows ? "shadows:reference" : "reference";
    for (std::size_t i = 0; i < sweep.frames.size(); ++i) {
        const capture::RenderedFrame& f = sweep.frames[i];
        techniques.push_back({{"oit", f.oit},
                              {"shadows", f.shadows},
                              {"gpu_bytes", f.gpuBytes},
                              {"passes", f.passes},
                              {"total_ms", f.totalMs},
                              {"oit_stats", f.oitStats},
                              {"oit_properties", f.oitProperties},
                              {"compare", errorJson(against, sweep.errors[i])}});
    }
    return techniques;
}

std::string sweepSummary(const Sweep& sweep) {
    std::string out;
    for (std::size_t i = 0; i < sweep.frames.size(); ++i)
        out += fmt::format("  {:<12} vs {}reference: {}\n", sweep.name(i),
                           sweep.kind == SweepKind::Shadows ? "shadows:" : "",
                           formatError(sweep.errors[i]));
    return out;
}

nlohmann::json errorJson(const std::string& against, const ImageError& e) {
    // JSON has no infinity: an identical image has "psnr_db": "inf".
    nlohmann::json j = {{"against", against}, {"rmse", e.rmse}, {"peak", e.peak}};
    if (std::isfinite(e.psnr))
        j["psnr_db"] = e.psnr;
    else
        j["psnr_db"] = std::isinf(e.psnr) ? "inf" : "undefined";
    j["metric"] = "linear HDR RGB; RMSE = sqrt(mean (a-b)^2); PSNR = 10 log10(peak^2 / MSE), "
                  "peak = max RGB of the reference";
    return j;
}

std::string formatError(const ImageError& e) {
    return fmt::format("RMSE {:.6g}, PSNR {} (peak {:.4g})", e.rmse,
                       std::isfinite(e.psnr) ? fmt::format("{:.2f} dB", e.psnr)
                                             : std::string(std::isinf(e.psnr) ? "inf" : "n/a"),
                       e.peak);
}

} // namespace veil::compare
