// Banded shadow passes (pass::Pass::executeRows, src/pass/pass.h): a pass
// run over consecutive bands of texel rows must leave every map bit for bit as the pass run
// whole (execute), so that the viewer can spread an expensive pass over several UI frames
// without changing the frame (docs/viewer.md "Slow drivers"). The reference is the whole
// pass, which the technique's own tests check against analytic and CPU values; exact
// equality is the tolerance, because both runs evaluate the same shader arithmetic on the
// same inputs per texel (the same driver, the same fragments blended in the same primitive
// order), and any difference is a band that missed, repeated or misplaced work.
//
// The scene is datasets/scenes/fog.json (a spot light through window slats onto glass and a
// smoke volume: opaque and transparent casters and a density volume in one map) with 256^2
// maps, with a pass::Context as frame::Renderer gives it (renderer.cpp). The bands are
// uneven and include ones thinner than the moment filter's radius.
#include "gl_fixture.h"

#include "base/image.h"
#include "frame/gpu_mesh.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "shadows/technique.h"
#include "shadows/views.h"
#include "support/test_support.h"
#include "fog/fog_pass.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace veil::test {

namespace {

constexpr int kMapSize = 256;
// Row bands covering [0, 256): uneven, two thinner than the moment filter's radius (4).
const std::vector<int> kBands = {100, 3, 1, 33, 119};

// The pieces of renderer.cpp's shadow frame for one scene: meshes, views, the shadows block,
// the fog's volumes (pass::Context::bindMedia).
struct Harness {
    scene::Scene scene;
    gpu::ProgramManager programs;
    shadows::ShadowLightSet set;
    std::vector<shadows::LightView> views;
    std::vector<frame::GpuMesh> meshes;
    std::unique_ptr<volume::FogPass> fog;
    gpu::Buffer shadowsUbo;
    gpu::StateTracker state;
    pass::Context frame;

    explicit Harness(const std::string& shadows)
        : scene(scene::loadScene(sourceDir() / "datasets/scenes/fog.json",
                                 {"render.shadows=" + shadows})) {
        set = shadows::chooseShadowLights(scene, 4, "test");
        glm::vec3 lo, hi;
        scene.bounds(lo, hi);
        views = shadows::fitViews(scene, set, lo, hi);
        for (const auto& mesh : scene.meshes)
            meshes.emplace_back(mesh);
        frame.lightViews = &views;
        frame.scene = &scene;
        frame.state = &state;
        frame.seed = scene.render.seed;
        frame.width = 64;
        frame.height = 48;
        frame.drawObjects = [this](const gpu::Program& program, pass::ObjectSet set) {
            frame::drawObjects(scene, meshes, program, set);
        };
    }

    // Creates the scene's technique (the programs of the fog's march include its visibility).
    std::unique_ptr<shadows::Technique> technique(const gpu::ContextInfo& context) {
        auto t = shadows::Registry::instance().create(scene.render.shadows, context, programs,
                                                      scene.render.shadowProperties, "test");
        if (!fog) {
            fog = std::make_unique<volume::FogPass>(
                scene, programs,
                gpu::IncludeAliases{{"veil:light_visibility", t->visibilityInclude()}});
            if (fog->hasGridVolumes())
                frame.bindMedia = [this](const gpu::Program& p) { fog->bindVolumes(p); };
        }
        t->resize(kMapSize, set.viewCount);
        shadows::ShadowsBlock block{};
        shadows::fillShadowsBlock(block, views, set, kMapSize);
        t->fillParams(block);
        shadowsUbo = gpu::Buffer();
        shadowsUbo.setStorage(sizeof(block), &block);
        return t;
    }

