// veil.Renderer (the C++ part; veil/__init__.py wraps render() into a Frame) and
// veil.techniques().
#include "bindings.h"

#include "base/error.h"
#include "capture/frame_capture.h"
#include "catalog/techniques.h"
#include "gpu/context.h"
#include "oit/technique.h"
#include "scene/scene_values.h"
#include "shadows/technique.h"

#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include <chrono>
#include <mutex>
#include <optional>

namespace veil::python {

namespace {

// `out`: a writable, C-contiguous float32 array of shape (height, width, 4), or veil.Error.
py::array_t<float> checkedOutArray(const py::object& out, int height, int width) {
    const auto name = [](const py::handle& o) {
        return py::str(o.get_type().attr("__name__")).cast<std::string>();
    };
    VEIL_CHECK(py::isinstance<py::array>(out), "out: expected a numpy array, got {}", name(out));
    const auto a = py::reinterpret_borrow<py::array>(out);
    std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
    VEIL_CHECK(a.dtype().is(py::dtype::of<float>()), "out: dtype {}, expected float32",
               py::str(a.dtype()).cast<std::string>());
    VEIL_CHECK(a.ndim() == 3 && shape[0] == height && shape[1] == width && shape[2] == 4,
               "out: shape ({}), expected ({}, {}, 4) for a {}x{} frame", fmt::join(shape, ", "),
               height, width, width, height);
    VEIL_CHECK(a.flags() & py::array::c_style, "out: not C-contiguous (use numpy.ascontiguousarray "
                                               "or numpy.empty)");
    VEIL_CHECK(a.writeable(), "out: read-only array");
    return py::reinterpret_borrow<py::array_t<float>>(out);
}

// One headless GL context (EGL; llvmpipe without a GPU) for every frame of a Renderer.
class PyRenderer {
public:
    explicit PyRenderer(std::optional<int> device) {
        VEIL_CHECK(!device || (*device >= 0 && *device <= 1023), "device {} not in range [0, 1023]",
                   device.value_or(0));
        context_ = std::make_unique<gpu::HeadlessContext>(
            gpu::HeadlessOptions{device.value_or(-1), false});
    }

    const gpu::ContextInfo& info() const { return context_->info(); }

    // The GL calls run under a lock with the context current on this thread; the GIL is
    // released meanwhile, so other Python threads run.
    template <class F>
    auto withContext(F&& f) {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(mutex_);
        context_->makeCurrent();
        return f();
    }

    py::dict render(const PyScene& scene, int width, int height, const std::string& oit,
                    const std::string& shadows, const std::string& camera,
                    const std::vector<std::string>& aovs, py::object outArray) {
        VEIL_CHECK(width >= 0 && width <= 16384, "width {} not in range [1, 16384]", width);
        VEIL_CHECK(height >= 0 && height <= 16384, "height {} not in range [1, 16384]", height);
        capture::FrameRequest request;
        for (const std::string& a : aovs) {
            VEIL_CHECK(a == "fog", "aov '{}': unknown (known: fog)", a);
            request.fogAov = true;
        }
        // Unknown techniques and bad properties fail before any GL work, as in `veil render`.
        const scene::Scene& s = *scene.parsed;
        const std::string oitName = oit.empty() ? s.render.oit : oit;
        const auto& registry = oit::Registry::instance();
        VEIL_CHECK(registry.find(oitName), "{}: unknown OIT technique '{}' (known: {})",
                   oit.empty() ? s.render.oitWhere + "/type" : "oit", oitName,
                   fmt::join(registry.names(), ", "));
        if (oitName == s.render.oit)
            registry.resolve(oitName, s.render.oitProperties, s.render.oitWhere);
        if (!shadows.empty()) shadows::Registry::instance().get(shadows, "shadows");
        request.width = width;
        request.height = height;
        request.oit = oitName;
        request.shadows = shadows;
        request.camera = camera;
        // A caller's array receives the HDR read-back directly (no copy on the CPU side).
        py::array_t<float> hdrOut;
        if (!outArray.is_none()) {
            const int w = width > 0 ? width : s.render.width;
            const int h = height > 0 ? height : s.render.height;
            hdrOut = checkedOutArray(outArray, h, w);
            request.hdrOut = hdrOut.mutable_data();
            request.hdrOutCount = static_cast<std::size_t>(hdrOut.size());
        }

        const auto start = std::chrono::steady_clock::now();
        capture::RenderedFrame f =
            withContext([&] { return capture::renderFrame(s, context_->info(), request); });
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        nlohmann::json report = capture::frameReport(f);
        report["scene"] = scene.file.empty() ? scene.source : scene.file.string();
        report["width"] = f.width;
        report["height"] = f.height;
        report["camera"] = f.camera;
        report["oit"] = f.oit;
        report["renderer"] = info().renderer;
        report["gl_version"] = info().version;
        report["vendor"] = info().vendor;
        report["scene_values"] = scene::sceneValues(s);
        report["scene_values"]["render"]["width"] = f.width;
        report["scene_values"]["render"]["height"] = f.height;
        report["seconds"] = seconds;

        py::dict out;
        if (request.hdrOut)
            out["rgba"] = hdrOut;
        else
            out["rgba"] = toArray(std::move(f.hdr));
        out["ldr"] = toArray(std::move(f.ldr));
        out["depth"] = toArray(std::move(f.extras.viewDepth));
        if (request.fogAov) {
            out["fog"] = toArray(std::move(f.extras.fogRadiance));
            out["fog_transmittance"] = toArray(std::move(f.extras.fogTransmittance));
        }
        out["report"] = toPython(report);
        return out;
    }

