// Scenes at a frame and frame ranges (timeline.h).
#include "scene/timeline.h"

#include "base/error.h"

#include <fmt/format.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace veil::scene {

std::string frameCountProblem(const FrameRange& r, const std::string& what) {
    if (r.count() <= kMaxRangeFrames) return {};
    const std::string step = r.step == 1 ? std::string() : fmt::format(":{}", r.step);
    return fmt::format("{}: {} frames, over the {} one run renders (split the range into "
                       "several runs, e.g. --frames {}-{}{} first)",
                       what, r.count(), kMaxRangeFrames, r.first,
                       (long long)r.first + (kMaxRangeFrames - 1) * r.step, step);
}

std::vector<int> FrameRange::frames(const std::string& what) const {
    if (const std::string problem = frameCountProblem(
            *this, fmt::format("{} {}-{}{}", what, first, last,
                               step == 1 ? std::string() : fmt::format(":{}", step)));
        !problem.empty())
        throw Error(problem);
    std::vector<int> out;
    out.reserve(std::size_t(std::max(count(), 0LL)));
    for (long long f = first; f <= last; f += step)
        out.push_back(int(f));
    return out;
}

namespace {

bool parseInt(const std::string& s, int& out) {
    if (s.empty()) return false;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && ptr == s.data() + s.size();
}

void widen(FrameRange& r, bool& any, int first, int last) {
    r.first = any ? std::min(r.first, first) : first;
    r.last = any ? std::max(r.last, last) : last;
    any = true;
}

void widenKeys(FrameRange& r, bool& any, const KeyChannel& c) {
    if (c.empty()) return;
    widen(r, any, int(std::floor(c.frames.front())), int(std::ceil(c.frames.back())));
}

} // namespace

FrameRange parseFrameRange(const std::string& text, const std::string& what) {
    const std::string problem =
        fmt::format("{} '{}': expected FIRST-LAST, FIRST-LAST:STEP or one frame N", what, text);
    FrameRange r;
    std::string body = text;
    if (auto colon = body.find(':'); colon != std::string::npos) {
        VEIL_CHECK(parseInt(body.substr(colon + 1), r.step), "{}", problem);
        VEIL_CHECK(r.step >= 1, "{} '{}': the step must be at least 1", what, text);
        body = body.substr(0, colon);
    }
    // The dash between the frames is the first one after a digit ("-5--1": -5 to -1).
    std::size_t dash = std::string::npos;
    for (std::size_t i = 1; i < body.size(); ++i)
        if (body[i] == '-' && std::isdigit((unsigned char)body[i - 1])) {
            dash = i;
            break;
        }
    if (dash == std::string::npos) {
        VEIL_CHECK(text.find(':') == std::string::npos && parseInt(body, r.first), "{}", problem);
        r.last = r.first;
        return r;
    }
    VEIL_CHECK(parseInt(body.substr(0, dash), r.first) && parseInt(body.substr(dash + 1), r.last),
               "{}", problem);
    VEIL_CHECK(r.last >= r.first, "{} '{}': the last frame is before the first", what, text);
    if (const std::string problem = frameCountProblem(r, fmt::format("{} '{}'", what, text));
        !problem.empty())
        throw Error(problem);
    return r;
}

bool Timeline::animated() const {
    for (const auto& v : volumes)
        if (v) return true;
    for (const CameraAnimation& c : cameras)
        if (c.animated()) return true;
    for (const LightAnimation& l : lights)
        if (l.animated()) return true;
    return false;
}

FrameRange sceneFrameRange(const Timeline& t) {
    if (t.time.rangeGiven) return {t.time.first, t.time.last, 1};
    FrameRange r;
    bool any = false;
    for (const auto& v : t.volumes)
        if (v) widen(r, any, v->first - v->frameOffset, v->last - v->frameOffset);
    for (const CameraAnimation& c : t.cameras) {
        widenKeys(r, any, c.position);
        widenKeys(r, any, c.target);
        widenKeys(r, any, c.fov);
        if (c.turntable.enabled)
            widen(r, any, c.turntable.startFrame, c.turntable.startFrame + c.turntable.frames - 1);
    }
    for (const LightAnimation& l : t.lights) {
        widenKeys(r, any, l.position);
        widenKeys(r, any, l.direction);
    }
    return r;
}

int defaultFrame(const Timeline& t) {
    return t.time.frame != TimeSettings::kNoFrame ? int(t.time.frame) : sceneFrameRange(t).first;
}

Camera cameraAtFrame(const Camera& c, const CameraAnimation& a, double frame) {
    Camera out = c;
    if (!a.position.empty()) out.position = evaluate(a.position, a.interpolation, frame);
    if (!a.target.empty()) out.target = evaluate(a.target, a.interpolation, frame);
    if (!a.fov.empty()) {
        const float v = evaluate(a.fov, a.interpolation, frame).x;
        // Catmull-Rom may overshoot the keys: kept inside what the parser accepts.
        if (c.type == CameraType::Orthographic)
            out.orthoHeight = std::max(v, 1e-6f);
        else
            out.fovYDegrees = std::clamp(v, 1e-3f, 179.999f);
    }
    if (a.turntable.enabled) {
        const double angle = glm::radians(a.turntable.degrees) * (frame - a.turntable.startFrame) /
                             a.turntable.frames;
        const glm::dvec3 axis = glm::normalize(glm::dvec3(c.up));
        const glm::dmat4 rot = glm::rotate(glm::dmat4(1.0), angle, axis);
        const glm::dvec3 offset = glm::dvec3(out.position) - glm::dvec3(out.target);
        out.position =
            glm::vec3(glm::dvec3(out.target) + glm::dvec3(rot * glm::dvec4(offset, 0.0)));
    }
    return out;
}

