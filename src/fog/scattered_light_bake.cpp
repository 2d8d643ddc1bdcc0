#include "fog/scattered_light_bake.h"

#include "base/error.h"

#include "shaders/common/bindings.h"
#include "shaders/volume/cache_bake.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace veil::volume {

namespace {

gpu::Texture makeCacheTexture(const glm::ivec3& dims) {
    gpu::Texture t(GL_TEXTURE_3D);
    t.storage3D(1, GL_RGBA32F, dims.x, dims.y, dims.z)
        .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
        .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE)
        .parameter(GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearTexImage(t.id(), 0, GL_RGBA, GL_FLOAT, zero);
    return t;
}

// The light types of cache_bake.comp.
int lightTypeCode(scene::LightType type) {
    switch (type) {
    case scene::LightType::Directional:
        return 0;
    case scene::LightType::Point:
        return 1;
    case scene::LightType::Spot:
        return 2;
    }
    return 0;
}

} // namespace

ScatteredLightBake::ScatteredLightBake(gpu::ProgramManager& programs,
                                       std::vector<std::string> defines,
                                       std::function<void(const gpu::Program&)> bindVolumes)
    : programs_(programs), bindVolumes_(std::move(bindVolumes)) {
    program_ =
        programs_.add(gpu::ProgramDesc::compute("volume/cache_bake.comp", std::move(defines)));
}

