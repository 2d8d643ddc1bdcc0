// Time in a scene: file sequences of volumes (one file per frame), keyframed camera and light
// values, a turntable camera, and the scene's time block. Frames are integers (the numbers of
// the files and of the rendered images); keyframe values are evaluated at any frame.
//
// Sequence file names (docs/scene-format.md "Sequences"): one frame-number pattern in the file
// name, one of
//   ####   a run of N >= 2 '#': the number zero-padded to N digits (wider numbers as they are)
//   #      a single '#': the number unpadded (any width: 1, 10, 100)
//   %0Nd   printf-style, padded to N; %d unpadded
//   $FN    Houdini-style, padded to N; $F unpadded
// A number matches a file name only as the pattern writes it ("007" is not frame 7 of an
// unpadded pattern), so two sequences with different padding in one folder stay apart.
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace veil::scene {

struct FilePattern {
    std::filesystem::path folder;
    std::string prefix, suffix; // of the file name around the number
    int padding = 0;            // 0: unpadded
    std::string written;        // the pattern as written (for messages)

    std::filesystem::path fileFor(int frame) const;
    // The frame number a file name stands for, if it matches.
    std::optional<int> frameOf(const std::string& fileName) const;
};

// The pattern in the last component of `path`, or none when the name has no pattern.
// Throws veil::Error for a name with two patterns or a malformed one ("%5d", "$F0").
std::optional<FilePattern> parseFilePattern(const std::filesystem::path& path);

// The frames of the files that exist now, ascending.
std::vector<int> existingFrames(const FilePattern& pattern);

enum class Outside { Hold, Loop, Blank };

// A volume's file sequence: file frame n = scene frame + frameOffset, over the frames
// first, first + step, ..., <= last. A frame between two steps holds the earlier one.
struct FileSequence {
    FilePattern pattern;
    int first = 1, last = 1, step = 1;
    bool framesGiven = false; // else first/last/step come from the files found
    int frameOffset = 0;
    Outside before = Outside::Hold, after = Outside::Hold;
    bool holdMissing = false; // else a missing file in the range is an error

    long long count() const { return ((long long)last - first) / step + 1; }
    // first/last from the files found (ascending, not empty), step their spacing's greatest
    // common divisor (1 for a single file).
    void spanFound(const std::vector<int>& found);
};

// What a scene frame of a sequence shows.
struct SequenceFrame {
    bool blank = false; // outside the range with `blank`: no volume this frame
    int fileFrame = 0;
    std::filesystem::path path;
    bool held = false; // a missing file replaced by the nearest earlier (else later) one
};

// Resolves a scene frame; throws veil::Error naming the file when it is missing (and
// holdMissing is off) or when no file of the sequence exists. `what` names the volume.
SequenceFrame resolveSequenceFrame(const FileSequence& s, int sceneFrame, const std::string& what);

// The frames of the sequence's range whose files do not exist (the first `limit`).
std::vector<int> missingFrames(const FileSequence& s, std::size_t limit = 1000);

enum class Interpolation { Linear, CatmullRom };

// One keyed value (a float is stored in x). Keys ascending by frame.
struct KeyChannel {
    std::vector<double> frames;
    std::vector<glm::vec3> values;
    bool empty() const { return frames.empty(); }
};

// Before the first key: the first value; after the last: the last. Linear: straight lines;
// Catmull-Rom: the uniform Catmull-Rom spline through the keys, the parameter running 0..1
// between two keys, end segments with the end key repeated as its outer neighbour.
glm::vec3 evaluate(const KeyChannel& c, Interpolation interp, double frame);

// Orbits the camera's position around its target about its up axis: `degrees` per `frames`
// frames from startFrame (counter-clockwise seen from the tip of up), angle 0 at startFrame.
struct Turntable {
    bool enabled = false;
    int startFrame = 1;
    int frames = 120;
    double degrees = 360.0;
};

struct CameraAnimation {
    Interpolation interpolation = Interpolation::Linear;
    KeyChannel position, target, fov; // fov: fov_y (perspective) or ortho_height
    Turntable turntable;
    bool animated() const {
        return !position.empty() || !target.empty() || !fov.empty() || turntable.enabled;
    }
};

struct LightAnimation {
    Interpolation interpolation = Interpolation::Linear;
    KeyChannel position, direction; // direction normalized after interpolation
    bool animated() const { return !position.empty() || !direction.empty(); }
};

// A sequence volume's declared values (scene_values.h), read into FileSequence.
struct SequenceValues {
    int frameOffset = 0;
    std::string before = "hold", after = "hold"; // hold, loop, blank
    std::string missing = "error";               // error, hold
};

// The scene's "time" block.
struct TimeSettings {
    float fps = 24.0f;
    bool rangeGiven = false;
    int first = 1, last = 1; // frame_range
    // The frame a still render, the viewer and regression cases show (loadScene());
    // kNoFrame: the first of the scene's frames.
    static constexpr long long kNoFrame = -(1LL << 40);
    long long frame = kNoFrame;
    int prefetchBudgetMiB = 1024; // frame ranges: memory for grids read ahead
};

} // namespace veil::scene
