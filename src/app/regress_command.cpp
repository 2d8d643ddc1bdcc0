// `veil regress suite.json`: renders every case of an image regression suite in this process
// (one GL context, frame::Renderer as `veil render` uses it), compares each with its
// reference (a stored EXR, another technique, or the fog's CPU reference) by the case's
// metrics and tolerances, and writes per-case JSON, results.json, JUnit XML and an HTML
// report. Sharding (--shard I/N or the Slurm / Kubernetes array variables), --jobs (shards
// in child processes, merged) and --merge (shard folders into one report). docs/regression.md.
#include "app/commands.h"
#include "app/regress_report.h"
#include "app/regress_suite.h"

#include "base/atomic_file.h"
#include "base/error.h"
#include "base/text.h"
#include "frame/renderer.h"
#include "gpu/context.h"
#include "io/image_io.h"
#include "io/metrics.h"
#include "scene/scene.h"
#include "volume/cpu_reference.h"
#include "volume/density_grid.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <map>
#include <memory>

extern char** environ;

namespace veil::app {

namespace fs = std::filesystem;

namespace {

struct RegressArgs {
    std::string suite;
    std::string output = "regress-report";
    std::string shard;
    std::vector<std::string> merge;
    int jobs = 1;
    int device = -1;
    bool update = false;
};

struct Shard {
    int index = 0, count = 1;
    std::string label() const { return count > 1 ? fmt::format("{}/{}", index, count) : ""; }
};

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

Shard shardOf(const RegressArgs& args) {
    Shard s;
    auto env = [](const char* name) -> std::string {
        const char* v = std::getenv(name);
        return v ? v : "";
    };
    std::string from;
    if (!args.shard.empty()) {
        const auto slash = args.shard.find('/');
        VEIL_CHECK(slash != std::string::npos, "--shard '{}': use I/N, e.g. 0/3",
                   printable(args.shard, 100));
        s.index = parseInt(args.shard.substr(0, slash), "--shard " + args.shard);
        s.count = parseInt(args.shard.substr(slash + 1), "--shard " + args.shard);
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

ImageF cpuReference(const scene::Scene& s, const scene::Camera& camera, int w, int h, int steps) {
    std::vector<openvdb::FloatGrid::ConstPtr> grids;
    for (const auto& v : s.volumes)
        if (v.procedural != "homogeneous") grids.push_back(volume::loadVolume(v));
    const volume::CpuFogReference ref(s, grids);
    const ImageF fog = ref.render(camera, w, h, steps);
    // Nothing but fog in the frame: the GPU's pixel is the fog's radiance plus the background
    // seen through the fog's transmittance (fog.a).
    ImageF out(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                out.at(x, y, c) = fog.at(x, y, c) + fog.at(x, y, 3) * s.render.background[c];
    return out;
}

double heatScaleOf(const RegressCase& k) {
    std::map<std::string, double> t(k.metrics.begin(), k.metrics.end());
    if (t.count("maxabs")) return t["maxabs"];
    if (t.count("p99")) return t["p99"];
    if (t.count("rmse")) return 10.0 * t["rmse"];
    return 0.0; // the largest error
}

CaseResult runCase(const RegressCase& k, const gpu::ContextInfo& info, const fs::path& out,
                   bool update) {
    const auto t0 = std::chrono::steady_clock::now();
    CaseResult r;
    r.name = k.name;
    r.reference = k.referenceLabel();
    r.scene = k.scene.string();
    r.note = k.note;
    r.seeds = k.seeds;
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
            if (update) {
                std::string change = "created";
                if (fs::exists(k.referenceFile)) {
                    const ImageF old = io::readImage(k.referenceFile);
                    change =
                        old.width == w && old.height == h && old.channels >= 3
                            ? fmt::format("rmse {:.4g}, max-abs {:.4g} against the old one",
                                          metrics::rmse(image, old), metrics::maxAbs(image, old))
                            : fmt::format("was {}x{}", old.width, old.height);
                }
                io::writeImage(k.referenceFile, image);
                std::cout << "  updated " << k.referenceFile.string() << " (" << change << ")\n";
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
            refs.push_back(
                cpuReference(s, camera, w, h, k.cpuSteps ? k.cpuSteps : 2 * s.render.fogSteps));
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
        if (r.heatScale <= 0.0) r.heatScale = std::max(metrics::maxAbs(image, reference), 1e-6);
        fs::create_directories(out / "images");
        r.renderPng = "images/" + k.name + "-render.png";
        r.referencePng = "images/" + k.name + "-reference.png";
        r.diffPng = "images/" + k.name + "-diff.png";
        io::writeImage(out / r.renderPng, metrics::toneMapSrgb(image, s.render.exposure, op));
        io::writeImage(out / r.referencePng,
                       metrics::toneMapSrgb(reference, s.render.exposure, op));
        io::writeImage(out / r.diffPng, metrics::heatMap(image, reference, r.heatScale));
    } catch (const std::exception& e) {
        r.passed = false;
        r.error = e.what();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

void printCase(const CaseResult& r) {
    std::string m;
    for (const MetricResult& x : r.metrics)
        m += fmt::format("{}{} {:.4g}{}", m.empty() ? "" : ", ", x.name, x.value,
                         x.passed ? "" : fmt::format(" (tolerance {:.4g})", x.threshold));
    std::cout << fmt::format("{} {} ({} vs {}): {} ({:.1f} s)\n", r.passed ? "PASS" : "FAIL",
                             r.name, r.technique, r.reference, r.error.empty() ? m : r.error,
                             r.seconds);
    std::cout.flush();
}

// Joins shard folders into one report in suite order; a case no shard ran is a failure.
Report mergeReports(const Suite& suite, const std::vector<std::string>& dirs, const fs::path& out) {
    std::map<std::string, CaseResult> found;
    double seconds = 0.0;
    for (const std::string& d : dirs) {
        const Report part = readReport(d);
        seconds = std::max(seconds, part.seconds);
        for (const CaseResult& c : part.cases) {
            VEIL_CHECK(found.emplace(c.name, c).second,
                       "--merge: case '{}' is in two of the folders", c.name);
            for (const std::string* png : {&c.renderPng, &c.referencePng, &c.diffPng})
                if (!png->empty() && fs::absolute(d) != fs::absolute(out)) {
                    fs::create_directories(out / "images");
                    fs::copy_file(fs::path(d) / *png, out / *png,
                                  fs::copy_options::overwrite_existing);
                }
        }
    }
    Report r{suite.name, suite.file.string(), "", {}, seconds};
    for (const RegressCase& k : suite.cases) {
        if (auto it = found.find(k.name); it != found.end()) {
            r.cases.push_back(it->second);
            found.erase(it);
        } else {
            CaseResult missing;
            missing.name = k.name;
            missing.reference = k.referenceLabel();
            missing.scene = k.scene.string();
            missing.error = "no merged shard ran this case";
            r.cases.push_back(missing);
        }
    }
    VEIL_CHECK(found.empty(), "--merge: case '{}' is not in suite '{}'", found.begin()->first,
               suite.file.string());
    return r;
}

// --jobs N: N child processes `veil regress SUITE --shard i/N -o OUT/.shard-i`, merged.
std::vector<std::string> runChildren(const RegressArgs& args, const fs::path& out) {
    const std::string exe = fs::read_symlink("/proc/self/exe").string();
    std::vector<pid_t> pids;
    std::vector<std::string> dirs;
    for (int i = 0; i < args.jobs; ++i) {
        const std::string dir = (out / fmt::format(".shard-{}", i)).string();
        dirs.push_back(dir);
        std::vector<std::string> argv{
            exe, "regress", args.suite, "--shard", fmt::format("{}/{}", i, args.jobs), "-o", dir};
        if (args.update) argv.push_back("--update");
        if (args.device >= 0) argv.insert(argv.end(), {"--device", std::to_string(args.device)});
        std::vector<char*> cargv;
        for (std::string& a : argv)
            cargv.push_back(a.data());
        cargv.push_back(nullptr);
        pid_t pid = 0;
        const int rc = posix_spawn(&pid, exe.c_str(), nullptr, nullptr, cargv.data(), environ);
        VEIL_CHECK(rc == 0, "--jobs: cannot start '{}': {}", exe, std::strerror(rc));
        pids.push_back(pid);
    }
    for (std::size_t i = 0; i < pids.size(); ++i) {
        int status = 0;
        waitpid(pids[i], &status, 0);
        // Exit status 1 with a results file is a shard with failing cases: merged below.
        VEIL_CHECK(fs::exists(fs::path(dirs[i]) / "results.json"),
                   "--jobs: shard {} ended without results (status {})", i, status);
    }
    return dirs;
}

void runRegress(const RegressArgs& args) {
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path out = args.output;
    VEIL_CHECK(!(args.update && !args.merge.empty()), "--update cannot be combined with --merge");
    VEIL_CHECK(args.jobs == 1 || (args.shard.empty() && args.merge.empty()),
               "--jobs cannot be combined with --shard or --merge");
    const Suite suite = loadSuite(args.suite, args.update);
    VEIL_CHECK(!fs::exists(out) || fs::is_directory(out), "output '{}' is not a folder",
               out.string());
    fs::create_directories(out);
    checkOutputPath(out / "results.json", "report", {suite.file});

    Report report;
    if (!args.merge.empty()) {
        report = mergeReports(suite, args.merge, out);
    } else if (args.jobs > 1) {
        const std::vector<std::string> dirs = runChildren(args, out);
        report = mergeReports(suite, dirs, out);
        for (const std::string& d : dirs)
            fs::remove_all(d);
        report.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    } else {
        const Shard shard = shardOf(args);
        std::vector<const RegressCase*> mine;
        for (std::size_t i = 0; i < suite.cases.size(); ++i)
            if (static_cast<int>(i % static_cast<std::size_t>(shard.count)) == shard.index)
                mine.push_back(&suite.cases[i]);
        std::cout << fmt::format("{}: {} of {} cases{}\n", suite.file.string(), mine.size(),
                                 suite.cases.size(),
                                 shard.count > 1 ? " (shard " + shard.label() + ")" : "");
        report = {suite.name, suite.file.string(), shard.label(), {}, 0.0};
        if (!mine.empty()) {
            gpu::HeadlessContext context({args.device, false});
            for (const RegressCase* k : mine) {
                report.cases.push_back(runCase(*k, context.info(), out, args.update));
                printCase(report.cases.back());
            }
        }
        report.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    writeReport(out, report);
    const int failed = report.failed();
    std::cout << fmt::format("{} of {} cases passed ({:.1f} s); report {}\n",
                             report.cases.size() - failed, report.cases.size(), report.seconds,
                             (out / "index.html").string());
    if (failed) {
        std::vector<std::string> names;
        for (const CaseResult& c : report.cases)
            if (!c.passed) names.push_back(c.name);
        throw Error(fmt::format("{}: {} case(s) failed: {}; see {}", suite.file.string(), failed,
                                fmt::join(names, ", "), (out / "index.html").string()));
    }
}

} // namespace

void addRegressCommand(CLI::App& app) {
    auto args = std::make_shared<RegressArgs>();
    CLI::App* cmd = app.add_subcommand(
        "regress", "Run an image regression suite (docs/regression.md); exit 0 only if all pass");
    cmd->add_option("suite", args->suite, "Suite file (JSON)")->required();
    cmd->add_option("-o,--output", args->output, "Report folder (default: regress-report)");
    cmd->add_flag("--update", args->update,
                  "Write the renders as the new stored references (cases with a .exr reference)");
    cmd->add_option("--shard", args->shard,
                    "Run only cases i with i % N == I (I/N; default from SLURM_ARRAY_TASK_ID / "
                    "SLURM_ARRAY_TASK_COUNT or JOB_COMPLETION_INDEX / VEIL_SHARD_COUNT)");
    cmd->add_option("--jobs", args->jobs, "Run N shards in parallel child processes, merged")
        ->check(CLI::Range(1, 64));
    cmd->add_option("--merge", args->merge,
                    "Join the -o folders of shard runs into one report (no rendering)");
    cmd->add_option("--device", args->device, "EGL device index")->check(CLI::Range(0, 1023));
    cmd->callback([args] { runRegress(*args); });
}

} // namespace veil::app
