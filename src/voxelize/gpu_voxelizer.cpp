#include "voxelize/gpu_voxelizer.h"

#include "base/error.h"
#include "gpu/pipeline_state.h"
#include "gpu/timer.h"
#include "shaders/common/bindings.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>

namespace veil::voxelize {

Method parseMethod(const std::string& name) {
    if (name == "raster") return Method::Raster;
    if (name == "conservative") return Method::Conservative;
    if (name == "three-axis") return Method::ThreeAxis;
    if (name == "compute") return Method::Compute;
    throw Error(fmt::format(
        "unknown voxelization method '{}' (use raster, conservative, three-axis or compute)",
        name));
}

std::string methodName(Method method) {
    switch (method) {
    case Method::Raster:
        return "raster";
    case Method::Conservative:
        return "conservative";
    case Method::ThreeAxis:
        return "three-axis";
    case Method::Compute:
        return "compute";
    }
    return "?";
}

struct GpuVoxelizer::Impl {
    gpu::ContextInfo info;
    // Declared state of each pass. Invalidated at every pass start: other code (a frame, the
    // viewer) may have run in this context since.
    mutable gpu::StateTracker state;
    gpu::Buffer vertices{gpu::NoCreate};
    gpu::VertexArray vao{gpu::NoCreate};
    std::size_t triangles = 0;
    gpu::Buffer words{gpu::NoCreate}, range{gpu::NoCreate};
    std::array<gpu::Buffer, 2> axisWords{gpu::Buffer{gpu::NoCreate}, gpu::Buffer{gpu::NoCreate}};
    std::map<std::string, gpu::Program> programs;

    const gpu::Program& program(const std::vector<gpu::ShaderStage>& stages,
                                const std::vector<std::string>& defines) {
        std::string key;
        for (const auto& s : stages)
            key += s.file.string() + ";";
        for (const auto& d : defines)
            key += d + ";";
        auto it = programs.find(key);
        if (it == programs.end()) {
            gpu::ProgramDesc desc;
            desc.stages = stages;
            desc.defines = defines;
            it = programs.emplace(key, gpu::Program(desc)).first;
        }
        return it->second;
    }

    void draw(const GpuVoxelizer& self, double done, double share) {
        vao.bind();
        const std::size_t batch = std::max<std::size_t>(self.batchTriangles, 1);
        for (std::size_t first = 0; first < triangles; first += batch) {
            const std::size_t n = std::min(batch, triangles - first);
            glDrawArrays(GL_TRIANGLES, static_cast<GLint>(3 * first), static_cast<GLsizei>(3 * n));
            if (self.progress) {
                glFinish();
                self.progress(done + share * double(first + n) / double(triangles));
            }
        }
        glBindVertexArray(0);
    }

