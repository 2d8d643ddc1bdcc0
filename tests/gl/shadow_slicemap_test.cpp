// transmittance-slicemap [Eisemann06 sec. 3] beyond the shared analytic cases of
// shadow_techniques_test.cpp: coloured shadows of stained glass (channel ratios), local
// slicing separating layers closer than a uniform slice, the GPU's bitCount-over-masked-words
// attenuation against a CPU double-precision model (src/voxelize SliceMap::countOccupied), and
// the grouping of materials into transmittance classes.
#include "gl_fixture.h"

#include "frame/renderer.h"
#include "gpu/objects.h"
#include "gpu/shader.h"
#include "scene/scene.h"
#include "shadow_test_scenes.h"
#include "shadows/transmittance_slicemap/transmittance_slicemap.h"
#include "support/test_support.h"
#include "voxelize/slice_map.h"

#include <cmath>
#include <random>

namespace veil::test {

namespace {

namespace ss = shadow_scenes;

class SlicemapShadowTest : public GlTest {
protected:
    static nlohmann::json technique(nlohmann::json extra = nlohmann::json::object()) {
        extra["type"] = "transmittance-slicemap";
        extra["size"] = 1024;
        return extra;
    }
    // (floor radiance - ambient) / unshadowed at world (x, z), per channel.
    static std::array<double, 3> transmittanceAt(const ImageF& img, double x, double z) {
        std::array<double, 3> t{};
        for (int c = 0; c < 3; ++c)
            t[c] = (img.at(ss::px(x), ss::px(z), c) - ss::ambient()) / ss::litFloor();
        return t;
    }
    static ImageF render(const nlohmann::json& doc) {
        const scene::Scene sc = scene::parseScene(doc, sourceDir());
        frame::Renderer renderer(sc, info());
        renderer.render();
        VEIL_EXPECT_NO_GL_ERROR();
        return renderer.readHdr();
    }
    // A 2x2 pane of coverage 1 and transmission t at height y, centred at (0, y, z).
    static void addGlass(nlohmann::json& doc, const std::string& name, double y, double z,
                         const glm::dvec3& t) {
        doc["materials"][name] = {{"base_color", 0.0},
                                  {"roughness", 0.5},
                                  {"alpha", 1.0},
                                  {"transmission", {t.x, t.y, t.z}}};
        doc["objects"].push_back({{"name", name},
                                  {"shape", {{"type", "plane"}, {"size", {2, 1.6}}}},
                                  {"material", name},
                                  {"transform", {{"translate", {0, y, z}}}}});
    }
};

} // namespace

// Two panes of stained glass side by side (two classes): each throws its own colour, the
// channel ratios of the shadow equal the glass's within 2% ([Eisemann06 sec. 3]'s coloured leaves).
TEST_F(SlicemapShadowTest, StainedGlassShadowKeepsChannelRatios) {
    nlohmann::json doc = ss::base(technique());
    const glm::dvec3 red(0.9, 0.45, 0.15), blue(0.2, 0.4, 0.8);
    addGlass(doc, "red", 1.0, -1.2, red);
    addGlass(doc, "blue", 1.0, 1.2, blue);
    const ImageF img = render(doc);
    for (const auto& [z, t] : {std::pair{-1.2, red}, std::pair{1.2, blue}}) {
        const auto m = transmittanceAt(img, ss::kShadowX, z);
        EXPECT_NEAR(m[0] / m[1], t.x / t.y, 0.02 * t.x / t.y) << "R/G under pane at z = " << z;
        EXPECT_NEAR(m[2] / m[1], t.z / t.y, 0.02 * t.z / t.y) << "B/G under pane at z = " << z;
        EXPECT_NEAR(m[1], t.y, 0.02 * t.y) << "G under pane at z = " << z;
    }
}

// Four coverage layers 0.02 apart in height (0.028 along the light's axis) share uniform
// slices of 11.4 / 128 = 0.089 (fewer counted crossings, too bright), but local slicing
// divides the layers' own 0.085 range into 128 slices: exactly (1 - 0.3)^4.
TEST_F(SlicemapShadowTest, LocalSlicingSeparatesCloseLayers) {
    const double expected = std::pow(0.7, 4);
    for (bool local : {false, true}) {
        nlohmann::json doc = ss::base(technique({{"local_slicing", local}}));
        for (int i = 0; i < 4; ++i)
            ss::addPane(doc, "leaf" + std::to_string(i), 1.0 + 0.02 * i, 0.3, {0.0, 0.0, 0.0});
        const auto m = transmittanceAt(render(doc), ss::kShadowX, ss::kShadowZ);
        if (local)
            EXPECT_NEAR(m[1], expected, 2e-3) << "local slicing";
        else
            EXPECT_GT(m[1], expected * 1.2) << "uniform slicing merges layers in a slice";
    }
}

// A lit semi-transparent surface is a receiver in its own slice: it must not shadow itself.
// The pane (coverage 0.5, diffuse 0.6) over a floor point that the light reaches beside it
// (x = -0.5: its light ray crosses height 1 at x = -1.5, outside the pane) looks the same as
// under `opaque`, which has no transparent casters at all.
TEST_F(SlicemapShadowTest, LitPaneDoesNotShadowItself) {
    std::array<double, 3> v[2];
    for (int i = 0; i < 2; ++i) {
        nlohmann::json doc =
            ss::base(i == 0 ? technique() : nlohmann::json{{"type", "opaque"}, {"size", 1024}});
        ss::addPane(doc, "pane", 1.0, 0.5, {0.3, 0.3, 0.3});
        doc["materials"]["pane"]["base_color"] = 0.6;
        const ImageF img = render(doc);
        for (int c = 0; c < 3; ++c)
            v[i][c] = img.at(ss::px(-0.5), ss::px(0.0), c);
    }
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(v[0][c], v[1][c], 2e-3 * v[1][c]) << "channel " << c;
}

// Perspective light views (a spot light, and a point light's -y cube face): the slice
// coordinate is the view's normalized linear depth there too. Light at (-2, 4, 0), the pane
// (T = (0.8, 0.5, 0.2)) at height 1 over x in [-1, 1] shadows the floor at (1.5, 0, 0), which
// the camera sees beside the pane; T = (radiance - ambient) with the pane over that without.
TEST_F(SlicemapShadowTest, PerspectiveViewsGiveT) {
    for (const char* type : {"spot", "point"}) {
        std::array<double, 3> v[2];
        for (int withPane = 0; withPane < 2; ++withPane) {
            nlohmann::json doc = ss::base(technique());
            nlohmann::json light = {
                {"type", type}, {"position", {-2, 4, 0}}, {"intensity", 20}, {"shadows", true}};
            if (std::string(type) == "spot") {
                light["target"] = {1, 0, 0};
                light["inner_cone"] = 50;
                light["outer_cone"] = 60;
            }
            doc["lights"] = nlohmann::json::array({light});
            if (withPane) ss::addPane(doc, "stained", 1.0, 1.0, {0.8, 0.5, 0.2});
            const ImageF img = render(doc);
            for (int c = 0; c < 3; ++c)
                v[withPane][c] = img.at(ss::px(1.5), ss::px(0.0), c) - ss::ambient();
        }
        const double t[3] = {0.8, 0.5, 0.2};
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(v[1][c] / v[0][c], t[c], 2e-3 * t[c] + 1e-3) << type << " channel " << c;
    }
}

// The GPU attenuation (slices.glsl: bitCount over the words a prefix of slices touches, the
// last one masked) against prod_c T_c^(n_c) in double precision with n_c from
// SliceMap::countOccupied, on random words of 2 views x 3 classes x 5 columns x 1..1024
// slices, probes at random prefixes (including word boundaries).
TEST_F(SlicemapShadowTest, BitCountAttenuationMatchesCpuModel) {
    gpu::Program probe(
        gpu::ProgramDesc::compute("shadows/transmittance_slicemap/count_probe.comp"));
    const std::vector<glm::dvec3> classT = {{0.9, 0.7, 0.5}, {0.99, 0.98, 0.97}, {0.5, 0.8, 0.95}};
    std::mt19937 rng(11);
    for (int slices : {1, 31, 32, 33, 100, 128, 1000, 1024}) {
        const int views = 2, classes = 3, columns = 5;
        // One SliceMap (1 row of `columns`) per (view, class), words filled at random with a
        // density that varies per map so that counts span 0 .. slices.
        std::vector<voxelize::SliceMap> maps(views * classes);
        std::vector<std::uint32_t> words;
        for (std::size_t m = 0; m < maps.size(); ++m) {
            voxelize::SliceMap& map = maps[m];
            map.width = columns;
            map.height = 1;
            map.slices = slices;
            map.allocate();
            const double density = 0.02 + 0.3 * double(m) / maps.size();
            std::bernoulli_distribution bit(density);
            for (int x = 0; x < columns; ++x)
                for (int s = 0; s < slices; ++s)
                    if (bit(rng)) map.set(x, 0, s);
            words.insert(words.end(), map.words.begin(), map.words.end());
        }
        std::vector<glm::ivec4> probes;
        for (int i = 0; i < 256; ++i) {
            int s1 = int(rng() % slices);
            if (i % 4 == 0) s1 = std::min(slices - 1, 32 * int(rng() % 33) + int(rng() % 2) - 1);
            probes.emplace_back(int(rng() % views), int(rng() % columns), std::max(s1, 0), 0);
        }
        gpu::Buffer wb, pb, ob;
        wb.setStorage(std::span<const std::uint32_t>(words));
        pb.setStorage(std::span<const glm::ivec4>(probes));
        ob.setStorage(probes.size() * 16, nullptr);
        wb.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_SLICES);
        pb.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_SLICES + 1);
        ob.bindBase(GL_SHADER_STORAGE_BUFFER, VEIL_SSBO_SHADOW_SLICES + 2);
        std::vector<glm::vec3> tf;
        for (const auto& t : classT)
            tf.emplace_back(t);
        probe.set("uProbeCount", int(probes.size()))
            .set("uClasses", classes)
            .set("uColumns", columns)
            .set("uSlices", slices);
        glProgramUniform3fv(probe.id(), probe.uniformLocation("uClassT"), 3, &tf[0].x);
        probe.use();
        glDispatchCompute(GLuint(probes.size() + 63) / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<glm::vec4> out(probes.size());
        glGetNamedBufferSubData(ob.id(), 0, GLsizeiptr(out.size() * 16), out.data());
        glUseProgram(0);
        VEIL_EXPECT_NO_GL_ERROR();
        for (std::size_t i = 0; i < probes.size(); ++i) {
            const auto& p = probes[i];
            glm::dvec3 want(1.0);
            int total = 0;
            for (int c = 0; c < classes; ++c) {
                const int n = maps[p.x * classes + c].countOccupied(p.y, 0, 0, p.z);
                total += n;
                want *= glm::pow(classT[c], glm::dvec3(n));
            }
            // float pow of T^n: relative error ~ n ulp of log2 T; 1e-5 relative plus 1e-30.
            for (int ch = 0; ch < 3; ++ch)
                ASSERT_NEAR(out[i][ch], want[ch], 1e-5 * want[ch] + 1e-30)
                    << "slices " << slices << " probe " << i << " (view " << p.x << ", column "
                    << p.y << ", s1 " << p.z << ", " << total << " set) channel " << ch;
        }
    }
}

