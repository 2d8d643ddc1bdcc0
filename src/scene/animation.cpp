// File sequence patterns and frame resolution, keyframe evaluation (animation.h).
#include "scene/animation.h"

#include "base/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <numeric>
#include <system_error>

namespace veil::scene {

namespace fs = std::filesystem;

namespace {

struct Found {
    std::size_t at = 0, length = 0;
    int padding = 0;
};

// Every pattern in `name` (the caller refuses more than one).
std::vector<Found> findPatterns(const std::string& name) {
    std::vector<Found> out;
    for (std::size_t i = 0; i < name.size();) {
        if (name[i] == '#') {
            std::size_t j = i;
            while (j < name.size() && name[j] == '#')
                ++j;
            const int n = int(j - i);
            out.push_back({i, j - i, n == 1 ? 0 : n});
            i = j;
        } else if (name[i] == '%') {
            std::size_t j = i + 1;
            std::string digits;
            while (j < name.size() && std::isdigit((unsigned char)name[j]))
                digits += name[j++];
            VEIL_CHECK(j < name.size() && name[j] == 'd',
                       "'{}': '%' must start a frame pattern %d or %0Nd", name);
            int padding = 0;
            if (!digits.empty()) {
                VEIL_CHECK(digits[0] == '0' && digits.size() >= 2 && digits.size() <= 3,
                           "'{}': the frame pattern is %d (unpadded) or %0Nd (padded to N)", name);
                padding = std::stoi(digits.substr(1));
            }
            out.push_back({i, j + 1 - i, padding});
            i = j + 1;
        } else if (name.compare(i, 2, "$F") == 0) {
            std::size_t j = i + 2;
            std::string digits;
            while (j < name.size() && std::isdigit((unsigned char)name[j]))
                digits += name[j++];
            int padding = digits.empty() ? 0 : std::stoi(digits.substr(0, 3));
            VEIL_CHECK(digits.empty() || (padding >= 1 && digits.size() <= 2),
                       "'{}': the frame pattern is $F (unpadded) or $FN with N in 1..99", name);
            out.push_back({i, j - i, padding <= 1 ? 0 : padding});
            i = j;
        } else {
            ++i;
        }
    }
    return out;
}

long long floorDiv(long long a, long long b) {
    long long q = a / b;
    if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
    return q;
}

long long positiveMod(long long a, long long b) {
    long long m = a % b;
    return m < 0 ? m + b : m;
}

bool isFile(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec);
}

} // namespace

fs::path FilePattern::fileFor(int frame) const {
    return folder / (prefix + fmt::format("{:0{}d}", frame, padding) + suffix);
}

