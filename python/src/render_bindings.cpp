// veil.Renderer (the C++ part; veil/__init__.py wraps render() into a Frame) and
// veil.techniques().
#include "bindings.h"

#include "base/error.h"
#include "base/text.h"
#include "capture/frame_capture.h"
#include "catalog/techniques.h"
#include "gpu/context.h"
#include "oit/technique.h"
#include "scene/scene_values.h"
#include "shadows/technique.h"

#include <EGL/egl.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>

namespace veil::python {

namespace {

void releaseCurrent() {
    if (EGLDisplay display = eglGetCurrentDisplay(); display != EGL_NO_DISPLAY)
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

std::vector<std::string> quoted(const std::vector<std::string>& names) {
    std::vector<std::string> out;
    for (const std::string& n : names)
        out.push_back("'" + printable(n, 60) + "'");
    return out;
}

// `out`: a writable, C-contiguous float32 array of shape (height, width, 4), or veil.Error.
py::array_t<float> checkedOutArray(const py::object& out, int height, int width) {
    const auto name = [](const py::handle& o) {
        return py::str(o.get_type().attr("__name__")).cast<std::string>();
    };
    VEIL_PY_CHECK(ErrorKind::Type, py::isinstance<py::array>(out),
                  "out: expected a numpy array, got {}", name(out));
    const auto a = py::reinterpret_borrow<py::array>(out);
    std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
    VEIL_PY_CHECK(ErrorKind::Value, a.dtype().is(py::dtype::of<float>()),
                  "out: dtype {}, expected float32", py::str(a.dtype()).cast<std::string>());
    VEIL_PY_CHECK(ErrorKind::Value,
                  a.ndim() == 3 && shape[0] == height && shape[1] == width && shape[2] == 4,
                  "out: shape ({}), expected ({}, {}, 4) for a {}x{} frame", fmt::join(shape, ", "),
                  height, width, width, height);
    VEIL_PY_CHECK(ErrorKind::Value, a.flags() & py::array::c_style,
                  "out: not C-contiguous (use numpy.ascontiguousarray or numpy.empty)");
    VEIL_PY_CHECK(ErrorKind::Value, a.writeable(), "out: read-only array");
    return py::reinterpret_borrow<py::array_t<float>>(out);
}

// One headless GL context (EGL; llvmpipe without a GPU) for every frame of a Renderer. The
// context is current on no thread between calls: each call makes it current on the calling
// thread under the lock and releases it after, so any thread may use the Renderer (EGL lets a
// context be current on one thread at a time).
class PyRenderer {
public:
    explicit PyRenderer(std::optional<long long> device) {
        VEIL_PY_CHECK(ErrorKind::Value, !device || (*device >= 0 && *device <= 1023),
                      "device={} is not in range [0, 1023]", device.value_or(0));
        py::gil_scoped_release release;
        context_ = std::make_unique<gpu::HeadlessContext>(
            gpu::HeadlessOptions{static_cast<int>(device.value_or(-1)), false});
        releaseCurrent();
    }

    const gpu::ContextInfo& info() const { return context_->info(); }

    // The GL calls run under a lock with the context current on this thread; the GIL is
    // released meanwhile, so other Python threads run.
    template <class F>
    auto withContext(F&& f) {
        py::gil_scoped_release release;
        std::lock_guard<std::mutex> lock(mutex_);
        context_->makeCurrent();
        struct Release {
            ~Release() { releaseCurrent(); }
        } releaseAfter;
        return f();
    }

    py::dict render(const PyScene& scene, std::optional<long long> width,
                    std::optional<long long> height, const std::string& oit,
                    const std::string& shadows, const std::string& camera,
                    const std::vector<std::string>& aovs, py::object outArray) {
        for (const auto& [name, v] : {std::pair{"width", width}, std::pair{"height", height}})
            VEIL_PY_CHECK(ErrorKind::Value, !v || (*v >= 1 && *v <= 16384),
                          "{}={} is not in range [1, 16384]", name, v.value_or(0));
        const scene::Scene& s = *scene.parsed;
        capture::FrameRequest request;
        for (const std::string& a : aovs) {
            VEIL_PY_CHECK(ErrorKind::Value, a == "fog", "aovs=[{}]: unknown AOV '{}' (known: fog)",
                          fmt::join(quoted(aovs), ", "), printable(a, 60));
            VEIL_PY_CHECK(ErrorKind::Value, !s.volumes.empty(),
                          "aovs=['fog']: the scene {} has no volumes or fog (add a volume, or "
                          "render without aovs)",
                          scene.source);
            request.fogAov = true;
        }
        // Unknown techniques, cameras and bad properties fail before any GL work, as in
        // `veil render`, naming the argument that chose them.
        const std::string oitName = oit.empty() ? s.render.oit : oit;
        const auto& registry = oit::Registry::instance();
        VEIL_PY_CHECK(ErrorKind::Value, registry.find(oitName),
                      "{}: unknown OIT technique '{}' (known: {})",
                      oit.empty() ? s.render.oitWhere + "/type" : "oit", printable(oitName, 60),
                      fmt::join(registry.names(), ", "));
        classified(ErrorKind::Value, [&] {
            if (oitName == s.render.oit)
                registry.resolve(oitName, s.render.oitProperties, s.render.oitWhere);
            if (!shadows.empty()) shadows::Registry::instance().get(shadows, "shadows");
        });
        if (!camera.empty()) {
            std::vector<std::string> names;
            for (const auto& c : s.cameras)
                names.push_back(c.name);
            VEIL_PY_CHECK(ErrorKind::Value,
                          std::find(names.begin(), names.end(), camera) != names.end(),
                          "camera='{}': the scene has no such camera (cameras: {})",
                          printable(camera, 60), fmt::join(names, ", "));
        }
        request.width = static_cast<int>(width.value_or(0));
        request.height = static_cast<int>(height.value_or(0));
        request.oit = oitName;
        request.shadows = shadows;
        request.camera = camera;
        // A caller's array receives the HDR read-back directly (no copy on the CPU side).
        py::array_t<float> hdrOut;
        if (!outArray.is_none()) {
            const int w = width ? static_cast<int>(*width) : s.render.width;
            const int h = height ? static_cast<int>(*height) : s.render.height;
            hdrOut = checkedOutArray(outArray, h, w);
            request.hdrOut = hdrOut.mutable_data();
            request.hdrOutCount = static_cast<std::size_t>(hdrOut.size());
        }

        const auto start = std::chrono::steady_clock::now();
        capture::RenderedFrame f = withContext([&] {
            try {
                return capture::renderFrame(s, context_->info(), request);
            } catch (const Error& e) {
                // The library names the command line's flag; the caller wrote aovs=.
                const std::string m = e.what();
                const std::string flag = "--aov fog: ";
                if (m.rfind(flag, 0) == 0)
                    throw PyError(ErrorKind::Value, "aovs=['fog']: " + m.substr(flag.size()));
                throw;
            }
        });
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
    VEIL_PY_CHECK(ErrorKind::Type, py::isinstance<PyRenderer>(renderer),
                  "renderer: expected a veil.Renderer, got {}", typeName(renderer));
    PyRenderer& r = renderer.cast<PyRenderer&>();
    r.withContext([&] {
        f(r.info());
        return 0;
    });
}

void bindRenderer(py::module_& m) {
    py::class_<PyRenderer>(m, "_Renderer")
        .def(py::init([](const OptIntArg& device) {
                 return std::make_unique<PyRenderer>(toOptInt(device, "device"));
             }),
             py::arg("device") = py::none())
        .def(
            "_render",
            [](PyRenderer& r, const SceneArg& scene, const OptIntArg& width,
               const OptIntArg& height, const OptStrArg& oit, const OptStrArg& shadows,
               const OptStrArg& camera, const StrListArg& aovs, const OptArrayArg& out) {
                const PyScene s = sceneArgument(scene);
                return r.render(
                    s, toOptInt(width, "width"), toOptInt(height, "height"),
                    toOptStr(oit, "oit").value_or(""), toOptStr(shadows, "shadows").value_or(""),
                    toOptStr(camera, "camera").value_or(""), toStrList(aovs, "aovs", true), out);
            },
            py::arg("scene"), py::arg("width") = py::none(), py::arg("height") = py::none(),
            py::arg("oit") = py::none(), py::arg("shadows") = py::none(),
            py::arg("camera") = py::none(), py::arg("aovs") = py::tuple(),
            py::arg("out") = py::none())
        .def(
            "_render_loop",
            [](PyRenderer& r, py::object scene, int frames, int width, int height) {
                VEIL_PY_CHECK(ErrorKind::Value, frames > 0 && width > 0 && height > 0,
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
