// `veil render --frames`: a file sequence under a fixed camera equals plain renders of its
// files, bit for bit; under a turntable, each frame of the range equals `--frame N` alone;
// SIGTERM mid-range leaves complete frames only and --resume renders the rest once; a missing
// or corrupt middle frame is one line naming the file.
#include "io/image_io.h"
#include "support/test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <thread>

namespace veil::test {

namespace fs = std::filesystem;

namespace {

fs::path dir(const std::string& name) { return freshOutputDir("sequence_cli", name); }

fs::path fireFrame(int n) {
    return dataDir() / "vdb-embergen-fire-seq" / fmt::format("embergen_fire_a_{}.vdb", n);
}

// 64x64, few steps, no shadow map: cheap on llvmpipe.
nlohmann::json fireScene(const std::string& volumePath, bool turntable) {
    nlohmann::json camera = {{"position", {0, -62, -98}},
                             {"target", {0, 0, -112}},
                             {"up", {0, 0, 1}},
                             {"fov_y", 40},
                             {"near", 1},
                             {"far", 400}};
    if (turntable) camera["turntable"] = {{"frames", 4}, {"start_frame", 1}};
    nlohmann::json volume = {
        {"name", "fire"}, {"path", volumePath}, {"grid", "flames"}, {"density_scale", 6.0}};
    if (volumePath.find('#') != std::string::npos) volume["after"] = "loop";
    return {{"render", {{"width", 64}, {"height", 64}, {"fog_steps", 48}, {"shadows", "opaque"}}},
            {"cameras", {camera}},
            {"lights",
             {{{"type", "directional"}, {"direction", {-0.4, 0.5, -0.75}}, {"shadows", false}}}},
            {"volumes", {volume}}};
}

fs::path writeScene(const fs::path& path, const nlohmann::json& doc) {
    std::ofstream(path) << doc.dump(2);
    return path;
}

std::string pattern() {
    return (dataDir() / "vdb-embergen-fire-seq" / "embergen_fire_a_#.vdb").string();
}

bool samePixels(const ImageF& a, const ImageF& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

CommandResult veil(const std::string& args) { return runCommand(veilExe() + " " + args); }

} // namespace

TEST(SequenceCliTest, FixedCameraFramesEqualPlainRendersOfTheFiles) {
    const fs::path d = dir("fixed");
    const fs::path scene = writeScene(d / "seq.json", fireScene(pattern(), false));
    const CommandResult r =
        veil("render " + shellQuote(scene) + " --frames 1-3 -o " + shellQuote(d / "seq.####.exr") +
             " --report " + shellQuote(d / "report.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::vector<ImageF> frames;
    for (int f = 1; f <= 3; ++f) {
        const fs::path still =
            writeScene(d / fmt::format("still{}.json", f), fireScene(fireFrame(f).string(), false));
        const fs::path out = d / fmt::format("still{}.exr", f);
        const CommandResult s = veil("render " + shellQuote(still) + " -o " + shellQuote(out));
        ASSERT_EQ(s.exitCode, 0) << s.output;
        frames.push_back(io::readImage(d / fmt::format("seq.{:04d}.exr", f)));
        const ImageF single = io::readImage(out);
        EXPECT_TRUE(samePixels(frames.back(), single))
            << "frame " << f << ": " << writeFailureImages("sequence_fixed", frames.back(), single);
    }
    // The fire moves: consecutive frames differ.
    EXPECT_FALSE(samePixels(frames[0], frames[1]));
    EXPECT_FALSE(samePixels(frames[1], frames[2]));
    std::ifstream in(d / "report.json");
    const nlohmann::json report = nlohmann::json::parse(in);
    ASSERT_EQ(report["frames"].size(), 3u);
    EXPECT_EQ(report["frames"][1]["frame"], 2);
    EXPECT_GT(report["frames"][1]["active_voxels"].get<long long>(), 0);
    EXPECT_TRUE(report["frames"][1].contains("read_ms"));
}

TEST(SequenceCliTest, TurntableFramesEqualSingleFrameRenders) {
    const fs::path d = dir("turntable");
    const fs::path scene = writeScene(d / "seq.json", fireScene(pattern(), true));
    const CommandResult r =
        veil("render " + shellQuote(scene) + " --frames 2-3 -o " + shellQuote(d / "t.%04d.png"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("wrote 2 frames"), std::string::npos) << r.output;
    const CommandResult s =
        veil("render " + shellQuote(scene) + " --frame 3 -o " + shellQuote(d / "single.png"));
    ASSERT_EQ(s.exitCode, 0) << s.output;
    const ImageF a = io::readImage(d / "t.0003.png"), b = io::readImage(d / "single.png");
    EXPECT_TRUE(samePixels(a, b)) << writeFailureImages("sequence_turntable", a, b);
    EXPECT_FALSE(samePixels(io::readImage(d / "t.0002.png"), a)); // camera and fire moved
}

TEST(SequenceCliTest, ResumeAfterSigtermRendersEveryFrameOnce) {
    const fs::path d = dir("resume");
    const fs::path scene = writeScene(d / "seq.json", fireScene(pattern(), true));
    const std::string out = (d / "r.####.png").string();
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        const std::string log = (d / "first.log").string();
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(fd, 1);
        ::dup2(fd, 2);
        ::execl(veilExe().c_str(), veilExe().c_str(), "render", scene.c_str(), "--frames", "1-12",
                "-o", out.c_str(), nullptr);
        ::_exit(127);
    }
    // SIGTERM once two frames are written.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!fs::exists(d / "r.0002.png") && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 1);
    std::ifstream logIn(d / "first.log");
    const std::string log((std::istreambuf_iterator<char>(logIn)), {});
    EXPECT_NE(log.find("interrupted by signal 15"), std::string::npos) << log;

    // Only complete numbered frames are there (no temporaries), each a whole image.
    std::map<std::string, fs::file_time_type> first;
    const std::regex numbered(R"(r\.\d{4}\.png)");
    for (const auto& e : fs::directory_iterator(d)) {
        const std::string name = e.path().filename().string();
        if (name == "seq.json" || name == "first.log") continue;
        ASSERT_TRUE(std::regex_match(name, numbered)) << "left behind: " << name;
        const ImageF img = io::readImage(e.path());
        EXPECT_EQ(img.width, 64);
        first[name] = fs::last_write_time(e.path());
    }
    ASSERT_GE(first.size(), 2u);
    ASSERT_LT(first.size(), 12u) << "the range ended before the signal";

    const CommandResult r =
        veil("render " + shellQuote(scene) + " --frames 1-12 -o " + shellQuote(out) +
             " --resume --report " + shellQuote(d / "resume.json"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(d / "resume.json");
    const nlohmann::json report = nlohmann::json::parse(in);
    ASSERT_EQ(report["frames"].size(), 12u);
    std::size_t skipped = 0;
    for (const auto& f : report["frames"]) {
        const std::string name = fmt::format("r.{:04d}.png", f["frame"].get<int>());
        const bool wasThere = first.count(name) > 0;
        EXPECT_EQ(f.contains("skipped"), wasThere) << name; // each frame rendered once
        skipped += wasThere;
        EXPECT_TRUE(fs::exists(d / name));
    }
    EXPECT_EQ(skipped, first.size());
    for (const auto& [name, time] : first)
        EXPECT_EQ(fs::last_write_time(d / name), time) << name << " was written again";
}

TEST(SequenceCliTest, MissingOrCorruptMiddleFrameIsOneLineNamingTheFile) {
    const fs::path d = dir("broken");
    for (int f : {1, 2, 4})
        fs::copy_file(fireFrame(f), d / fmt::format("f_{}.vdb", f));
    nlohmann::json doc = fireScene((d / "f_#.vdb").string(), false);
    const fs::path scene = writeScene(d / "missing.json", doc);
    CommandResult r =
        veil("render " + shellQuote(scene) + " --frames 1-4 -o " + shellQuote(d / "m.####.png"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("frame 3 (scene frame 3): file '" + (d / "f_3.vdb").string() +
                            "' is missing"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(d / "m.0001.png")); // checked before anything renders

    // A truncated file: frame 1 is written, frame 2 names the file.
    fs::copy_file(fireFrame(3), d / "f_3.vdb");
    fs::resize_file(d / "f_2.vdb", fs::file_size(d / "f_2.vdb") / 2);
    r = veil("render " + shellQuote(scene) + " --frames 1-3 -o " + shellQuote(d / "c.####.png"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find((d / "f_2.vdb").string()), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_TRUE(fs::exists(d / "c.0001.png"));
    EXPECT_FALSE(fs::exists(d / "c.0002.png"));

    // A regression case of frame 2 fails naming the file (frame 1 would render and pass).
    std::ofstream(d / "suite.json") << R"({"name": "seq", "cases": [{"name": "frame2",
        "scene": "missing.json", "frame": 2, "reference": "cpu", "metrics": {"nrmse": 0.5}}]})";
    r = veil("regress " + shellQuote(d / "suite.json") + " -o " + shellQuote(d / "report"));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("FAIL frame2"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find((d / "f_2.vdb").string() + "' (truncated or corrupt?)"),
              std::string::npos)
        << r.output;
}

TEST(SequenceCliTest, VideoWithoutFfmpegIsAClearError) {
    if (runCommand("command -v ffmpeg").exitCode == 0) GTEST_SKIP() << "ffmpeg is installed";
    const fs::path d = dir("video");
    const fs::path scene = writeScene(d / "seq.json", fireScene(pattern(), false));
    const CommandResult r =
        veil("render " + shellQuote(scene) + " --frames 1-2 -o " + shellQuote(d / "out.mp4"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("writing video needs ffmpeg, which is not installed"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(d / "out.mp4"));
    const CommandResult bad = veil("render " + shellQuote(scene) + " --frames 5-1 -o x.#.png");
    EXPECT_EQ(bad.exitCode, 2) << bad.output;
}

} // namespace veil::test