std::optional<int> FilePattern::frameOf(const std::string& name) const {
    if (name.size() <= prefix.size() + suffix.size()) return std::nullopt;
    if (name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
    if (name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) return std::nullopt;
    const std::string digits =
        name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (!std::all_of(digits.begin(), digits.end(),
                     [](char c) { return std::isdigit((unsigned char)c); }))
        return std::nullopt;
    // Padding may be wider than an int's digits (%012d, $F12): leading zeros do not count.
    const std::size_t lead = std::min(digits.find_first_not_of('0'), digits.size() - 1);
    if (digits.size() - lead > 10) return std::nullopt;
    const long long wide = std::stoll(digits.substr(lead));
    if (wide > INT_MAX) return std::nullopt;
    const int n = int(wide);
    // Only as the pattern writes the number: "007" is not frame 7 of an unpadded pattern.
    if (fmt::format("{:0{}d}", n, padding) != digits) return std::nullopt;
    return n;
}

std::optional<FilePattern> parseFilePattern(const fs::path& path) {
    const std::string name = path.filename().string();
    const std::vector<Found> found = findPatterns(name);
    if (found.empty()) return std::nullopt;
    VEIL_CHECK(found.size() == 1, "'{}': a file name may hold one frame pattern, this one has {}",
               name, found.size());
    FilePattern p;
    p.folder = path.parent_path();
    p.prefix = name.substr(0, found[0].at);
    p.suffix = name.substr(found[0].at + found[0].length);
    p.padding = found[0].padding;
    p.written = path.string();
    return p;
}

void FileSequence::spanFound(const std::vector<int>& found) {
    first = found.front();
    last = found.back();
    int gcd = 0;
    for (std::size_t i = 1; i < found.size(); ++i)
        gcd = std::gcd(gcd, found[i] - found[i - 1]);
    step = std::max(gcd, 1);
}

std::vector<int> existingFrames(const FilePattern& pattern) {
    std::vector<int> frames;
    std::error_code ec;
    for (fs::directory_iterator it(pattern.folder, ec), end; !ec && it != end; it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        if (auto n = pattern.frameOf(it->path().filename().string())) frames.push_back(*n);
    }
    std::sort(frames.begin(), frames.end());
    return frames;
}

SequenceFrame resolveSequenceFrame(const FileSequence& s, int sceneFrame, const std::string& what) {
    const long long n = (long long)sceneFrame + s.frameOffset;
    const long long count = s.count();
    long long index = floorDiv(n - s.first, s.step);
    SequenceFrame out;
    for (const auto& [outside, beyond] :
         {std::pair{s.before, index < 0}, std::pair{s.after, index >= count}}) {
        if (!beyond) continue;
        if (outside == Outside::Blank) {
            out.blank = true;
            return out;
        }
        index = outside == Outside::Loop ? positiveMod(index, count)
                                         : std::clamp(index, 0LL, count - 1);
    }
    auto frameAt = [&](long long i) { return int(s.first + i * s.step); };
    out.fileFrame = frameAt(index);
    out.path = s.pattern.fileFor(out.fileFrame);
    if (isFile(out.path)) return out;
    VEIL_CHECK(s.holdMissing,
               "{}: frame {} (scene frame {}): file '{}' is missing (sequence '{}', frames {}-{} "
               "step {}; \"missing\": \"hold\" holds the nearest frame instead)",
               what, out.fileFrame, sceneFrame, out.path.string(), s.pattern.written, s.first,
               s.last, s.step);
    // The nearest earlier file of the sequence's frames, else the nearest later one (from one
    // scan of the folder: a long range with few files is no long loop).
    std::optional<int> earlier, later;
    for (int f : existingFrames(s.pattern)) {
        if (f < s.first || f > s.last || (f - s.first) % s.step != 0) continue;
        if (f < out.fileFrame) earlier = f;
        if (f > out.fileFrame && !later) later = f;
    }
    if (earlier || later) {
        out.fileFrame = earlier ? *earlier : *later;
        out.path = s.pattern.fileFor(out.fileFrame);
        out.held = true;
        return out;
    }
    throw Error(fmt::format("{}: no file of sequence '{}' exists (frames {}-{} step {})", what,
                            s.pattern.written, s.first, s.last, s.step));
}

std::vector<int> missingFrames(const FileSequence& s, std::size_t limit) {
    const std::vector<int> found = existingFrames(s.pattern);
    std::vector<int> out;
    for (long long i = 0; i < s.count() && out.size() < limit; ++i) {
        const int f = int(s.first + i * s.step);
        if (!std::binary_search(found.begin(), found.end(), f)) out.push_back(f);
    }
    return out;
}

glm::vec3 evaluate(const KeyChannel& c, Interpolation interp, double frame) {
    const std::size_t n = c.frames.size();
    if (n == 0) return glm::vec3(0.0f);
    if (frame <= c.frames.front()) return c.values.front();
    if (frame >= c.frames.back()) return c.values.back();
    const std::size_t k = std::size_t(std::upper_bound(c.frames.begin(), c.frames.end(), frame) -
                                      c.frames.begin() - 1);
    const double t = (frame - c.frames[k]) / (c.frames[k + 1] - c.frames[k]);
    const glm::dvec3 p1(c.values[k]), p2(c.values[k + 1]);
    if (interp == Interpolation::Linear) return glm::vec3(p1 + (p2 - p1) * t);
    const glm::dvec3 p0(c.values[k == 0 ? 0 : k - 1]);
    const glm::dvec3 p3(c.values[k + 2 < n ? k + 2 : n - 1]);
    // Uniform Catmull-Rom: tangents (p2 - p0) / 2 and (p3 - p1) / 2 at p1 and p2.
    const double t2 = t * t, t3 = t2 * t;
    return glm::vec3(0.5 *
                     ((2.0 * p1) + (p2 - p0) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                      (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3));
}

} // namespace veil::scene
