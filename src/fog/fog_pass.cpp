#include "fog/fog_pass.h"

#include "base/error.h"
#include "base/log.h"
#include "fog/gpu_volume.h"
#include "fog/scattered_light_cache.h"
#include "grid/density_grid.h"
#include "grid/grid_preload.h"
#include "integrators/blackbody.h"
#include "shaders/common/bindings.h"

#include <openvdb/tools/GridTransformer.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace veil::volume {

namespace {

// The blackbody table of fog_medium.glsl (blackbody.h: colour and ln Y, linear in T).
constexpr int kBlackbodyEntries = 2048;
constexpr double kBlackbodyMaxKelvin = 25000.0;

// An emission grid may reach past the density's active voxels: the density's topology is
// widened to it (resampled to the density's transform where the two differ), so the
// texture's leaves hold both.
openvdb::FloatGrid::Ptr widenedToEmission(const openvdb::FloatGrid& density,
                                          const std::vector<openvdb::FloatGrid::Ptr>& emission) {
    openvdb::FloatGrid::Ptr widened = density.deepCopy();
    for (const auto& e : emission) {
        if (e->transform() == density.transform()) {
            widened->topologyUnion(*e);
        } else {
            openvdb::FloatGrid::Ptr resampled = openvdb::FloatGrid::create(0.0f);
            resampled->setTransform(density.transform().copy());
            openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*e, *resampled);
            widened->topologyUnion(*resampled);
        }
    }
    return widened;
}

} // namespace