    static void allocWords(gpu::Buffer& buffer, std::size_t count) {
        if (!buffer || buffer.size() != count * 4) {
            buffer = gpu::Buffer();
            buffer.setStorage(count * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
        }
        const GLuint zero = 0;
        glClearNamedBufferData(buffer.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    }

    // Local slicing's range pass [Eisemann06 sec. 2.2]: per column min and max slice coordinate.
    void rangePass(const GpuVoxelizer& self, SliceMap& grid, bool conservative, double share);
    // One geometry pass of 1024 slices into 8 RGBA32UI targets, packed into `dst`.
    void slicePass(const GpuVoxelizer& self, const SliceMap& view, int pass, bool conservative,
                   bool solid, bool local, int axis, gpu::Buffer& dst, double done, double share);
    void setGridUniforms(const gpu::Program& p, const SliceMap& view) const {
        glProgramUniform3i(p.id(), p.uniformLocation("uGridSize"), view.width, view.height,
                           view.slices);
        p.set("uViewProj", glm::mat4(view.viewProj))
            .set("uViewport", glm::vec2(view.width, view.height))
            .set("uPerspective", view.perspective ? 1 : 0)
            .set("uNearFar", glm::vec2(view.nearPlane, view.farPlane));
    }
    // axis >= 0: one dominant-axis view of the three-axis method.
    std::vector<gpu::ShaderStage> rasterStages(bool conservative, int axis) const {
        std::vector<gpu::ShaderStage> s{{GL_VERTEX_SHADER, "voxelize/voxelize.vert"}};
        if (conservative || axis >= 0)
            s.push_back({GL_GEOMETRY_SHADER, "voxelize/conservative.geom"});
        s.push_back({GL_FRAGMENT_SHADER, "voxelize/voxelize.frag"});
        return s;
    }
    std::vector<std::string> rasterDefines(bool conservative, int axis = -1) const {
        std::vector<std::string> d;
        if (conservative || axis >= 0) d.push_back("CONSERVATIVE");
        if ((conservative || axis >= 0) && info.conservativeRaster) d.push_back("NV_CONSERVATIVE");
        if (axis >= 0) d.push_back("THREE_AXIS");
        return d;
    }
    // No depth test or writes, no culling, no blending; hardware conservative raster where
    // the driver has it and the method wants it.
    gpu::PipelineState rasterState(bool conservative, int width, int height) const {
        gpu::PipelineState s;
        s.view(width, height);
        s.depthWrite = false;
        s.conservativeRasterNV = conservative && info.conservativeRaster;
        return s;
    }
    // Back to GL's defaults (conservative raster and logic op off) for code that does not
    // declare its state.
    void restoreState() const {
        state.apply(gpu::PipelineState{});
        glUseProgram(0);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
};

GpuVoxelizer::GpuVoxelizer(const gpu::ContextInfo& info) : impl_(std::make_unique<Impl>()) {
    impl_->info = info;
}
GpuVoxelizer::~GpuVoxelizer() = default;

void GpuVoxelizer::upload(const Triangles& tris) {
    VEIL_CHECK(tris.count() > 0, "nothing to voxelize: no triangles");
    impl_->vertices = gpu::Buffer();
    impl_->vertices.setStorage(std::span<const glm::vec3>(tris.vertices), 0);
    impl_->vao = gpu::VertexArray();
    impl_->vao.attribute(VEIL_ATTR_POSITION, 0, impl_->vertices, 3, sizeof(glm::vec3));
    impl_->triangles = tris.count();
}

void GpuVoxelizer::Impl::rangePass(const GpuVoxelizer& self, SliceMap& grid, bool conservative,
                                   double share) {
    gpu::Texture tex(GL_TEXTURE_2D);
    tex.storage2D(1, GL_RG32F, grid.width, grid.height);
    gpu::Framebuffer fbo;
    fbo.attach(GL_COLOR_ATTACHMENT0, tex).drawBuffers({GL_COLOR_ATTACHMENT0});
    fbo.checkComplete("voxelize range pass");
    fbo.bind();
    gpu::PipelineState s = rasterState(conservative, grid.width, grid.height);
    state.invalidate();
    state.apply(s);
    const GLfloat big[4] = {1e30f, 1e30f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, big);
    s.blendAll(gpu::BlendState::func(GL_ONE, GL_ONE, GL_MIN));
    state.apply(s);
    std::vector<std::string> defines = rasterDefines(conservative);
    defines.push_back("DEPTH_PASS");
    const gpu::Program& p = program(rasterStages(conservative, -1), defines);
    setGridUniforms(p, grid);
    p.use();
    draw(self, 0.0, share);
    restoreState();
    // (min, -max) -> near, far for the CPU copy and the range SSBO (vec2 per column).
    std::vector<float> rg(static_cast<std::size_t>(grid.width) * grid.height * 2);
    glGetTextureImage(tex.id(), 0, GL_RG, GL_FLOAT, static_cast<GLsizei>(rg.size() * 4), rg.data());
    grid.nearDepth.resize(rg.size() / 2);
    grid.farDepth.resize(rg.size() / 2);
    for (std::size_t i = 0; i < rg.size() / 2; ++i) {
        grid.nearDepth[i] = rg[2 * i];
        grid.farDepth[i] = -rg[2 * i + 1];
        rg[2 * i + 1] = grid.farDepth[i];
    }
    range = gpu::Buffer();
    range.setStorage(std::span<const float>(rg), 0);
}

void GpuVoxelizer::Impl::slicePass(const GpuVoxelizer& self, const SliceMap& view, int pass,
                                   bool conservative, bool solid, bool local, int axis,
                                   gpu::Buffer& dst, double done, double share) {
    std::vector<gpu::Texture> targets;
    gpu::Framebuffer fbo;
    for (int t = 0; t < 8; ++t) {
        targets.emplace_back(GL_TEXTURE_2D);
        // Integer textures with the default linear filter are incomplete (texelFetch -> 0).
        targets.back()
            .storage2D(1, GL_RGBA32UI, view.width, view.height)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        fbo.attach(GL_COLOR_ATTACHMENT0 + t, targets.back());
    }
    fbo.drawBuffers({GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                     GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4, GL_COLOR_ATTACHMENT5,
                     GL_COLOR_ATTACHMENT6, GL_COLOR_ATTACHMENT7});
    fbo.checkComplete("voxelize slice pass");
    fbo.bind();
    gpu::PipelineState s = rasterState(conservative || axis >= 0, view.width, view.height);
    state.invalidate();
    state.apply(s);
    const GLuint zero[4] = {0, 0, 0, 0};
    for (int t = 0; t < 8; ++t)
        glClearBufferuiv(GL_COLOR, t, zero);
    // [Eisemann06 sec. 2]: OR of fragments' bit masks; solid: XOR toggles parity of crossings.
    s.logicOp = true;
    s.logicOpMode = solid ? GL_XOR : GL_OR;
    state.apply(s);
    std::vector<std::string> defines = rasterDefines(conservative, axis);
    if (solid) defines.push_back("SOLID");
    if (local) defines.push_back("LOCAL");
    const gpu::Program& p = program(rasterStages(conservative, axis), defines);
    setGridUniforms(p, view);
    p.set("uPass", pass).set("uAxis", axis);
    p.use();
    draw(self, done, share);
    restoreState();

    const gpu::Program& pack = program({{GL_COMPUTE_SHADER, "voxelize/pack.comp"}}, {});
    glProgramUniform3i(pack.id(), pack.uniformLocation("uGridSize"), view.width, view.height,
                       view.slices);
    pack.set("uPass", pass);
    for (int t = 0; t < 8; ++t)
        targets[t].bind(VEIL_TEX_VOX0 + t);
    dst.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_WORDS);
    pack.use();
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glDispatchCompute((view.width + 7) / 8, (view.height + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

void GpuVoxelizer::voxelize(SliceMap& grid, const VoxelizeOptions& options) {
    Impl& im = *impl_;
    VEIL_CHECK(im.triangles > 0, "voxelize: upload() triangles first");
    VEIL_CHECK(grid.width > 0 && grid.height > 0 && grid.slices > 0,
               "voxelize: grid size {}x{}x{} must be positive", grid.width, grid.height,
               grid.slices);
    const Method m = options.method;
    VEIL_CHECK(!options.local || m == Method::Raster || m == Method::Conservative,
               "local slicing works with the raster and conservative methods, not '{}'",
               methodName(m));
    VEIL_CHECK(!options.solid || m == Method::Raster,
               "solid voxelization needs the raster method, not '{}' (XOR parity needs exactly "
               "one crossing per surface and column centre)",
               methodName(m));
    VEIL_CHECK(!(m == Method::ThreeAxis || m == Method::Compute) || !grid.perspective,
               "the {} method needs an orthographic grid", methodName(m));
    grid.nearDepth.clear();
    grid.farDepth.clear();

    gpu::GpuTimer timer(im.info.softwareRenderer || im.info.timerQueryBits == 0
                            ? gpu::GpuTimer::Mode::CpuFinish
                            : gpu::GpuTimer::Mode::Query);
    timer.begin("voxelize");
    const std::size_t total =
        static_cast<std::size_t>(grid.width) * grid.height * grid.wordsPerColumn();
    Impl::allocWords(im.words, total);
    const bool conservative = m == Method::Conservative;
    const bool solid = options.solid;
    if (m == Method::Raster || m == Method::Conservative) {
        const int passes = (grid.slices + 1023) / 1024;
        const double share = 1.0 / (passes + (options.local ? 1 : 0));
        if (options.local) {
            im.rangePass(*this, grid, conservative, share);
        }
        gpu::Texture rangeTex{gpu::NoCreate};
        if (options.local) {
            rangeTex = gpu::Texture(GL_TEXTURE_2D);
            rangeTex.storage2D(1, GL_RG32F, grid.width, grid.height)
                .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
                .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            std::vector<float> rg(grid.nearDepth.size() * 2);
            for (std::size_t i = 0; i < grid.nearDepth.size(); ++i) {
                rg[2 * i] = grid.nearDepth[i];
                rg[2 * i + 1] = -grid.farDepth[i];
            }
            glTextureSubImage2D(rangeTex.id(), 0, 0, 0, grid.width, grid.height, GL_RG, GL_FLOAT,
                                rg.data());
            rangeTex.bind(VEIL_TEX_VOX_RANGE);
        }
        for (int p = 0; p < passes; ++p)
            im.slicePass(*this, grid, p, conservative, solid, options.local, -1, im.words,
                         share * (p + (options.local ? 1 : 0)), share);
        if (conservative)
            path_ = im.info.conservativeRaster
                        ? "conservative: GL_NV_conservative_raster + per-pixel depth range"
                        : "conservative: geometry-shader dilation (no "
                          "GL_NV_conservative_raster) + per-pixel depth range";
        else
            path_ = "raster: one slice per pixel centre [Eisemann06]";
        path_ += fmt::format(", {} geometry pass{}", passes, passes > 1 ? "es" : "");
        if (options.local) path_ += ", local slicing (min/max range pass)";
        if (solid) path_ += ", solid (XOR)";
    } else if (m == Method::ThreeAxis) {
        for (int axis = 0; axis < 3; ++axis) {
            const SliceMap view = axisView(grid, axis);
            gpu::Buffer& dst = axis == 2 ? im.words : im.axisWords[axis];
            if (axis < 2)
                Impl::allocWords(dst, static_cast<std::size_t>(view.width) * view.height *
                                          view.wordsPerColumn());
            const int passes = (view.slices + 1023) / 1024;
            for (int p = 0; p < passes; ++p)
                im.slicePass(*this, view, p, false, false, false, axis, dst,
                             (axis + double(p) / passes) / 3.0, 1.0 / (3.0 * passes));
        }
        const gpu::Program& merge =
            im.program({{GL_COMPUTE_SHADER, "voxelize/merge_axes.comp"}}, {});
        glProgramUniform3i(merge.id(), merge.uniformLocation("uGridSize"), grid.width, grid.height,
                           grid.slices);
        im.words.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_WORDS);
        im.axisWords[0].bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_AXIS0);
        im.axisWords[1].bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_AXIS0 + 1);
        merge.use();
        glDispatchCompute(static_cast<GLuint>((total + 63) / 64), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        glUseProgram(0);
        path_ = fmt::format("three-axis: dominant-axis geometry-shader selection, {} + "
                            "diamond test (6-separating), 3 views, compute merge",
                            im.info.conservativeRaster ? "GL_NV_conservative_raster"
                                                       : "geometry-shader dilation");
    } else {
        glm::dvec3 lo, hi;
        gridBounds(grid, lo, hi);
        const glm::dvec3 voxel = (hi - lo) / glm::dvec3(grid.width, grid.height, grid.slices);
        // Pre-pass: tiles per triangle (same bounds as the voxelizing pass), scanned here.
        const gpu::Program& count =
            im.program({{GL_COMPUTE_SHADER, "voxelize/compute.comp"}}, {"COUNT_TILES"});
        const gpu::Program& p = im.program({{GL_COMPUTE_SHADER, "voxelize/compute.comp"}}, {});
        gpu::Buffer tileStart;
        tileStart.setStorage((im.triangles + 1) * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
        im.words.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_WORDS);
        im.vertices.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_TRIS);
        tileStart.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_TRIS + 1);
        const auto dispatch = [&](const gpu::Program& prog, std::uint64_t items, bool report) {
            glProgramUniform3i(prog.id(), prog.uniformLocation("uGridSize"), grid.width,
                               grid.height, grid.slices);
            prog.set("uGridLo", glm::vec3(lo))
                .set("uVoxel", glm::vec3(voxel))
                .set("uTriangleCount", static_cast<unsigned>(im.triangles));
            prog.use();
            const std::uint64_t batch = 65535u * 64u;
            for (std::uint64_t first = 0; first < items; first += batch) {
                const std::uint64_t n = std::min(batch, items - first);
                prog.set("uItemOffset", static_cast<unsigned>(first))
                    .set("uItemCount", static_cast<unsigned>(n));
                glDispatchCompute(static_cast<GLuint>((n + 63) / 64), 1, 1);
                if (report && progress) {
                    glFinish();
                    progress(double(first + n) / double(items));
                }
            }
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        };
        dispatch(count, im.triangles, false);
        std::vector<std::uint32_t> starts(im.triangles + 1, 0);
        glGetNamedBufferSubData(tileStart.id(), 0, static_cast<GLsizeiptr>(im.triangles * 4),
                                starts.data());
        std::uint64_t items = 0;
        for (std::size_t t = 0; t <= im.triangles; ++t) {
            const std::uint64_t c = t < im.triangles ? starts[t] : 0;
            starts[t] = static_cast<std::uint32_t>(items);
            items += c;
        }
        VEIL_CHECK(items < (1ull << 32), "compute voxelization: {} tiles exceed 2^32", items);
        tileStart.setSubData(0, starts.size() * 4, starts.data());
        dispatch(p, items, true);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        glUseProgram(0);
        path_ = "compute: one thread per (triangle, 4x4x32 tile), plane + 2D edge tests "
                "(Schwarz-Seidel), "
                "atomicOr";
    }
    timer.end();
    for (const auto& t : timer.collect())
        milliseconds_ = t.milliseconds;
    grid.words.resize(total);
    glGetNamedBufferSubData(im.words.id(), 0, static_cast<GLsizeiptr>(total * 4),
                            grid.words.data());
}

void GpuVoxelizer::bindSliceMap(const gpu::Program& program, const SliceMap& grid) const {
    impl_->words.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_WORDS);
    if (impl_->range) impl_->range.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_VOX_RANGE);
    glProgramUniform3i(program.id(), program.uniformLocation("uSmSize"), grid.width, grid.height,
                       grid.slices);
    program.set("uSmViewProj", glm::mat4(grid.viewProj))
        .set("uSmPerspective", grid.perspective ? 1 : 0)
        .set("uSmNearFar", glm::vec2(grid.nearPlane, grid.farPlane))
        .set("uSmLocal", grid.local() ? 1 : 0);
}

} // namespace veil::voxelize