void ScatteredLightBake::start(const scene::Scene& scene, const Setup& setup) {
    VEIL_CHECK(glm::all(glm::greaterThan(setup.dims, glm::ivec3(0))) && setup.samples > 0,
               "scattered-light cache: empty grid or no samples");
    VEIL_CHECK(glm::all(glm::greaterThan(setup.majorantDims, glm::ivec3(0))) &&
                   setup.majorants.size() == std::size_t(setup.majorantDims.x) *
                                                 setup.majorantDims.y * setup.majorantDims.z,
               "scattered-light cache: the majorant grid does not match its size");
    VEIL_CHECK(scene.lights.size() <= VEIL_CACHE_MAX_LIGHTS,
               "scattered-light cache: the GPU bake takes at most {} lights ({} in the scene)",
               VEIL_CACHE_MAX_LIGHTS, scene.lights.size());
    const bool sameGrid = mean_ && setup.dims == setup_.dims;
    scene_ = &scene;
    setup_ = setup;
    cells_ = std::size_t(setup.dims.x) * setup.dims.y * setup.dims.z;
    if (!sameGrid) {
        mean_ = makeCacheTexture(setup.dims);
        flux_ = makeCacheTexture(setup.dims);
        accumulator_ = gpu::Buffer();
        accumulator_.setStorage(cells_ * 2 * sizeof(glm::vec4), nullptr, 0);
    }
    if (!majorants_ || majorants_.width() != setup.majorantDims.x ||
        majorants_.height() != setup.majorantDims.y || majorants_.depth() != setup.majorantDims.z) {
        majorants_ = gpu::Texture(GL_TEXTURE_3D);
        majorants_
            .storage3D(1, GL_R32F, setup.majorantDims.x, setup.majorantDims.y, setup.majorantDims.z)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(majorants_.id(), 0, 0, 0, 0, setup.majorantDims.x, setup.majorantDims.y,
                        setup.majorantDims.z, GL_RED, GL_FLOAT, setup.majorants.data());
    if (setup_.surfaceSamples <= setup_.samples) setup_.surfaceTexels.clear();
    // The surface pass's texel list (a word where there is none: the program's buffer is bound).
    const std::vector<std::uint32_t> none{0};
    const std::vector<std::uint32_t>& list =
        setup_.surfaceTexels.empty() ? none : setup_.surfaceTexels;
    texels_ = gpu::Buffer();
    texels_.setStorage(list.size() * sizeof(std::uint32_t), list.data(), 0);
    next_ = {};
}

double ScatteredLightBake::fraction() const {
    if (setup_.samples <= 0 || cells_ == 0) return 0.0;
    const double listed = double(setup_.surfaceTexels.size());
    const double all = double(setup_.samples) * double(cells_) +
                       double(setup_.surfaceSamples - setup_.samples) * listed;
    double done = double(next_.sampleBegin) * double(passCells()) +
                  double(next_.sampleEnd - next_.sampleBegin) * double(next_.cellBegin);
    if (next_.pass == 1)
        done += double(setup_.samples) * double(cells_) - double(setup_.samples) * listed;
    return std::min(1.0, done / all);
}

void ScatteredLightBake::dispatch(int cellBegin, int cellCount, int sampleBegin, int sampleEnd) {
    const gpu::Program& p = programs_.get(program_);
    bindVolumes_(p);
    const scene::Scene& s = *scene_;
    p.set("dims", setup_.dims)
        .set("boxLo", glm::vec3(setup_.lo))
        .set("boxHi", glm::vec3(setup_.hi))
        .set("cellBegin", cellBegin)
        .set("cellCount", cellCount)
        .set("texelList", next_.pass)
        .set("sampleBegin", sampleBegin)
        .set("sampleEnd", sampleEnd)
        .set("seed", unsigned(setup_.seed))
        .set("majorantDims", setup_.majorantDims)
        // The R16F texels round up to 2^-11 of the grid's values.
        .set("majorantScale", 1.001f)
        .set("ambient", s.render.ambient)
        .set("maxBounces", setup_.maxBounces)
        .set("rouletteDepth", setup_.rouletteDepth)
        .set("lightCount", int(s.lights.size()));
    for (std::size_t l = 0; l < s.lights.size(); ++l) {
        const scene::Light& light = s.lights[l];
        const auto name = [l](const char* n) { return fmt::format("{}[{}]", n, l); };
        const glm::vec3 dir = glm::length(light.direction) > 0.0f ? glm::normalize(light.direction)
                                                                  : glm::vec3(0.0f, -1.0f, 0.0f);
        p.set(name("lightType").c_str(), lightTypeCode(light.type))
            .set(name("lightRadiance").c_str(), light.color * light.intensity)
            .set(name("lightPosition").c_str(), light.position)
            .set(name("lightDirection").c_str(), dir)
            .set(name("lightCone").c_str(),
                 glm::vec2(std::cos(glm::radians(double(light.outerConeDegrees))),
                           std::cos(glm::radians(double(light.innerConeDegrees)))));
    }
    p.use();
    majorants_.bind(VEIL_TEX_CACHE_MAJORANT);
    accumulator_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_CACHE_BAKE);
    texels_.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_CACHE_TEXELS);
    glBindImageTexture(VEIL_IMG_CACHE_MEAN, mean_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(VEIL_IMG_CACHE_FLUX, flux_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(GLuint((cellCount + VEIL_CACHE_BAKE_GROUP - 1) / VEIL_CACHE_BAKE_GROUP), 1,
                      1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
    ++dispatches_;
}

bool ScatteredLightBake::step(double budgetMs, int batch) {
    VEIL_CHECK(scene_, "scattered-light cache: step() before start()");
    using Clock = std::chrono::steady_clock;
    const auto begin = Clock::now();
    // Each dispatch aims at this much time (a progress update, and well below a driver's
    // watchdog), within the budget.
    const double target = std::clamp(budgetMs, 0.5, 100.0);
    batch = std::max(1, batch);
    while (!done()) {
        const std::size_t cells = passCells();
        const std::size_t minCells = std::min(cells, kMinDispatchCells);
        // Texel-samples the target allows (0: unknown before the first dispatch).
        const double work = cellSamplesPerMs_ * target;
        if (next_.cellBegin == 0) {
            const double k = std::clamp(std::floor(work / double(cells)), 1.0, double(batch));
            next_.sampleEnd = std::min(passSamples(), next_.sampleBegin + int(k));
        }
        const int samples = next_.sampleEnd - next_.sampleBegin;
        const std::size_t left = cells - next_.cellBegin;
        std::size_t count = work > 0.0 ? std::size_t(work / samples) : minCells;
        count = std::max(count, minCells);
        count = std::min(left, (count + VEIL_CACHE_BAKE_GROUP - 1) / VEIL_CACHE_BAKE_GROUP *
                                   VEIL_CACHE_BAKE_GROUP);
        const auto t0 = Clock::now();
        dispatch(int(next_.cellBegin), int(count), next_.sampleBegin, next_.sampleEnd);
        glFinish();
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        // Only a dispatch that fills the GPU tells its throughput (the tail of a pass may not,
        // nor a surface pass over fewer texels than a full dispatch).
        if (count >= minCells && (next_.pass == 0 || count >= kMinDispatchCells))
            cellSamplesPerMs_ = double(count) * samples / std::max(ms, 1e-3);
        next_.cellBegin += count;
        if (next_.cellBegin >= cells) {
            next_.cellBegin = 0;
            next_.sampleBegin = next_.sampleEnd;
            // Every texel has its samples: the surface texels go on to theirs.
            if (next_.pass == 0 && next_.sampleBegin >= setup_.samples &&
                !setup_.surfaceTexels.empty())
                next_.pass = 1;
        }
        if (std::chrono::duration<double, std::milli>(Clock::now() - begin).count() >= budgetMs)
            break;
    }
    return done();
}

ScatteredLight ScatteredLightBake::read() const {
    ScatteredLight out;
    out.lo = setup_.lo;
    out.hi = setup_.hi;
    out.dims = setup_.dims;
    out.samples = next_.pass == 0 ? next_.sampleBegin : setup_.samples;
    out.mean.resize(cells_);
    out.flux.resize(cells_);
    const GLsizei bytes = GLsizei(cells_ * sizeof(glm::vec4));
    glGetTextureImage(mean_.id(), 0, GL_RGBA, GL_FLOAT, bytes, out.mean.data());
    glGetTextureImage(flux_.id(), 0, GL_RGBA, GL_FLOAT, bytes, out.flux.data());
    return out;
}

std::vector<double> ScatteredLightBake::luminanceVariance() const {
    std::vector<glm::vec4> acc(cells_ * 2);
    glGetNamedBufferSubData(accumulator_.id(), 0, GLsizeiptr(acc.size() * sizeof(glm::vec4)),
                            acc.data());
    // Samples per texel (of a pass in flight, those of its finished rounds).
    std::vector<double> samples(cells_, next_.pass == 0 ? next_.sampleBegin : setup_.samples);
    if (next_.pass == 1)
        for (std::uint32_t t : setup_.surfaceTexels)
            samples[t] = next_.sampleBegin;
    const glm::dvec3 lum(0.2126, 0.7152, 0.0722);
    std::vector<double> var(cells_, 0.0);
    for (std::size_t i = 0; i < cells_; ++i) {
        const double n = samples[i];
        if (n < 2) continue;
        const double mean = glm::dot(glm::dvec3(acc[2 * i]), lum) / n;
        var[i] = std::max(0.0, (double(acc[2 * i].w) / n - mean * mean) * n / (n - 1.0));
    }
    return var;
}

} // namespace veil::volume
