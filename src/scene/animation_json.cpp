// The scene format's time keys (docs/scene-format.md "Sequences and animation"): a volume's
// file sequence, camera and light keys, the turntable, the time block.
#include "scene/animation_json.h"

#include "scene/scene_values.h"

#include <algorithm>
#include <numeric>

namespace veil::scene::detail {

namespace {

Outside outsideOf(const std::string& s) {
    return s == "loop" ? Outside::Loop : s == "blank" ? Outside::Blank : Outside::Hold;
}

constexpr long long kFrameLimit = 1LL << 30;

Interpolation interpolationOf(const Obj& o) {
    return o.str("interpolation", "linear", {"linear", "catmull-rom"}) == "catmull-rom"
               ? Interpolation::CatmullRom
               : Interpolation::Linear;
}

// "keys": [{"frame": F, key: value, ...}, ...] with frames strictly ascending; each entry's
// `channels` (key, channel, is a scalar) that it names go into the channel.
struct ChannelSpec {
    const char* key;
    KeyChannel* channel;
    bool scalar;
    Range range;
};

void parseKeys(const Obj& parent, std::vector<ChannelSpec> specs) {
    std::vector<std::string> known{"frame"};
    for (const ChannelSpec& c : specs)
        known.push_back(c.key);
    double previous = -kInf;
    forEach(parent, "keys", [&](const json& j, const std::string& p, std::size_t) {
        Obj k(parent.ctx(), j, p, known);
        k.require("frame");
        const double frame = k.num("frame", 0.0f, Range{-1e9, 1e9});
        if (frame <= previous)
            fail(parent.ctx(), k.ptr("frame"),
                 fmt::format("key frames must increase (this {} follows {})", frame, previous));
        previous = frame;
        for (ChannelSpec& c : specs) {
            if (!k.has(c.key)) continue;
            c.channel->frames.push_back(frame);
            c.channel->values.push_back(c.scalar ? glm::vec3(k.num(c.key, 0.0f, c.range))
                                                 : k.vec<3>(c.key, glm::vec3(0.0f), c.range));
        }
    });
    if (parent.has("keys") && previous == -kInf)
        fail(parent.ctx(), parent.ptr("keys"), "needs at least one key");
}

// The declared values of `decls` (int, float and string fields) with their ranges and choices.
template <class S>
void readPlainValues(const Obj& o, const std::vector<ValueDecl<S>>& decls, S& s) {
    for (const ValueDecl<S>& d : decls) {
        const Range r{d.accepted.lo, d.accepted.hi, d.accepted.loOpen, d.accepted.hiOpen};
        if (auto f = std::get_if<float S::*>(&d.field))
            s.*(*f) = o.num(d.key, s.*(*f), r);
        else if (auto i = std::get_if<int S::*>(&d.field))
            s.*(*i) =
                int(o.integer(d.key, s.*(*i), (long long)d.accepted.lo, (long long)d.accepted.hi));
        else if (auto ll = std::get_if<long long S::*>(&d.field))
            s.*(*ll) =
                o.integer(d.key, s.*(*ll), (long long)d.accepted.lo, (long long)d.accepted.hi);
        else if (auto str = std::get_if<std::string S::*>(&d.field))
            s.*(*str) = o.str(d.key, s.*(*str), d.choices);
    }
}

} // namespace

const std::vector<std::string>& cameraAnimationKeys() {
    static const std::vector<std::string> keys{"keys", "interpolation", "turntable"};
    return keys;
}

const std::vector<std::string>& lightAnimationKeys() {
    static const std::vector<std::string> keys{"keys", "interpolation"};
    return keys;
}

const std::vector<std::string>& sequenceKeys() {
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k{"frames"};
        for (const auto& d : sequenceValueDecls())
            k.push_back(d.key);
        return k;
    }();
    return keys;
}

const std::vector<std::string>& timeKeys() {
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k;
        for (const auto& d : timeValueDecls())
            k.push_back(d.key);
        k.push_back("frame_range");
        return k;
    }();
    return keys;
}

void parseCameraAnimation(const Obj& o, const Camera& c, CameraAnimation& a) {
    a.interpolation = interpolationOf(o);
    const bool ortho = c.type == CameraType::Orthographic;
    parseKeys(o, {{"position", &a.position, false, kAny},
                  {"target", &a.target, false, kAny},
                  {ortho ? "ortho_height" : "fov_y", &a.fov, true,
                   ortho ? Range{0.0, kInf, true} : Range{0.0, 180.0, true, true}}});
    if (const json* t = o.get("turntable")) {
        Obj tt(o.ctx(), *t, o.ptr("turntable"), {"frames", "start_frame", "degrees"});
        a.turntable.enabled = true;
        a.turntable.frames = int(tt.integer("frames", a.turntable.frames, 1, kFrameLimit));
        a.turntable.startFrame =
            int(tt.integer("start_frame", a.turntable.startFrame, -kFrameLimit, kFrameLimit));
        a.turntable.degrees = tt.num("degrees", float(a.turntable.degrees), Range{-1e6, 1e6});
    }
}