FogPass::FogPass(const scene::Scene& scene, gpu::ProgramManager& programs,
                 const gpu::IncludeAliases& lightVisibility)
    : scene_(scene), programs_(programs), lightVisibility_(lightVisibility) {
    divisor_ = scene.render.fogResolution;
    GpuVolumeOptions options;
    options.budgetBytes = std::size_t(scene.render.volumeBudgetMiB) << 20;
    options.refuseOverBudget = scene.render.volumeOverBudget == "refuse";
    options.neighbourhood = scene.render.fogOctaveRadius > 0.0f && scene.render.fogOctaves > 1;
    std::size_t used = 0;
    std::vector<openvdb::FloatGrid::ConstPtr> densities; // the scattered-light cache's input
    const std::string source =
        scene.sourcePath.empty() ? std::string("<scene>") : scene.sourcePath.string();
    for (std::size_t i = 0; i < scene.volumes.size(); ++i) {
        const scene::VolumeRef& ref = scene.volumes[i];
        // The grid's own limits (index range, budget, coarsening) name the file and the JSON
        // path of the volume, not only the grid.
        const std::string where =
            ref.path.empty()
                ? fmt::format("{}: /volumes/{} (procedural '{}')", source, i, ref.procedural)
                : fmt::format("{}: /volumes/{} ('{}')", source, i, ref.path.string());
        if (ref.procedural == "homogeneous") {
            // Global fog: densities, albedos and phase functions add up per unit length.
            globalAlbedo_ = (globalAlbedo_ * globalDensity_ + ref.albedo * ref.densityScale) /
                            std::max(globalDensity_ + ref.densityScale, 1e-20f);
            globalAnisotropy_ = ref.anisotropy;
            globalDensity_ += ref.densityScale;
            continue;
        }
        VEIL_CHECK(volumes_.size() < VEIL_MAX_VOLUMES,
                   "{}: at most {} grid volumes per scene (volume '{}')", where, VEIL_MAX_VOLUMES,
                   ref.name);
        options.budgetBytes = std::size_t(scene.render.volumeBudgetMiB) << 20;
        options.budgetBytes = options.budgetBytes > used ? options.budgetBytes - used : 0;
        // Converted ahead on a worker thread (grid_preload.h) when the options match.
        GLint max3D = 0;
        glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
        std::vector<openvdb::FloatGrid::Ptr> channel;
        try {
            channel = loadEmissionChannel(ref);
        } catch (const Error& e) {
            throw Error(fmt::format("{}: {}", where, e.what()));
        }
        const auto converted = ref.path.empty() || !channel.empty()
                                   ? nullptr
                                   : findPreconverted(ref.path, ref.grid, options, max3D);
        openvdb::FloatGrid::Ptr grid = converted ? nullptr : loadVolume(ref);
        std::unique_ptr<GpuVolume> gpuVolume;
        try {
            if (!channel.empty()) {
                // Density and emission channel: two textures of one layout, planned within
                // 1/2 of the budget left (1/5 for an RGBA16F colour; the indirection table is
                // counted with each).
                if (!ref.emissionGrid.empty()) grid = widenedToEmission(*grid, channel);
                GpuVolumeOptions part = options;
                part.budgetBytes /= channel.size() == 1 ? 2 : 5;
                GridConversion c = convertGrid(*grid, part, max3D);
                addChannel(c, channel);
                gpuVolume = std::make_unique<GpuVolume>(c, ref.transform);
                emissive_ = true;
            } else {
                gpuVolume = converted ? std::make_unique<GpuVolume>(*converted, ref.transform)
                                      : std::make_unique<GpuVolume>(grid, ref.transform, options);
            }
        } catch (const Error& e) {
            throw Error(fmt::format("{}: {}", where, e.what()));
        }
        if (scene.render.fogScatteredLight) densities.push_back(grid ? grid : loadVolume(ref));
        Entry e{
            .ref = &ref, .gpu = std::move(gpuVolume), .source = ref.path, .sourceGrid = ref.grid};
        used += e.gpu->stats().gpuBytes;
        log::info("volume '{}': {} active voxels, {} ({} bricks), {:.2f} MiB on the GPU, grid "
                  "{:.2f} MiB",
                  ref.name, e.gpu->stats().activeVoxels, e.gpu->stats().dense ? "dense" : "atlas",
                  e.gpu->stats().bricks, e.gpu->stats().gpuBytes / 1048576.0,
                  e.gpu->stats().gridBytes / 1048576.0);
        volumes_.push_back(std::move(e));
    }
    if (!active()) return;
    if (scene.render.fogScatteredLight) {
        VEIL_CHECK(scene.render.fogOctaves == 1,
                   "{}: render.fog_scattered_light and render.fog_octaves {} both add multiple "
                   "scattering: set fog_octaves to 1",
                   source, scene.render.fogOctaves);
        VEIL_CHECK(globalDensity_ == 0.0f && !volumes_.empty(),
                   "{}: render.fog_scattered_light needs grid volumes and no homogeneous fog (the "
                   "path tracer that bakes it has no fog filling all space)",
                   source);
        // The GPU bake samples the density textures as the marcher does.
        ScatteredLightGpu gpu{&programs_, {slotsDefine()}, [this](const gpu::Program& p) {
                                  setVolumeUniforms(p);
                                  p.set("blackbodyMaxKelvin", float(kBlackbodyMaxKelvin));
                                  if (blackbody_) blackbody_.bind(VEIL_TEX_BLACKBODY);
                              }};
        if (emissive_) gpu.defines.push_back("VEIL_VOLUME_EMISSION 1");
        for (const auto& e : volumes_)
            gpu.coarsened = std::max(gpu.coarsened, e.gpu->stats().coarsened);
        scattered_ =
            std::make_unique<ScatteredLightCache>(scene, std::move(densities), std::move(gpu));
    }
    for (std::size_t i = 0; i < scene.lights.size() && i < VEIL_MAX_LIGHTS; ++i)
        if (scene.lights[i].castShadows) {
            primaryLight_ = static_cast<int>(i);
            break;
        }
    if (primaryLight_ < 0 && !scene.lights.empty()) primaryLight_ = 0;
    if (emissive_) {
        const std::vector<glm::vec4> table = blackbodyTable(kBlackbodyEntries, kBlackbodyMaxKelvin);
        blackbody_ = gpu::Texture(GL_TEXTURE_1D);
        glTextureStorage1D(blackbody_.id(), 1, GL_RGBA32F, kBlackbodyEntries);
        blackbody_.parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
            .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureSubImage1D(blackbody_.id(), 0, 0, kBlackbodyEntries, GL_RGBA, GL_FLOAT,
                            table.data());
    }
    marchProgram_ = programs_.add(
        gpu::ProgramDesc::compute("volume/fog_march.comp", marchDefines(), lightVisibility));
    lightProgram_ = programs_.add(
        gpu::ProgramDesc::compute("volume/light_transmittance.comp", {slotsDefine()}));
    for (auto& e : volumes_)
        fitLightVolume(e);
    emptyVao_ = gpu::VertexArray();
}