// Classes: distinct transmittances get their own class while they fit; more are merged in
// absorbance, nearest first, into geometric means.
TEST(SlicemapClasses, GroupsByTransmittance) {
    using shadows::slicemap::groupClasses;
    std::vector<int> a;
    auto c = groupClasses({{0.8, 0.5, 0.2}, {0.6, 0.6, 0.6}, {0.8, 0.5, 0.2}}, 3, &a);
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(a, (std::vector<int>{0, 1, 0}));
    EXPECT_NEAR(c[0].y, 0.5, 1e-12);
    // Four values into two classes: the two nearly equal greens merge, then the two reds.
    c = groupClasses({{0.9, 0.2, 0.2}, {0.2, 0.9, 0.2}, {0.8, 0.2, 0.2}, {0.2, 0.88, 0.2}}, 2, &a);
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(a[0], a[2]);
    EXPECT_EQ(a[1], a[3]);
    EXPECT_NE(a[0], a[1]);
    EXPECT_NEAR(c[a[0]].x, std::sqrt(0.9 * 0.8), 1e-12); // geometric mean
    EXPECT_NEAR(c[a[1]].y, std::sqrt(0.9 * 0.88), 1e-12);
    // One class: everything shares it.
    c = groupClasses({{0.9, 0.2, 0.2}, {0.2, 0.9, 0.2}}, 1, &a);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(a, (std::vector<int>{0, 0}));
}

} // namespace veil::test
