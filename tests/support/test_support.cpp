#include "support/test_support.h"

#include "io/image_io.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <sys/wait.h>

namespace veil::test {

namespace fs = std::filesystem;

fs::path sourceDir() { return VEIL_SOURCE_DIR; }
fs::path dataDir() { return VEIL_DATA_DIR; }
fs::path outputDir() {
    fs::path dir = VEIL_TEST_OUTPUT_DIR;
    fs::create_directories(dir);
    return dir;
}

fs::path outputSubdir(const std::string& name) {
    const fs::path dir = outputDir() / name;
    fs::create_directories(dir);
    return dir;
}

fs::path freshOutputDir(const std::string& group, const std::string& name) {
    const fs::path d = outputDir() / group / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

fs::path writeTextFile(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string readTextFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

std::string shellQuote(const fs::path& path) {
    std::string s(1, '\'');
    for (const char c : path.string())
        if (c == '\'')
            s.append("'\\''");
        else
            s.push_back(c);
    s.push_back('\'');
    return s;
}

ImageDiff compareImages(const ImageF& a, const ImageF& b, int channels) {
    ImageDiff d;
    if (a.width != b.width || a.height != b.height || a.channels < channels ||
        b.channels < channels) {
        d.maxAbs = d.rmse = std::numeric_limits<double>::infinity();
        return d;
    }
    double sum = 0.0;
    std::size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < channels; ++c) {
                const double e = std::abs(double(a.at(x, y, c)) - double(b.at(x, y, c)));
                d.maxAbs = std::max(d.maxAbs, std::isnan(e) ? 1e30 : e);
                sum += e * e;
                ++n;
            }
    d.rmse = n ? std::sqrt(sum / double(n)) : 0.0;
    return d;
}

std::string writeFailureImages(const std::string& name, const ImageF& render,
                               const ImageF& reference) {
    const fs::path dir = outputDir();
    io::writeImage(dir / (name + "-render.exr"), render);
    if (reference.width == render.width && reference.height == render.height) {
        io::writeImage(dir / (name + "-reference.exr"), reference);
        ImageF diff(render.width, render.height, 3);
        for (int y = 0; y < render.height; ++y)
            for (int x = 0; x < render.width; ++x)
                for (int c = 0; c < 3; ++c)
                    diff.at(x, y, c) = std::abs(render.at(x, y, c) - reference.at(x, y, c));
        io::writeImage(dir / (name + "-diff.exr"), diff);
    }
    return dir.string();
}

CommandResult runCommand(const std::string& commandLine) {
    CommandResult result;
    const std::string cmd = commandLine + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buf{};
    std::size_t n;
    while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0)
        result.output.append(buf.data(), n);
    const int status = pclose(pipe);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

std::string veilExe() { return VEIL_EXE; }

} // namespace veil::test
