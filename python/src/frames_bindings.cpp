// veil.Renderer.frames(): a frame range of an animated scene rendered with one renderer
// (sequence/range_player.h, as `veil render --frames` renders it): the grids of the next
// frames read and converted on worker threads, each later frame of the same structure
// replacing only the volumes' data, camera and lights, its upload queued behind the previous
// frame's render. The C++ part is an iterator of (frame, dict); veil/__init__.py wraps the
// dicts into Frames.
#include "bindings.h"

#include "base/text.h"
#include "capture/exr_output.h"
#include "frame/renderer.h"
#include "scene/timeline.h"
#include "sequence/range_player.h"

#include <pybind11/stl.h>

#include <memory>
#include <optional>

namespace veil::python {

namespace {

class PyFrames {
public:
    PyFrames(py::object renderer, const PyScene& scene, std::optional<long long> first,
             std::optional<long long> last, long long step, std::optional<long long> width,
             std::optional<long long> height, const std::string& oit, long long threads)
        : renderer_(std::move(renderer)) {
        for (const auto& [name, v] : {std::pair{"width", width}, std::pair{"height", height}})
            VEIL_PY_CHECK(ErrorKind::Value, !v || (*v >= 1 && *v <= 16384),
                          "{}={} is not in range [1, 16384]", name, v.value_or(0));
        VEIL_PY_CHECK(ErrorKind::Value, threads >= 1 && threads <= 64,
                      "threads={} is not in range [1, 64]", threads);
        VEIL_PY_CHECK(ErrorKind::Value, step >= 1 && step <= 1000000,
                      "step={} is not in range [1, 1000000]", step);
        scene_ = std::make_shared<scene::AnimatedScene>(classified(
            ErrorKind::Value, [&] { return scene::parseAnimatedScene(scene.doc, scene.baseDir); }));
        const scene::FrameRange whole = scene::sceneFrameRange(scene_->timeline);
        const long long a = first.value_or(whole.first), b = last.value_or(first ? a : whole.last);
        for (const auto& [name, v] : {std::pair{"first", a}, std::pair{"last", b}})
            VEIL_PY_CHECK(ErrorKind::Value, v >= -1000000000 && v <= 1000000000,
                          "{}={} is not in range [-1e9, 1e9]", name, v);
        VEIL_PY_CHECK(ErrorKind::Value, a <= b, "first={} is after last={}", a, b);
        frames_ = classified(ErrorKind::Value, [&] {
            return scene::FrameRange{int(a), int(b), int(step)}.frames("frames(first, last)");
        });
        // Every frame's files exist before the first frame renders (renderRange's check).
        classified(ErrorKind::Error, [&] {
            for (int f : frames_)
                scene::volumeFrames(*scene_, f);
        });
        options_ = frame::RendererOptions(int(width.value_or(0)), int(height.value_or(0)), {}, oit);
        threads_ = int(threads);
    }

    ~PyFrames() {
        if (!player_) return;
        // GL objects go with the context current (and the workers stop).
        try {
            withRendererContext(renderer_, [&](const gpu::ContextInfo&) { player_.reset(); });
        } catch (...) {
        }
    }

    PyFrames(const PyFrames&) = delete;
    PyFrames& operator=(const PyFrames&) = delete;

    py::tuple next() {
        if (next_ >= frames_.size()) throw py::stop_iteration();
        ImageF hdr, ldr, depth;
        nlohmann::json report;
        withRendererContext(renderer_, [&](const gpu::ContextInfo& context) {
            if (!player_) {
                GLint max3D = 0;
                glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
                player_ = std::make_unique<sequence::RangePlayer>(
                    *scene_, frames_, context, options_,
                    std::size_t(scene_->timeline.time.prefetchBudgetMiB) << 20, threads_, max3D);
            }
            ++next_; // a frame that fails is not tried again
            const sequence::PlayedFrame f = player_->step();
            const frame::Renderer& r = *f.renderer;
            hdr = r.readHdr();
            ldr = r.readLdr();
            depth = capture::captureExtras(r, false).viewDepth;
            double gpu = 0.0;
            nlohmann::json passes = nlohmann::json::array();
            for (const auto& p : r.passTimes()) {
                passes.push_back({{"name", p.name}, {"ms", p.milliseconds}});
                gpu += p.milliseconds;
            }
            report = f.json();
            report.update({{"width", r.width()},
                           {"height", r.height()},
                           {"camera", r.camera().name},
                           {"oit", r.oitName()},
                           {"passes", passes},
                           {"total_ms", gpu},
                           {"renderer", context.renderer},
                           {"renderers_built", player_->renderers().built()}});
        });
        py::dict out;
        out["rgba"] = toArray(std::move(hdr));
        out["ldr"] = toArray(std::move(ldr));
        out["depth"] = toArray(std::move(depth));
        out["report"] = toPython(report);
        return py::make_tuple(report["frame"].get<int>(), out);
    }

    std::size_t size() const { return frames_.size(); }

private:
    py::object renderer_;
    std::shared_ptr<scene::AnimatedScene> scene_;
    std::vector<int> frames_;
    frame::RendererOptions options_;
    int threads_ = 2;
    std::size_t next_ = 0;
    std::unique_ptr<sequence::RangePlayer> player_;
};

} // namespace

void bindFrames(py::module_& m) {
    py::class_<PyFrames>(m, "_Frames")
        .def(py::init([](py::object renderer, const SceneArg& scene, const OptIntArg& first,
                         const OptIntArg& last, const OptIntArg& step, const OptIntArg& width,
                         const OptIntArg& height, const OptStrArg& oit, const OptIntArg& threads) {
                 return std::make_unique<PyFrames>(
                     std::move(renderer), sceneArgument(scene), toOptInt(first, "first"),
                     toOptInt(last, "last"), toOptInt(step, "step").value_or(1),
                     toOptInt(width, "width"), toOptInt(height, "height"),
                     toOptStr(oit, "oit").value_or(""), toOptInt(threads, "threads").value_or(2));
             }),
             py::arg("renderer"), py::arg("scene"), py::arg("first") = py::none(),
             py::arg("last") = py::none(), py::arg("step") = py::none(),
             py::arg("width") = py::none(), py::arg("height") = py::none(),
             py::arg("oit") = py::none(), py::arg("threads") = py::none())
        .def("__iter__", [](py::object self) { return self; })
        .def("__next__", &PyFrames::next)
        .def("__len__", &PyFrames::size);
}

} // namespace veil::python
