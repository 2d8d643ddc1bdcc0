#include "frame/stages/fog_stage.h"

#include "fog/scattered_light_cache.h"

namespace veil::frame {

void FogStage::beginFrame(pass::Context& context) {
    fog_->prepareScatteredLight(); // its bake is not part of the timed pass `fog`
    // Surfaces lit by the cache (shaders/volume/scattered_light.glsl): every receiver program
    // (opaque, transparent, the compute rasterizer's, the marcher's) gets its textures with the
    // shadow technique's inputs (ShadowStage::beginFrame sets those first, every frame).
    if (const volume::ScatteredLightCache* cache = fog_->scatteredLightCache())
        context.prepareReceiver =
            [cache, shadows = std::move(context.prepareReceiver)](const gpu::Program& program) {
                if (shadows) shadows(program);
                cache->bind(program);
            };
    context.bindMedia = nullptr;
    if (fog_->hasGridVolumes())
        context.bindMedia = [this](const gpu::Program& program) { fog_->bindVolumes(program); };
}

} // namespace veil::frame