void FogPass::fitLightVolume(Entry& e) {
    // Light transmittance volumes: about 2 voxels per texel, at most 128 per axis.
    glm::vec3 lo, hi;
    e.gpu->worldBounds(lo, hi);
    const glm::vec3 extent = hi - lo;
    const glm::ivec3 dims = glm::clamp(glm::ivec3(glm::ceil(extent / (2.0f * e.gpu->voxelSize()))),
                                       glm::ivec3(4), glm::ivec3(128));
    if (!e.light || e.light.width() != dims.x || e.light.height() != dims.y ||
        e.light.depth() != dims.z) {
        e.light = gpu::Texture(GL_TEXTURE_3D);
        e.light.storage3D(1, GL_R32F, dims.x, dims.y, dims.z)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_LINEAR)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_LINEAR)
            .parameter(GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE)
            .parameter(GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE)
            .parameter(GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    }
    e.lightToWorld = glm::translate(glm::mat4(1.0f), lo) * glm::scale(glm::mat4(1.0f), extent);
}

void FogPass::replaceVolume(std::size_t i, const GridConversion& converted) {
    VEIL_CHECK(i < volumes_.size(), "fog: no grid volume {} to replace ({} volumes)", i,
               volumes_.size());
    Entry& e = volumes_[i];
    VEIL_CHECK(converted.channelComponents == e.gpu->channelComponents() &&
                   converted.neighbourhood.mean.empty() == !e.gpu->neighbourhood(),
               "fog: volume '{}' replaced by a conversion of another kind (emission channel "
               "or neighbourhood differ)",
               e.ref->name);
    e.gpu->replace(converted, e.ref->transform);
    fitLightVolume(e);
    invalidateLightVolumes();
    // The scattered-light cache bakes again only for another file or grid (a static volume
    // under a moving camera keeps it); the grid comes from the frame's read-ahead
    // (PreloadedGridScope) where there is one.
    if (scattered_ && (e.ref->path != e.source || e.ref->grid != e.sourceGrid)) {
        int coarsened = 0;
        for (const auto& v : volumes_)
            coarsened = std::max(coarsened, v.gpu->stats().coarsened);
        scattered_->replaceGrid(i, loadVolume(*e.ref), coarsened);
        e.source = e.ref->path;
        e.sourceGrid = e.ref->grid;
    }
}

FogPass::~FogPass() = default;

std::vector<GpuVolumeStats> FogPass::stats() const {
    std::vector<GpuVolumeStats> s;
    for (const auto& e : volumes_)
        s.push_back(e.gpu->stats());
    return s;
}

std::size_t FogPass::gpuBytes() const {
    std::size_t bytes = 0;
    for (const auto& e : volumes_)
        bytes += e.gpu->stats().gpuBytes +
                 std::size_t(e.light.width()) * e.light.height() * e.light.depth() * 4;
    return bytes + std::size_t(width_) * height_ * 16 + (emissive_ ? kBlackbodyEntries * 16 : 0);
}

std::vector<pass::Pass> FogPass::passes(int slabTexels) {
    pass::Pass fog{"fog",
                   {"depth"},
                   {"fog.light_transmittance", "fog.radiance"},
                   [this](const pass::Context& context) { march(context); }};
    fog.scope = pass::Scope::Pixels;
    fog.receivesShadows = true;
    fog.prepareStep = [this, slabTexels](const pass::Context& context) {
        return updateLightVolumesSlab(context, slabTexels);
    };
    fog.prepareName = "fog.light_transmittance";
    return {std::move(fog)};
}

void FogPass::addResources(pass::Resources& resources) const {
    resources.add("fog.radiance", [this] { return perPixelMarchRuns() ? &radiance_ : nullptr; });
    resources.add("fog.light_transmittance", [this] { return lightTransmittanceTexture(0); });
}