    // Every pass of `t`, whole or (where the pass has executeRows) in kBands; afterBand(pass,
    // y0, y1) after each band.
    void run(shadows::Technique& t, bool banded, int* bandedPasses = nullptr,
             const std::function<void(const std::string&, int, int)>& afterBand = {}) {
        state.invalidate();
        shadowsUbo.bindBase(GL_UNIFORM_BUFFER, VEIL_UBO_SHADOWS);
        for (pass::Pass& p : t.passes()) {
            if (!banded || !p.executeRows) {
                p.execute(frame);
                continue;
            }
            if (bandedPasses) ++*bandedPasses;
            int y0 = 0;
            for (int h : kBands) {
                p.executeRows(frame, y0, y0 + h);
                if (afterBand) afterBand(p.name, y0, y0 + h);
                y0 += h;
            }
            ASSERT_EQ(y0, kMapSize);
        }
        glFinish();
    }
};

// One texture's level 0, every layer, as its bytes (depth as floats, colour as RGBA of the
// texture's own component type, so equal bytes are equal texels).
struct Texels {
    GLint width = 0, height = 0, layers = 0, format = 0;
    std::vector<std::uint8_t> bytes;
};
// Every sample of a multisample depth array, through tests/gl/data/ms_depth_probe.comp.
void readSamples(GLuint id, Texels& t) {
    GLint samples = 0;
    glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_SAMPLES, &samples);
    gpu::Program probe(
        gpu::ProgramDesc::compute(sourceDir() / "tests/gl/data/ms_depth_probe.comp"));
    t.bytes.assign(std::size_t(t.width) * t.height * t.layers * samples * 4, 0);
    gpu::Buffer out;
    out.setStorage(t.bytes.size(), t.bytes.data());
    probe.use();
    probe.set("samples", samples);
    glBindTextureUnit(0, id);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    glDispatchCompute(GLuint(t.width + 7) / 8, GLuint(t.height + 7) / 8, GLuint(t.layers));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(t.bytes.size()), t.bytes.data());
    glBindTextureUnit(0, 0);
}

Texels readTexels(GLuint id) {
    Texels t;
    GLint target = 0;
    glGetTextureParameteriv(id, GL_TEXTURE_TARGET, &target);
    glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_WIDTH, &t.width);
    glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_HEIGHT, &t.height);
    glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_DEPTH, &t.layers);
    glGetTextureLevelParameteriv(id, 0, GL_TEXTURE_INTERNAL_FORMAT, &t.format);
    if (target == GL_TEXTURE_2D_MULTISAMPLE_ARRAY) {
        readSamples(id, t);
        return t;
    }
    GLenum format = GL_RGBA, type = GL_FLOAT;
    int texelBytes = 16;
    switch (t.format) {
    case GL_DEPTH_COMPONENT32F:
        format = GL_DEPTH_COMPONENT, texelBytes = 4;
        break;
    case GL_RGBA16:
        type = GL_UNSIGNED_SHORT, texelBytes = 8;
        break;
    case GL_RGBA16F:
        type = GL_HALF_FLOAT, texelBytes = 8;
        break;
    case GL_RG32F:
        format = GL_RG, texelBytes = 8;
        break;
    case GL_R32F:
        format = GL_RED, texelBytes = 4;
        break;
    case GL_R32UI:
        format = GL_RED_INTEGER, type = GL_UNSIGNED_INT, texelBytes = 4;
        break;
    default:
        break; // RGBA32F
    }
    t.bytes.resize(std::size_t(t.width) * t.height * t.layers * texelBytes);
    glGetTextureImage(id, 0, format, type, GLsizei(t.bytes.size()), t.bytes.data());
    return t;
}

// The (multisample) 2D array textures bindForReceivers() binds at the shadow units (what
// the receivers sample; some are not behind a resource name).
std::vector<GLuint> receiverTextures(const shadows::Technique& t) {
    const int units[] = {VEIL_TEX_SHADOW_MAP, VEIL_TEX_SHADOW1, VEIL_TEX_SHADOW2, VEIL_TEX_SHADOW3};
    for (int u : units) { // unbind every target of the unit
        glActiveTexture(GLenum(GL_TEXTURE0 + u));
        glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE_ARRAY, 0);
        glBindTexture(GL_TEXTURE_3D, 0);
    }
    t.bindForReceivers();
    std::vector<GLuint> ids;
    for (int u : units) {
        glActiveTexture(GLenum(GL_TEXTURE0 + u));
        for (GLenum binding : {GL_TEXTURE_BINDING_2D_ARRAY, GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY,
                               GL_TEXTURE_BINDING_3D}) {
            GLint id = 0;
            glGetIntegerv(binding, &id);
            if (id != 0) ids.push_back(GLuint(id));
        }
    }
    glActiveTexture(GL_TEXTURE0);
    return ids;
}