Light lightAtFrame(const Light& l, const LightAnimation& a, double frame) {
    Light out = l;
    if (!a.position.empty()) out.position = evaluate(a.position, a.interpolation, frame);
    if (!a.direction.empty()) {
        const glm::dvec3 d(evaluate(a.direction, a.interpolation, frame));
        const double len = glm::length(d);
        // Opposite keys pass through zero halfway: the light keeps its direction there.
        if (len > 1e-12) out.direction = glm::vec3(d / len);
    }
    return out;
}

std::vector<SequenceFrame> volumeFrames(const AnimatedScene& s, int frame) {
    std::vector<SequenceFrame> out;
    for (std::size_t i = 0; i < s.scene.volumes.size(); ++i) {
        const VolumeRef& v = s.scene.volumes[i];
        const bool sequence = i < s.timeline.volumes.size() && s.timeline.volumes[i];
        if (!sequence) {
            out.push_back({false, frame, v.path, false});
            continue;
        }
        out.push_back(resolveSequenceFrame(*s.timeline.volumes[i], frame,
                                           fmt::format("volume '{}'", v.name)));
    }
    return out;
}

std::string cameraProblemAtFrame(const Camera& c, const CameraAnimation& a, int frame) {
    if (!a.animated()) return {};
    if (!a.fov.empty()) {
        // Catmull-Rom may overshoot the keys (cameraAtFrame clamps; the image would be black).
        const double v = evaluate(a.fov, a.interpolation, frame).x;
        if (c.type == CameraType::Perspective && !(v > 0.0 && v < 180.0))
            return fmt::format("at frame {} its fov keys give fov_y {:.4g} degrees, outside "
                               "(0, 180) (Catmull-Rom overshoots keys near the limits: use "
                               "\"interpolation\": \"linear\" or keys further from them)",
                               frame, v);
        if (c.type == CameraType::Orthographic && !(v > 0.0))
            return fmt::format("at frame {} its keys give ortho_height {:.4g}, not positive "
                               "(Catmull-Rom overshoots keys near 0: use \"interpolation\": "
                               "\"linear\")",
                               frame, v);
    }
    const Camera at = cameraAtFrame(c, a, frame);
    const glm::dvec3 dir = glm::dvec3(at.target) - glm::dvec3(at.position);
    const double len = glm::length(dir);
    if (!(len > 0.0) || !std::isfinite(len))
        return fmt::format("at frame {} its position ({:.4g} {:.4g} {:.4g}) equals its target",
                           frame, at.position.x, at.position.y, at.position.z);
    const glm::dvec3 up(at.up);
    if (glm::length(glm::cross(dir / len, up / glm::length(up))) < 1e-6)
        return fmt::format("at frame {} its up ({:.3g} {:.3g} {:.3g}) is parallel to the view "
                           "direction",
                           frame, at.up.x, at.up.y, at.up.z);
    return {};
}

void checkCamerasAtFrame(const AnimatedScene& s, int frame) {
    for (std::size_t i = 0; i < s.scene.cameras.size() && i < s.timeline.cameras.size(); ++i)
        if (const std::string problem =
                cameraProblemAtFrame(s.scene.cameras[i], s.timeline.cameras[i], frame);
            !problem.empty())
            throw Error(fmt::format("camera '{}': {} (no image can be rendered from it)",
                                    s.scene.cameras[i].name, problem));
}

Scene sceneAtFrame(const AnimatedScene& s, int frame, std::vector<std::string>* notes) {
    checkCamerasAtFrame(s, frame);
    const std::vector<SequenceFrame> files = volumeFrames(s, frame);
    Scene out = s.scene;
    out.volumes.clear();
    for (std::size_t i = 0; i < s.scene.volumes.size(); ++i) {
        if (files[i].blank) continue;
        VolumeRef v = s.scene.volumes[i];
        if (files[i].held && notes)
            notes->push_back(fmt::format("volume '{}' frame {}: file missing, holding '{}'", v.name,
                                         frame, files[i].path.string()));
        v.path = files[i].path;
        out.volumes.push_back(std::move(v));
    }
    for (std::size_t i = 0; i < out.cameras.size() && i < s.timeline.cameras.size(); ++i)
        out.cameras[i] = cameraAtFrame(out.cameras[i], s.timeline.cameras[i], frame);
    for (std::size_t i = 0; i < out.lights.size() && i < s.timeline.lights.size(); ++i)
        out.lights[i] = lightAtFrame(out.lights[i], s.timeline.lights[i], frame);
    return out;
}

} // namespace veil::scene