void FogPass::resize(int width, int height) {
    width_ = (width + divisor_ - 1) / divisor_;
    height_ = (height + divisor_ - 1) / divisor_;
    for (gpu::Texture* t : {&radiance_, &transmittance_}) {
        *t = gpu::Texture(GL_TEXTURE_2D);
        t->storage2D(1, GL_RGBA16F, width_, height_)
            .parameter(GL_TEXTURE_MIN_FILTER, GL_NEAREST)
            .parameter(GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
}

void FogPass::setVolumeUniforms(const gpu::Program& program) const {
    program.set("volumeCount", static_cast<int>(volumes_.size()));
    for (std::size_t i = 0; i < volumes_.size(); ++i) {
        const Entry& e = volumes_[i];
        auto name = [i](const char* member) { return fmt::format("volumes[{}].{}", i, member); };
        program.set(name("worldToIndex").c_str(), e.gpu->worldToIndex())
            .set(name("worldToLight").c_str(), glm::inverse(e.lightToWorld))
            .set(name("indexMin").c_str(), e.gpu->indexMin())
            .set(name("indexMax").c_str(), e.gpu->indexMax())
            .set(name("leafOrigin").c_str(), e.gpu->leafOrigin())
            .set(name("bricksPerAxis").c_str(), e.gpu->bricksPerAxis())
            .set(name("cellOrigin").c_str(), e.gpu->neighbourhoodOrigin())
            .set(name("densityScale").c_str(), e.ref->densityScale)
            .set(name("albedo").c_str(), e.ref->albedo)
            .set(name("anisotropy").c_str(), e.ref->anisotropy)
            .set(name("emission").c_str(), e.ref->emission)
            .set(name("emissionMode").c_str(), emissionMode(e))
            .set(name("temperature").c_str(),
                 glm::vec3(e.ref->temperatureScale, e.ref->temperatureOffset,
                           e.ref->temperatureIntensity * e.ref->densityScale));
        e.gpu->data().bind(VEIL_TEX_VOLUME_DATA + static_cast<GLuint>(i));
        if (e.gpu->channel()) e.gpu->channel().bind(VEIL_TEX_VOLUME_EMISSION + GLuint(i));
        if (e.gpu->indirection()) e.gpu->indirection().bind(VEIL_TEX_VOLUME_TABLE + GLuint(i));
        e.light.bind(VEIL_TEX_VOLUME_LIGHT + static_cast<GLuint>(i));
        if (e.gpu->neighbourhood())
            e.gpu->neighbourhood().bind(VEIL_TEX_VOLUME_NEIGHBOURHOOD + GLuint(i));
    }
}

void FogPass::march(const pass::Context& targets) {
    if (!active()) return;
    updateLightVolumes(targets);
    // 2. March (not needed beside the piecewise march, perPixelMarchRuns()).
    if (!perPixelMarchRuns()) return;
    ++perPixelMarches_;
    const gpu::Program& mp = programs_.get(marchProgram_);
    setMarchUniforms(mp, targets);
    // The region in fog texels: those the upsampling of the region's pixels reads
    // (fog_contribution.glsl: the 4 texels around (p + 0.5) / divisor - 0.5, so for pixels
    // [x0, x1) texels floor(x0 / divisor) - 1 to ceil(x1 / divisor), clamped; each texel is
    // marched on its own, so a region's texels equal the whole march's).
    glm::ivec4 r(0, 0, width_, height_);
    if (targets.region.z > 0) {
        const int grow = divisor_ > 1 ? 1 : 0;
        r = glm::ivec4(std::max(0, targets.region.x / divisor_ - grow),
                       std::max(0, targets.region.y / divisor_ - grow),
                       std::min(width_, (targets.region.z + divisor_ - 1) / divisor_ + grow),
                       std::min(height_, (targets.region.w + divisor_ - 1) / divisor_ + grow));
    }
    mp.set("resolutionDivisor", divisor_).set("marchRegion", r);
    mp.use();
    glBindImageTexture(VEIL_IMG_FOG_RADIANCE, radiance_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                       GL_RGBA16F);
    glBindImageTexture(VEIL_IMG_FOG_TRANSMITTANCE, transmittance_.id(), 0, GL_FALSE, 0,
                       GL_WRITE_ONLY, GL_RGBA16F);
    glDispatchCompute((r.z - r.x + 7) / 8, (r.w - r.y + 7) / 8, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

bool FogPass::lightVolumesStale(const pass::Context& targets, glm::vec4& key) {
    if (targets.width != width_ * divisor_ || targets.height != height_ * divisor_ || !radiance_)
        resize(targets.width, targets.height);
    // 1. Transmittance toward the primary light through all volumes (self-shadowing).
    const scene::Light* light =
        primaryLight_ >= 0 ? &scene_.lights[static_cast<std::size_t>(primaryLight_)] : nullptr;
    const bool directional = light && light->type == scene::LightType::Directional;
    key = light ? glm::vec4(directional ? glm::normalize(light->direction) : light->position,
                            directional ? float(VEIL_LIGHT_DIRECTIONAL) : float(VEIL_LIGHT_SPOT))
                : glm::vec4(0.0f);
    return selfShadowing_ && light && !volumes_.empty() && (!lightValid_ || key != lightKey_);
}

void FogPass::updateLightVolumes(const pass::Context& targets) {
    while (updateLightVolumesSlab(targets, std::numeric_limits<int>::max())) {
    }
}

void FogPass::prepareScatteredLight() {
    if (scattered_) scattered_->ensure();
}

void FogPass::setScatteredLightBudgetMs(double ms) {
    if (scattered_) scattered_->setBudgetMs(ms);
}

double FogPass::scatteredLightBakeMs() const {
    return scattered_ && scattered_->bakes() > 0 ? scattered_->lastBakeSeconds() * 1e3 : -1.0;
}

bool FogPass::updateLightVolumesSlab(const pass::Context& targets, int slabTexels) {
    // Bakes again after a light or volume edit (a progressive bake in flight steps once per
    // frame, in prepareScatteredLight()).
    if (scattered_ && !scattered_->converging()) scattered_->ensure();
    glm::vec4 key;
    if (!active() || !lightVolumesStale(targets, key)) return false;
    if (!slab_.started || slab_.key != key) slab_ = {true, key, 0, 0};
    const Entry& e = volumes_[slab_.volume];
    const gpu::Program& lp = programs_.get(lightProgram_);
    setVolumeUniforms(lp);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const auto& v : volumes_) {
        glm::vec3 a, b;
        v.gpu->worldBounds(a, b);
        lo = glm::min(lo, a);
        hi = glm::max(hi, b);
    }
    // Each texel's value depends on its own coordinate only: a slab's texels come out as in
    // the volume computed in one piece.
    const int z0 = slab_.z, z1 = z0 + std::min(slabTexels, e.light.depth() - z0);
    lp.set("lightPositionType", key)
        .set("steps", 64)
        .set("maxDistance", glm::length(hi - lo))
        .set("lightToWorld", e.lightToWorld)
        .set("zRange", glm::ivec2(z0, z1));
    lp.use();
    glBindImageTexture(VEIL_IMG_VOLUME_LIGHT, e.light.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R32F);
    glDispatchCompute((e.light.width() + 3) / 4, (e.light.height() + 3) / 4, (z1 - z0 + 3) / 4);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    ++lightSlabs_;
    slab_.z = z1;
    if (slab_.z >= e.light.depth()) {
        slab_.z = 0;
        if (++slab_.volume == volumes_.size()) {
            slab_ = {};
            lightKey_ = key;
            lightValid_ = true;
        }
    }
    return true;
}

int FogPass::emissionMode(const Entry& e) {
    // fog_medium.glsl volumeEmitted(): 0 emission x density, 1 scalar emission grid,
    // 2 temperature grid, 3 colour emission grid.
    if (!e.gpu->channel()) return 0;
    if (!e.ref->temperatureGrid.empty()) return 2;
    return e.gpu->channelComponents() == 1 ? 1 : 3;
}

std::vector<std::string> FogPass::marchDefines() const {
    std::vector<std::string> defines{slotsDefine()};
    if (emissive_) defines.push_back("VEIL_VOLUME_EMISSION 1"); // fog_medium.glsl
    if (scattered_) defines.push_back("VEIL_SCATTERED_LIGHT 1");
    // Depth-aware octaves (fog_medium.glsl): the neighbourhood textures are sampled.
    if (scene_.render.fogOctaveRadius > 0.0f && scene_.render.fogOctaves > 1 && !volumes_.empty())
        defines.push_back("VEIL_OCTAVE_RADIUS 1");
    return defines;
}

std::string FogPass::slotsDefine() const {
    // Sampler arrays of exactly the scene's grid volumes (volume_common.glsl).
    return fmt::format("VEIL_VOLUME_SLOTS {}", std::max<std::size_t>(1, volumes_.size()));
}

void FogPass::setMarchUniforms(const gpu::Program& program, const pass::Context& targets) const {
    setVolumeUniforms(program);
    program.set("invViewProjection", glm::inverse(targets.viewProjection))
        .set("steps", scene_.render.fogSteps)
        .set("seed", targets.seed)
        .set("jitter", scene_.render.fogJitter ? 1 : 0)
        .set("primaryLight", volumes_.empty() || !selfShadowing_ ? -1 : primaryLight_)
        .set("globalDensity", globalDensity_)
        .set("globalAlbedo", globalAlbedo_)
        .set("globalAnisotropy", globalAnisotropy_)
        .set("octaves", scene_.render.fogOctaves)
        .set("octaveParams",
             glm::vec3(scene_.render.fogOctaveExtinction, scene_.render.fogOctaveScattering,
                       scene_.render.fogOctaveAnisotropy))
        .set("ambientScale", scene_.render.fogAmbient)
        .set("octaveRadius", scene_.render.fogOctaveRadius)
        .set("blackbodyMaxKelvin", float(kBlackbodyMaxKelvin));
    if (blackbody_) blackbody_.bind(VEIL_TEX_BLACKBODY);
    if (scattered_) scattered_->bind(program);
    if (targets.prepareReceiver) targets.prepareReceiver(program);
    targets.depth->bind(VEIL_TEX_DEPTH);
}

gpu::ProgramHandle FogPass::addSegmentsProgram(gpu::ProgramManager& programs,
                                               std::vector<std::string> oitDefines,
                                               const std::filesystem::path& oitEmitInclude) const {
    gpu::IncludeAliases aliases = lightVisibility_;
    aliases.push_back({"veil:oit_emit", oitEmitInclude});
    for (std::string& d : marchDefines())
        oitDefines.push_back(std::move(d));
    return programs.add(
        gpu::ProgramDesc::compute("volume/fog_segments.comp", std::move(oitDefines), aliases));
}

void FogPass::marchSegments(const pass::Context& targets, const gpu::Program& program,
                            const std::function<void(const gpu::Program&)>& prepareOit) const {
    if (!active()) return;
    // The surfaces were stored by fragment shaders; the marcher reads their lists.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    setMarchUniforms(program, targets);
    const glm::ivec4 r =
        targets.region.z > 0 ? targets.region : glm::ivec4(0, 0, targets.width, targets.height);
    program.set("targetSize", glm::ivec2(targets.width, targets.height)).set("marchRegion", r);
    prepareOit(program);
    program.use();
    // From pixel 0, not from the region's origin (fog_segments.comp: an offset invocation id
    // costs ~1.1 ms of the whole-frame march on the H200); a tile's dispatch has idle
    // invocations below and left of it, which return at once.
    glDispatchCompute((r.z + 7) / 8, (r.w + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void FogPass::bindForEmit(const gpu::Program& program, const pass::Context& targets) const {
    program.set("resolutionDivisor", divisor_)
        .set("invProjection", glm::inverse(targets.projection))
        .set("projection", targets.projection);
    radiance_.bind(VEIL_TEX_FOG_RADIANCE);
    transmittance_.bind(VEIL_TEX_FOG_TRANSMITTANCE);
    targets.depth->bind(VEIL_TEX_DEPTH);
}

void FogPass::drawEmit() const {
    emptyVao_.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
}

void FogPass::extendBounds(glm::vec3& lo, glm::vec3& hi) const {
    for (const Entry& e : volumes_) {
        glm::vec3 vlo, vhi;
        e.gpu->worldBounds(vlo, vhi);
        lo = glm::min(lo, vlo);
        hi = glm::max(hi, vhi);
    }
}

} // namespace veil::volume