// Rows of layer 0 where the texels differ (first few, for the failure message).
std::string differingRows(const Texels& a, const Texels& b) {
    const std::size_t row = a.bytes.size() / std::size_t(a.layers) / std::size_t(a.height);
    std::string rows;
    int n = 0;
    for (int y = 0; y < a.height && n < 8; ++y)
        if (std::memcmp(a.bytes.data() + y * row, b.bytes.data() + y * row, row) != 0)
            rows += std::to_string(y) + " ", ++n;
    return rows.empty() ? "none in layer 0" : rows;
}

// Whether rows [y0, y1) of every layer hold the same bytes in a and b.
bool sameRows(const Texels& a, const Texels& b, int y0, int y1) {
    const std::size_t row = a.bytes.size() / std::size_t(a.layers) / std::size_t(a.height);
    for (int l = 0; l < a.layers; ++l) {
        const std::size_t at = (std::size_t(l) * a.height + y0) * row;
        if (std::memcmp(a.bytes.data() + at, b.bytes.data() + at, std::size_t(y1 - y0) * row))
            return false;
    }
    return true;
}

// Fills a texture with a value no pass writes (0.375), so that work outside a band shows.
void fillSentinel(GLuint id, GLint format) {
    const float v[4] = {0.375f, 0.375f, 0.375f, 0.375f};
    glClearTexImage(id, 0, format == GL_DEPTH_COMPONENT32F ? GL_DEPTH_COMPONENT : GL_RGBA, GL_FLOAT,
                    v);
}

// Distinct 4-byte words of a texture (a map of one value is no test).
std::size_t distinctWords(const Texels& t) {
    std::vector<std::uint32_t> w(t.bytes.size() / 4);
    std::memcpy(w.data(), t.bytes.data(), w.size() * 4);
    std::sort(w.begin(), w.end());
    return std::size_t(std::unique(w.begin(), w.end()) - w.begin());
}

// The moment technique's absorbance map (b0: glass rgb, media alpha) as a PNG to look at.
void writeAbsorbancePng(const Texels& t, const std::string& name) {
    if (t.format != GL_RGBA32F) return;
    ImageF img(t.width, t.height, 3);
    const float* f = reinterpret_cast<const float*>(t.bytes.data());
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x) {
            const float* p = f + (std::size_t(t.height - 1 - y) * t.width + x) * 4;
            img.at(x, y, 0) = std::min(1.0f, 0.5f * (p[0] + p[1] + p[2]) / 3.0f);
            img.at(x, y, 1) = std::min(1.0f, 0.5f * p[3]);
            img.at(x, y, 2) = 0.0f;
        }
    io::writeImage(outputDir() / (name + ".png"), img);
}

// A technique (test name, render.shadows) and how many of its passes run in bands (the
// rest run whole in both runs); -1: all.
struct BandCase {
    const char* first;
    const char* second;
    int bandedPasses = -1;
};

} // namespace

class ShadowBandsTest : public GlTest, public ::testing::WithParamInterface<BandCase> {};