void parseLightAnimation(const Obj& o, const Light& l, LightAnimation& a) {
    a.interpolation = interpolationOf(o);
    std::vector<ChannelSpec> specs;
    if (l.type != LightType::Directional) specs.push_back({"position", &a.position, false, kAny});
    if (l.type != LightType::Point) specs.push_back({"direction", &a.direction, false, kAny});
    parseKeys(o, specs);
    for (std::size_t i = 0; i < a.direction.values.size(); ++i)
        if (a.direction.values[i] == glm::vec3(0.0f))
            fail(o.ctx(), o.ptr("keys"),
                 fmt::format("key at frame {}: direction must not be zero", a.direction.frames[i]));
}

void parseTime(const Obj& o, TimeSettings& t) {
    readPlainValues(o, timeValueDecls(), t);
    if (const json* r = o.get("frame_range")) {
        if (!r->is_array() || r->size() != 2)
            fail(o.ctx(), o.ptr("frame_range"),
                 fmt::format("expected [first, last], got {}", show(*r)));
        t.first = int(
            integer(o.ctx(), (*r)[0], child(o.ptr("frame_range"), 0), -kFrameLimit, kFrameLimit));
        t.last =
            int(integer(o.ctx(), (*r)[1], child(o.ptr("frame_range"), 1), t.first, kFrameLimit));
        t.rangeGiven = true;
    }
}

bool parseVolumeSequence(const Obj& o, VolumeRef& v, std::optional<FileSequence>& sequence) {
    const std::string written = o.str("path", "");
    fs::path p(written);
    if (p.is_relative()) p = o.ctx().baseDir / p;
    p = p.lexically_normal();
    std::error_code ec;
    std::optional<FilePattern> pattern;
    // A file of that name is taken as it is.
    if (!fs::is_regular_file(p, ec)) try {
            pattern = parseFilePattern(p);
        } catch (const Error& e) {
            fail(o.ctx(), o.ptr("path"), e.what());
        }
    if (!pattern) {
        for (const std::string& key : sequenceKeys())
            if (o.has(key))
                fail(o.ctx(), o.ptr(key),
                     fmt::format("{} needs a frame pattern in path (name.####.vdb, %04d, $F4, #)",
                                 key));
        return false;
    }
    FileSequence s;
    s.pattern = *pattern;
    const std::vector<int> found = existingFrames(s.pattern);
    if (const json* f = o.get("frames")) {
        if (!f->is_array() || f->size() < 2 || f->size() > 3)
            fail(o.ctx(), o.ptr("frames"),
                 fmt::format("expected [first, last] or [first, last, step], got {}", show(*f)));
        const std::string fp = o.ptr("frames");
        s.first = int(integer(o.ctx(), (*f)[0], child(fp, 0), -kFrameLimit, kFrameLimit));
        s.last = int(integer(o.ctx(), (*f)[1], child(fp, 1), s.first, kFrameLimit));
        if (f->size() == 3) s.step = int(integer(o.ctx(), (*f)[2], child(fp, 2), 1, kFrameLimit));
        s.last = s.first + (s.last - s.first) / s.step * s.step;
        s.framesGiven = true;
    } else {
        if (found.empty())
            fail(o.ctx(), o.ptr("path"),
                 fmt::format("no file matches the sequence '{}' (in '{}')", p.filename().string(),
                             p.parent_path().string()));
        s.spanFound(found);
    }
    SequenceValues values;
    readPlainValues(o, sequenceValueDecls(), values);
    s.frameOffset = values.frameOffset;
    s.before = outsideOf(values.before);
    s.after = outsideOf(values.after);
    s.holdMissing = values.missing == "hold";
    // Scene frames (file frame - frame_offset) stay within the frame limit, so frame ranges
    // and `veil info` count them without overflow.
    const long long sceneFirst = (long long)s.first - s.frameOffset,
                    sceneLast = (long long)s.last - s.frameOffset;
    if (sceneFirst < -kFrameLimit || sceneLast > kFrameLimit)
        fail(o.ctx(), o.ptr("frame_offset"),
             fmt::format("file frames {}-{} with frame_offset {} are scene frames {}-{}, outside "
                         "the {}..{} a scene's frames may span",
                         s.first, s.last, s.frameOffset, sceneFirst, sceneLast, -kFrameLimit,
                         kFrameLimit));
    v.path = p;
    sequence = s;
    return true;
}

} // namespace veil::scene::detail