    // The C++ side of bench/python_overhead.py: the loop render() runs per call, `frames`
    // times without Python in between; the wall-clock seconds of each frame.
    std::vector<double> renderLoop(const PyScene& scene, int frames, int width, int height) {
        capture::FrameRequest request;
        request.width = width;
        request.height = height;
        return withContext([&] {
            std::vector<double> seconds;
            for (int i = 0; i < frames; ++i) {
                const auto start = std::chrono::steady_clock::now();
                const capture::RenderedFrame f =
                    capture::renderFrame(*scene.parsed, context_->info(), request);
                seconds.push_back(
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                        .count());
            }
            return seconds;
        });
    }

private:
    std::unique_ptr<gpu::HeadlessContext> context_;
    std::mutex mutex_;
};

} // namespace

void withRendererContext(py::handle renderer,
                         const std::function<void(const gpu::ContextInfo&)>& f) {
    VEIL_CHECK(py::isinstance<PyRenderer>(renderer), "renderer: expected a veil.Renderer, got {}",
               py::str(renderer.get_type().attr("__name__")).cast<std::string>());
    PyRenderer& r = renderer.cast<PyRenderer&>();
    r.withContext([&] {
        f(r.info());
        return 0;
    });
}

void bindRenderer(py::module_& m) {
    py::class_<PyRenderer>(m, "_Renderer")
        .def(py::init<std::optional<int>>(), py::arg("device") = py::none())
        .def(
            "_render",
            [](PyRenderer& r, py::object scene, int width, int height, const std::string& oit,
               const std::string& shadows, const std::string& camera,
               const std::vector<std::string>& aovs, py::object out) {
                const PyScene s = sceneArgument(scene);
                return r.render(s, width, height, oit, shadows, camera, aovs, out);
            },
            py::arg("scene"), py::arg("width") = 0, py::arg("height") = 0, py::arg("oit") = "",
            py::arg("shadows") = "", py::arg("camera") = "",
            py::arg("aovs") = std::vector<std::string>{}, py::arg("out") = py::none())
        .def(
            "_render_loop",
            [](PyRenderer& r, py::object scene, int frames, int width, int height) {
                VEIL_CHECK(frames > 0 && width > 0 && height > 0,
                           "frames, width and height must be > 0");
                return r.renderLoop(sceneArgument(scene), frames, width, height);
            },
            py::arg("scene"), py::arg("frames"), py::arg("width"), py::arg("height"))
        .def_property_readonly(
            "gl_renderer", [](const PyRenderer& r) { return r.info().renderer; },
            "The GL renderer string, e.g. 'llvmpipe (LLVM 15.0.6, 256 bits)'.")
        .def_property_readonly("gl_version", [](const PyRenderer& r) { return r.info().version; })
        .def_property_readonly(
            "software", [](const PyRenderer& r) { return r.info().softwareRenderer; },
            "True on llvmpipe / softpipe (pass times are glFinish + CPU clock).")
        .def("_techniques",
             [](const PyRenderer& r) { return toPython(catalog::catalogJson(r.info())); });

    m.def("_techniques_without_renderer", []() {
        std::optional<gpu::ContextInfo> info;
        try {
            gpu::HeadlessContext context(gpu::HeadlessOptions{});
            info = context.info();
        } catch (const Error&) {
        }
        return toPython(catalog::catalogJson(info));
    });
}

} // namespace veil::python