// Every pass whole on one instance, every pass in bands on another (the same programs, scene
// and views): every texture the receivers sample and every receiver resource equal bit for bit.
TEST_P(ShadowBandsTest, BandsEqualTheWholePass) {
    Harness h(GetParam().second);
    ASSERT_EQ(h.views.size(), 1u);
    auto whole = h.technique(info());
    auto banded = h.technique(info());
    ASSERT_TRUE(h.frame.bindMedia) << "fog.json's smoke volume";
    ASSERT_FALSE(banded->dependsOnCamera());
    // Both instances' maps start as a sentinel (a map this configuration never writes, e.g.
    // slicemap's range without `local`, keeps it in both).
    for (GLuint id : receiverTextures(*whole))
        fillSentinel(id, readTexels(id).format);
    std::vector<Texels> sentinels;
    for (GLuint id : receiverTextures(*whole))
        sentinels.push_back(readTexels(id));
    h.run(*whole, false);
    // A band leaves the rows after it alone (it does the band's work, not the whole pass's
    // again): after each band the rows from its end on hold what they held before it.
    const std::vector<GLuint> bandedMaps = receiverTextures(*banded);
    std::vector<Texels> before;
    for (GLuint id : bandedMaps) {
        fillSentinel(id, readTexels(id).format);
        before.push_back(readTexels(id));
    }
    int bandedPasses = 0, outside = 0;
    h.run(*banded, true, &bandedPasses, [&](const std::string& pass, int, int y1) {
        for (std::size_t i = 0; i < bandedMaps.size(); ++i) {
            Texels after = readTexels(bandedMaps[i]);
            // A map of another resolution (slicemap's fog columns): its rows of the band.
            const int end = int(std::int64_t(y1) * after.height / kMapSize);
            if (!sameRows(before[i], after, end, after.height) && outside++ < 4)
                ADD_FAILURE() << GetParam().first << ": pass \"" << pass << "\" band ending at "
                              << y1 << " wrote rows after it in texture " << i;
            before[i] = std::move(after);
        }
    });
    EXPECT_EQ(outside, 0);
    VEIL_EXPECT_NO_GL_ERROR();
    // Every pass of the technique (or as many as the case says) has its banded form.
    EXPECT_EQ(bandedPasses,
              GetParam().bandedPasses < 0 ? int(banded->passes().size()) : GetParam().bandedPasses);

    std::vector<GLuint> a = receiverTextures(*whole), b = receiverTextures(*banded);
    for (const std::string& r : whole->receiverResources()) {
        // A buffer resource (slicemap's shadow.slices words) has no texture: only its whole
        // pass writes it here.
        if (!whole->resourceTexture(r)) continue;
        a.push_back(whole->resourceTexture(r)->id());
        b.push_back(banded->resourceTexture(r)->id());
    }
    ASSERT_EQ(a.size(), b.size());
    int written = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const Texels ta = readTexels(a[i]), tb = readTexels(b[i]);
        ASSERT_EQ(ta.bytes.size(), tb.bytes.size());
        if (i < sentinels.size() && ta.bytes == sentinels[i].bytes) {
            std::printf("[ bands ] %s: texture %zu not written in this configuration\n",
                        GetParam().first, i);
        } else {
            ++written;
            EXPECT_GT(distinctWords(ta), 100u) << "texture " << i << " is (nearly) constant";
        }
        EXPECT_TRUE(ta.bytes == tb.bytes)
            << GetParam().first << ": texture " << i << " (internal format 0x" << std::hex
            << ta.format << std::dec << ") differs in rows " << differingRows(ta, tb);
        if (i == 1) writeAbsorbancePng(tb, std::string("shadow_bands_") + GetParam().first);
    }
    EXPECT_GE(written, 2); // the depth map and at least one map of the other casters
}

INSTANTIATE_TEST_SUITE_P(
    Techniques, ShadowBandsTest,
    ::testing::Values(
        BandCase{"moment", R"({"type": "moment", "size": 256})"},
        BandCase{"moment_quantized16",
                 R"({"type": "moment", "size": 256, "storage": "quantized16"})"},
        BandCase{"opaque", R"({"type": "opaque", "size": 256})"},
        BandCase{"stochastic", R"({"type": "stochastic", "size": 256})"},
        BandCase{"stochastic_vsm", R"({"type": "stochastic-vsm", "size": 256})"},
        // Depth and fog in bands, the slices whole; fog columns 96: bands of map rows map to
        // bands of column rows of another height.
        BandCase{"transmittance_slicemap",
                 R"({"type": "transmittance-slicemap", "size": 256, "fog_columns": 96})", 2}),
    [](const auto& info) { return std::string(info.param.first); });

} // namespace veil::test
