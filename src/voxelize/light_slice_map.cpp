#include "voxelize/light_slice_map.h"

#include "base/error.h"
#include "gpu/pipeline_state.h"
#include "shaders/common/bindings.h"
#include "voxelize/gpu_voxelizer.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace veil::voxelize {

namespace {
constexpr int kSlicesPerPass = 1024; // 8 RGBA32UI targets ([Eisemann06 sec. 2]: MRT)
} // namespace

LightSliceMap::LightSliceMap(gpu::ProgramManager& programs, pass::LightSliceMapRequest request)
    : programs_(programs), request_(std::move(request)) {
    const pass::LightSliceMapRequest& r = request_;
    const Method method = parseMethod(r.method);
    VEIL_CHECK(method == Method::Raster || method == Method::Conservative,
               "{}: method '{}' is not available for light views (it voxelizes CPU triangles "
               "into a world-aligned orthographic grid; the casters come from the frame's caster "
               "draw into perspective/oblique light views): use raster or conservative",
               r.owner, methodName(method));
    std::vector<std::string> defines;
    if (method == Method::Conservative) defines.push_back("CONSERVATIVE");
    if (r.local) defines.push_back("LOCAL");
    sliceProgram_ = programs.add(gpu::ProgramDesc::graphics("frame/mesh.vert", r.caster, defines));
    rangeProgram_ =
        programs.add(gpu::ProgramDesc::graphics("frame/mesh.vert", r.caster, {"DEPTH_PASS"}));
    packProgram_ = programs.add(gpu::ProgramDesc::compute("voxelize/pack.comp"));

    const int size = r.size, views = std::max(r.views, 1);
    range_ = gpu::Texture(GL_TEXTURE_2D_ARRAY);
    range_.storage3D(1, GL_RG32F, size, size, views)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    const int targets = std::min(8, (std::min(r.slices, kSlicesPerPass) + 127) / 128);
    for (int t = 0; t < targets; ++t) {
        targets_.emplace_back(GL_TEXTURE_2D);
        targets_.back()
            .storage2D(1, GL_RGBA32UI, size, size)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    sliceFbo_ = gpu::Framebuffer();
    for (int t = 0; t < targets; ++t)
        sliceFbo_.attach(GL_COLOR_ATTACHMENT0 + t, targets_[t]);
    auto buf = [&](int t) {
        return t < targets ? GLenum(GL_COLOR_ATTACHMENT0 + t) : GLenum(GL_NONE);
    };
    sliceFbo_.drawBuffers({buf(0), buf(1), buf(2), buf(3), buf(4), buf(5), buf(6), buf(7)});
    sliceFbo_.checkComplete((r.owner + " slice pass").c_str());
    rangeFbo_ = gpu::Framebuffer();
}

void LightSliceMap::addResources(pass::Resources& resources) const {
    resources.addBuffer(request_.name, [this] { return words_ ? &words_ : nullptr; });
    resources.add(request_.name + ".range", range_);
}

void LightSliceMap::render(const pass::Context& frame, const std::vector<View>& views) {
    const pass::LightSliceMapRequest& r = request_;
    VEIL_CHECK(frame.scene, "{}: the frame gives no scene (classes)", r.owner);
    const std::vector<glm::vec3> classT = r.classes(*frame.scene);
    const int classCount = static_cast<int>(classT.size());
    const int classes = std::max(classCount, 1);
    const int size = r.size, slices = r.slices;
    const int wpc = (slices + 31) / 32;
    const std::size_t words = std::size_t(r.views) * classes * size * size * wpc;
    VEIL_CHECK(words * 4 <= (std::size_t(2) << 30),
               "{}: {} views x {} classes x {}^2 columns x {} slices need {} MiB of slice words "
               "(limit 2048): lower size, slices or classes",
               r.owner, r.views, classes, size, slices, words * 4 >> 20);
    if (!words_ || words_.size() != words * 4) {
        words_ = gpu::Buffer();
        words_.setStorage(words * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    const GLuint zero = 0;
    glClearNamedBufferData(words_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    if (classT.empty()) return; // no transparent caster: every count is 0

    const gpu::Program& slice = programs_.get(sliceProgram_);
    const gpu::Program& range = programs_.get(rangeProgram_);
    const gpu::Program& pack = programs_.get(packProgram_);
    std::vector<glm::vec3> classT3(3, glm::vec3(1.0f));
    std::copy(classT.begin(), classT.begin() + std::min(classCount, 3), classT3.begin());
    // The casters seen from the view; particles (billboards) face the light.
    const auto setView = [](const gpu::Program& program, const View& view) {
        const glm::mat4 inv = glm::inverse(view.view);
        program.set("useOverride", 1)
            .set("viewProjection", view.viewProjection)
            .set("overrideRight", glm::vec3(inv[0]))
            .set("overrideUp", glm::vec3(inv[1]));
    };
    for (const View& view : views) {
        if (r.local) {
            // [Eisemann06 sec. 2.2]: per-column near and far of the casters (one MIN-blended
            // pass).
            rangeFbo_.attachLayer(GL_COLOR_ATTACHMENT0, range_, view.layer)
                .drawBuffers({GL_COLOR_ATTACHMENT0});
            rangeFbo_.bind();
            gpu::PipelineState s;
            s.view(size, size);
            s.depthWrite = false;
            frame.state->apply(s);
            const GLfloat big[4] = {1e30f, 1e30f, 0.0f, 0.0f};
            glClearNamedFramebufferfv(rangeFbo_.id(), GL_COLOR, 0, big);
            s.blendAll(gpu::BlendState::func(GL_ONE, GL_ONE, GL_MIN));
            frame.state->apply(s);
            range.use();
            setView(range, view);
            range.set("shadowView", view.layer);
            frame.drawObjects(range, pass::ObjectSet::TransparentCasters);
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
            range_.bind(VEIL_TEX_SHADOW1);
        }
        const int passes = (slices + kSlicesPerPass - 1) / kSlicesPerPass;
        for (int c = 0; c < classCount; ++c)
            for (int p = 0; p < passes; ++p) {
                sliceFbo_.bind();
                gpu::PipelineState s;
                s.view(size, size);
                s.depthWrite = false;
                frame.state->apply(s);
                const GLuint zeros[4] = {0, 0, 0, 0};
                for (int t = 0; t < int(targets_.size()); ++t)
                    glClearNamedFramebufferuiv(sliceFbo_.id(), GL_COLOR, t, zeros);
                // [Eisemann06 sec. 2]: the fragments' bit masks OR-ed into the integer targets.
                s.logicOp = true;
                s.logicOpMode = GL_OR;
                frame.state->apply(s);
                slice.use();
                setView(slice, view);
                slice.set("shadowView", view.layer)
                    .set("uSlices", slices)
                    .set("uPass", p)
                    .set("uClass", c)
                    .set("uClasses", classCount);
                glProgramUniform3fv(slice.id(), slice.uniformLocation("uClassT"), 3, &classT3[0].x);
                frame.drawObjects(slice, pass::ObjectSet::TransparentCasters);
                glBindFramebuffer(GL_FRAMEBUFFER, 0);
                // The pack pass: targets -> column-contiguous words of map (view, class).
                const std::size_t offset =
                    (std::size_t(view.layer) * classes + c) * size * size * wpc;
                glProgramUniform3i(pack.id(), pack.uniformLocation("uGridSize"), size, size,
                                   slices);
                pack.set("uPass", p).set("uWordOffset", static_cast<unsigned>(offset));
                for (int t = 0; t < 8; ++t)
                    targets_[std::min<std::size_t>(t, targets_.size() - 1)].bind(VEIL_TEX_VOX0 + t);
                words_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_WORDS);
                pack.use();
                glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
                glDispatchCompute((size + 7) / 8, (size + 7) / 8, 1);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
                glUseProgram(0);
            }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

} // namespace veil::voxelize
