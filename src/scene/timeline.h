// A scene in time: the file sequences of its volumes, the keys of its cameras and lights, the
// time block (scene/animation.h has the rules), and the scene at one frame. loadScene()
// returns the scene at one frame (time.frame, else the first); loadAnimatedScene() keeps the
// time for frame ranges (src/sequence) and `veil info`.
#pragma once

#include "scene/animation.h"
#include "scene/scene.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace veil::scene {

struct Timeline {
    TimeSettings time;
    std::vector<std::optional<FileSequence>> volumes; // by index of Scene::volumes
    std::vector<CameraAnimation> cameras;             // by index of Scene::cameras
    std::vector<LightAnimation> lights;               // by index of Scene::lights
    bool animated() const;
};

// The scene as written (a sequence volume's path is its pattern) and its time.
struct AnimatedScene {
    Scene scene;
    Timeline timeline;
};

AnimatedScene loadAnimatedScene(const std::filesystem::path& path,
                                const std::vector<std::string>& overrides = {},
                                const TechniqueChoice& choice = {});
AnimatedScene parseAnimatedScene(const nlohmann::json& doc, const std::filesystem::path& baseDir);

// The most frames one range may hold (docs/sequences.md): over an hour at 24 fps. A longer
// range is refused before anything is allocated or rendered; split it into several runs.
constexpr long long kMaxRangeFrames = 100000;

struct FrameRange {
    int first = 1, last = 1, step = 1;
    long long count() const { return ((long long)last - first) / step + 1; }
    // first, first + step, ..., <= last; throws veil::Error (naming `what`) for more than
    // kMaxRangeFrames frames.
    std::vector<int> frames(const std::string& what = "frame range") const;
};

// "A-B", "A-B:S" or "N" (negative frames as "-5--1"); throws veil::Error naming `what`, also
// for a range of more than kMaxRangeFrames frames.
FrameRange parseFrameRange(const std::string& text, const std::string& what = "--frames");

// The message for a range of more than kMaxRangeFrames frames (`what` names it), empty for
// one that is not.
std::string frameCountProblem(const FrameRange& range, const std::string& what);

// The scene's frames: time.frame_range when given; else the union of the volume sequences'
// ranges (in scene frames), the camera and light keys and the turntable's frames; else 1-1.
FrameRange sceneFrameRange(const Timeline& timeline);

// The frame loadScene() gives: time.frame, else the first of sceneFrameRange().
int defaultFrame(const Timeline& timeline);

Camera cameraAtFrame(const Camera& c, const CameraAnimation& a, double frame);
Light lightAtFrame(const Light& l, const LightAnimation& a, double frame);

// Why no image can be rendered from an animated camera at `frame` (its Catmull-Rom fov
// overshooting out of range, its position on its target, its up parallel to the view: what
// the parser refuses for a static camera), or empty. checkCamerasAtFrame throws veil::Error
// naming the camera for the first such camera; sceneAtFrame() calls it.
std::string cameraProblemAtFrame(const Camera& c, const CameraAnimation& a, int frame);
void checkCamerasAtFrame(const AnimatedScene& s, int frame);

// What each volume shows at `frame`, in scene.volumes order (a volume that is no sequence:
// its own path). Throws veil::Error naming a missing file (scene/animation.h).
std::vector<SequenceFrame> volumeFrames(const AnimatedScene& s, int frame);

// The scene at `frame`: each sequence volume's path is its file at that frame, a blank one is
// left out; cameras and lights evaluated. `notes` gets a line per held missing file.
Scene sceneAtFrame(const AnimatedScene& s, int frame, std::vector<std::string>* notes = nullptr);

} // namespace veil::scene
