#include "regress/runner.h"

#include "base/error.h"
#include "base/text.h"
#include "compare/target.h"
#include "frame/renderer.h"
#include "io/image_io.h"
#include "io/metrics.h"
#include "regress/report_folder.h"
#include "scene/scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <set>

namespace veil::regress {

namespace fs = std::filesystem;

namespace {

int parseInt(const std::string& text, const std::string& what) {
    std::size_t used = 0;
    long v = -1;
    try {
        v = std::stol(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    VEIL_CHECK(used == text.size() && !text.empty() && v >= 0 && v < (1 << 20),
               "{}: '{}' is not a non-negative integer", what, printable(text, 100));
    return static_cast<int>(v);
}

std::vector<ImageF> renderSeeds(const scene::Scene& scene, const gpu::ContextInfo& info,
                                const std::string& oit, const nlohmann::json& properties, int n,
                                scene::Camera* camera, std::string* oitName,
                                std::uint32_t seedOffset = 0) {
    std::vector<ImageF> out;
    for (int i = 0; i < n; ++i) {
        scene::Scene s = scene;
        s.render.seed = scene.render.seed + seedOffset + static_cast<std::uint32_t>(i);
        frame::Renderer r(s, info, {0, 0, "", oit, properties});
        r.render();
        out.push_back(r.readHdr());
        if (camera) *camera = r.camera();
        if (oitName) *oitName = r.oitName();
    }
    return out;
}

double heatScaleOf(const RegressCase& k) {
    std::map<std::string, double> t(k.metrics.begin(), k.metrics.end());
    if (t.count("maxabs")) return t["maxabs"];
    if (t.count("p99")) return t["p99"];
    if (t.count("rmse")) return 10.0 * t["rmse"];
    return 0.0; // the largest error
}

} // namespace

std::string Shard::label() const { return count > 1 ? fmt::format("{}/{}", index, count) : ""; }

Shard shardFromArgumentOrEnvironment(const std::string& text) {
    Shard s;
    auto env = [](const char* name) -> std::string {
        const char* v = std::getenv(name);
        return v ? v : "";
    };
    std::string from;
    if (!text.empty()) {
        const auto slash = text.find('/');
        VEIL_CHECK(slash != std::string::npos, "--shard '{}': use I/N, e.g. 0/3",
                   printable(text, 100));
        s.index = parseInt(text.substr(0, slash), "--shard " + text);
        s.count = parseInt(text.substr(slash + 1), "--shard " + text);
        from = "--shard";
    } else if (!env("SLURM_ARRAY_TASK_ID").empty()) {
        // Array ids need not start at 0 (--array=1-3): count from SLURM_ARRAY_TASK_MIN.
        const int id = parseInt(env("SLURM_ARRAY_TASK_ID"), "SLURM_ARRAY_TASK_ID");
        const int lo = env("SLURM_ARRAY_TASK_MIN").empty()
                           ? 0
                           : parseInt(env("SLURM_ARRAY_TASK_MIN"), "SLURM_ARRAY_TASK_MIN");
        VEIL_CHECK(!env("SLURM_ARRAY_TASK_COUNT").empty(),
                   "SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not");
        s.index = id - lo;
        s.count = parseInt(env("SLURM_ARRAY_TASK_COUNT"), "SLURM_ARRAY_TASK_COUNT");
        from = "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT";
    } else if (!env("JOB_COMPLETION_INDEX").empty()) {
        s.index = parseInt(env("JOB_COMPLETION_INDEX"), "JOB_COMPLETION_INDEX");
        VEIL_CHECK(!env("VEIL_SHARD_COUNT").empty(),
                   "JOB_COMPLETION_INDEX is set: set VEIL_SHARD_COUNT to the job's completions");
        s.count = parseInt(env("VEIL_SHARD_COUNT"), "VEIL_SHARD_COUNT");
        from = "JOB_COMPLETION_INDEX/VEIL_SHARD_COUNT";
    }
    if (!from.empty())
        VEIL_CHECK(s.count >= 1 && s.index >= 0 && s.index < s.count,
                   "{}: shard {} of {} is not in 0..{}", from, s.index, s.count, s.count - 1);
    return s;
}

std::vector<const RegressCase*> shardCases(const Suite& suite, const Shard& shard) {
    std::vector<const RegressCase*> mine;
    for (std::size_t i = 0; i < suite.cases.size(); ++i)
        if (static_cast<int>(i % static_cast<std::size_t>(shard.count)) == shard.index)
            mine.push_back(&suite.cases[i]);
    return mine;
}

CaseResult runCase(const RegressCase& k, const gpu::ContextInfo& info, const RunOptions& options) {
    const fs::path& out = options.output;
    const auto t0 = std::chrono::steady_clock::now();
    CaseResult r;
    r.name = k.name;
    r.reference = k.referenceLabel();
    r.scene = k.scene.string();
    r.note = k.note;
    r.overrides = k.overrides;
    r.seeds = k.seeds;
    // Every image of the case records what made it (with io::provenanceAttributes()).
    const std::vector<std::pair<std::string, std::string>> header{
        {"veil:case", k.name},
        {"veil:scene", k.scene.string()},
        {"veil:overrides", nlohmann::json(k.overrides).dump()}};
    try {
        const scene::Scene s = scene::loadScene(k.scene, k.overrides);
        scene::Camera camera;
        const std::vector<ImageF> renders =
            renderSeeds(s, info, "", nlohmann::json(), k.seeds, &camera, &r.technique);
        const int w = renders.front().width, h = renders.front().height;
        r.width = w;
        r.height = h;
        const metrics::PixelStats stats = metrics::pixelStats(renders);
        const ImageF& image = k.seeds > 1 ? stats.mean : renders.front();

        std::vector<ImageF> refs;
        switch (k.reference) {
        case ReferenceKind::File: {
            if (options.update) {
                std::string change = "created";
                if (fs::exists(k.referenceFile)) {
                    const ImageF old = io::readImage(k.referenceFile);
                    change =
                        old.width == w && old.height == h && old.channels >= 3
                            ? fmt::format("rmse {:.4g}, max-abs {:.4g} against the old one",
                                          metrics::rmse(image, old), metrics::maxAbs(image, old))
                            : fmt::format("was {}x{}", old.width, old.height);
                }
                io::writeImage(k.referenceFile, image, true, header);
                r.updated = k.referenceFile.string() + " (" + change + ")";
            }
            ImageF ref = io::readImage(k.referenceFile);
            VEIL_CHECK(ref.channels >= 3, "reference '{}' has {} channel(s): RGB needed",
                       k.referenceFile.string(), ref.channels);
            VEIL_CHECK(ref.width == w && ref.height == h,
                       "reference '{}' is {}x{} but the case renders {}x{}",
                       k.referenceFile.string(), ref.width, ref.height, w, h);
            refs.push_back(std::move(ref));
            break;
        }
        case ReferenceKind::Technique: {
            // Several reference renders take seeds of their own (seed + 1000 + i), independent
            // of the case's.
            std::vector<std::string> all = k.overrides;
            all.insert(all.end(), k.referenceOverrides.begin(), k.referenceOverrides.end());
            const scene::Scene rs =
                k.referenceOverrides.empty() ? s : scene::loadScene(k.scene, all);
            refs = renderSeeds(rs, info, k.referenceTechnique, k.referenceProperties,
                               k.referenceSeeds, nullptr, nullptr, k.referenceSeeds > 1 ? 1000 : 0);
            break;
        }
        case ReferenceKind::Cpu:
            refs.push_back(compare::cpuFogOverBackground(
                s, camera, w, h, k.cpuSteps ? k.cpuSteps : 2 * s.render.fogSteps));
            break;
        }
        const metrics::PixelStats refStats = metrics::pixelStats(refs);
        const ImageF& reference = refs.size() > 1 ? refStats.mean : refs.front();

        const metrics::ToneMap op =
            s.render.tonemap == "aces" ? metrics::ToneMap::Aces : metrics::ToneMap::Clamp;
        r.passed = true;
        for (const auto& [name, threshold] : k.metrics) {
            MetricResult m{name, 0.0, threshold, false};
            if (name == "rejected")
                m.value = metrics::welchPixelTest(stats, refStats, k.test).fraction;
            else
                m.value = metrics::compute(name, image, reference, s.render.exposure, op);
            m.passed = name == "rejected" ? !(m.value > threshold)
                                          : metrics::withinThreshold(name, m.value, threshold);
            r.passed = r.passed && m.passed;
            r.metrics.push_back(m);
        }
        r.heatScale = heatScaleOf(k);
        if (r.heatScale <= 0.0) { // NaN pixels (maxabs NaN): white, at a scale of 1
            const double largest = metrics::maxAbs(image, reference);
            r.heatScale = std::isfinite(largest) ? std::max(largest, 1e-6) : 1.0;
        }
        reportSubfolder(out, "images");
        r.renderPng = "images/" + k.name + "-render.png";
        r.referencePng = "images/" + k.name + "-reference.png";
        r.diffPng = "images/" + k.name + "-diff.png";
        io::writeImage(out / r.renderPng, metrics::toneMapSrgb(image, s.render.exposure, op), true,
                       header);
        io::writeImage(out / r.referencePng, metrics::toneMapSrgb(reference, s.render.exposure, op),
                       true, header);
        io::writeImage(out / r.diffPng, metrics::heatMap(image, reference, r.heatScale), true,
                       header);
    } catch (const std::exception& e) {
        r.passed = false;
        r.error = e.what();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

Report runSuite(const Suite& suite, const RunOptions& options, const Shard& shard) {
    const auto t0 = std::chrono::steady_clock::now();
    Report report{suite.name, suite.file.string(), shard.label(),   {},
                  0.0,        suite.sha256,        options.version, ""};
    std::unique_ptr<gpu::HeadlessContext> context; // made for the first case that renders
    for (const RegressCase* k : shardCases(suite, shard)) {
        std::optional<CaseResult> done;
        if (options.resume)
            done = readCaseFile(options.output, k->name, suite.sha256, options.version);
        if (!done) {
            if (!context) {
                context = std::make_unique<gpu::HeadlessContext>(
                    gpu::HeadlessOptions{options.device, false});
                if (options.onDevice) options.onDevice(context->info());
            }
            markRunning(options.output, k->name);
            done = runCase(*k, context->info(), options);
            writeCaseFile(options.output, *done, suite.sha256, options.version);
            clearRunning(options.output);
        }
        report.cases.push_back(*done);
        if (options.onCase) options.onCase(report.cases.back());
    }
    if (context)
        report.device = fmt::format("EGL device {}: {} ({})", context->info().deviceIndex,
                                    context->info().renderer, context->info().deviceChoice);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return report;
}

namespace {

// The images of one case to copy in a merge: from inside the shard folder to inside `out`.
struct ImageCopy {
    fs::path from, to;
};

bool sameFolder(const fs::path& a, const fs::path& b) {
    std::error_code e1, e2;
    const fs::path ca = fs::weakly_canonical(a, e1), cb = fs::weakly_canonical(b, e2);
    if (e1 || e2) return false;
    return ca == cb || (fs::exists(a) && fs::exists(b) && fs::equivalent(a, b, e1));
}

} // namespace

Report mergeReports(const Suite& suite, const std::vector<fs::path>& dirs, const fs::path& out,
                    const std::string& version) {
    std::map<std::string, CaseResult> found;
    std::map<std::string, fs::path> from; // case -> the results.json it came from
    std::vector<ImageCopy> copies;
    std::set<std::string> names;
    for (const RegressCase& k : suite.cases)
        names.insert(k.name);
    double seconds = 0.0;
    // Everything is read and checked first; nothing is written to `out` on a refusal.
    for (const fs::path& d : dirs) {
        const std::string file = (d / "results.json").string();
        VEIL_CHECK(!sameFolder(d, out),
                   "--merge: the output folder '{}' is one of the shard folders ('{}'): choose "
                   "another -o",
                   out.string(), d.string());
        const Report part = readReport(d);
        VEIL_CHECK(part.suiteSha256 == suite.sha256,
                   "--merge: '{}' is a run of another suite file ('{}', sha256 {}) than '{}' "
                   "(sha256 {}): refusing to merge it",
                   file, printable(part.suiteFile, 200),
                   part.suiteSha256.empty() ? "not recorded" : part.suiteSha256.substr(0, 16),
                   suite.file.string(), suite.sha256.substr(0, 16));
        VEIL_CHECK(version.empty() || part.veilVersion == version,
                   "--merge: '{}' was made by another veil binary ('{}') than this one ('{}'): "
                   "refusing to merge it",
                   file,
                   printable(part.veilVersion.empty() ? "not recorded" : part.veilVersion, 200),
                   version);
        seconds = std::max(seconds, part.seconds);
        for (CaseResult c : part.cases) {
            checkCaseName(c.name, "--merge: '" + file + "'");
            VEIL_CHECK(names.count(c.name), "--merge: '{}': case '{}' is not in suite '{}'", file,
                       c.name, suite.file.string());
            if (auto [it, fresh] = from.emplace(c.name, d / "results.json"); !fresh)
                throw Error(fmt::format("--merge: case '{}' is in two of the folders: '{}' and "
                                        "'{}'",
                                        c.name, it->second.string(), file));
            const std::pair<std::string*, const char*> images[] = {
                {&c.renderPng, "render_png"},
                {&c.referencePng, "reference_png"},
                {&c.diffPng, "diff_png"}};
            for (const auto& [png, key] : images) {
                if (png->empty()) continue;
                const std::string what =
                    fmt::format("--merge: '{}': case '{}': {}", file, c.name, key);
                const fs::path src = safePathInside(d, *png, what);
                VEIL_CHECK(fs::is_regular_file(src), "{} '{}' does not exist in '{}'", what,
                           printable(*png, 200), d.string());
                // The copy's name comes from the (checked) case name, not from the shard.
                const std::string suffix = std::string(key) == "render_png"      ? "-render.png"
                                           : std::string(key) == "reference_png" ? "-reference.png"
                                                                                 : "-diff.png";
                *png = "images/" + c.name + suffix;
                copies.push_back({src, safePathInside(out, *png, "--merge: output")});
            }
            found.emplace(c.name, c);
        }
    }
    Report r{suite.name, suite.file.string(), "", {}, seconds, suite.sha256, version, ""};
    for (const RegressCase& k : suite.cases) {
        if (auto it = found.find(k.name); it != found.end()) {
            r.cases.push_back(it->second);
        } else {
            CaseResult missing;
            missing.name = k.name;
            missing.reference = k.referenceLabel();
            missing.scene = k.scene.string();
            missing.overrides = k.overrides;
            missing.error = "no merged shard ran this case";
            r.cases.push_back(missing);
        }
    }
    // Now the writes: the previous report goes first, so `out` never shows a mix.
    clearReport(out);
    if (!copies.empty()) reportSubfolder(out, "images");
    for (const ImageCopy& c : copies) {
        std::error_code ec;
        fs::copy_file(c.from, c.to, fs::copy_options::overwrite_existing, ec);
        VEIL_CHECK(!ec, "--merge: cannot copy '{}' to '{}': {}", c.from.string(), c.to.string(),
                   ec.message());
    }
    return r;
}

} // namespace veil::regress
