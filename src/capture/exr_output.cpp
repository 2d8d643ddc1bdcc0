#include "capture/exr_output.h"

#include "base/error.h"
#include "base/sha256.h"
#include "gpu/readback.h"
#include "io/provenance.h"

#include <fmt/format.h>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace veil::capture {

namespace {

// Level 0 of a depth texture as floats, row 0 at the top.
ImageF readDepth(const gpu::Texture& texture) {
    ImageF image(texture.width(), texture.height(), 1);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                      static_cast<GLsizei>(image.pixels.size() * sizeof(float)),
                      image.pixels.data());
    const std::size_t row = static_cast<std::size_t>(image.width);
    for (int y = 0; y < image.height / 2; ++y)
        std::swap_ranges(image.pixels.begin() + y * row, image.pixels.begin() + (y + 1) * row,
                         image.pixels.begin() + (image.height - 1 - y) * row);
    return image;
}

// Nearest-neighbour upsampling of a reduced-resolution fog target to the frame size.
ImageF upsample(const ImageF& image, int width, int height, int channels) {
    ImageF out(width, height, channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const int sx = std::min(image.width - 1, x * image.width / width);
            const int sy = std::min(image.height - 1, y * image.height / height);
            for (int c = 0; c < channels; ++c)
                out.at(x, y, c) = image.at(sx, sy, c);
        }
    return out;
}

} // namespace

ImageF linearViewDepth(const ImageF& windowDepth, const glm::mat4& projection) {
    const glm::dmat4 inverse = glm::inverse(glm::dmat4(projection));
    ImageF out(windowDepth.width, windowDepth.height, 1);
    for (std::size_t i = 0; i < out.pixels.size(); ++i) {
        const double d = windowDepth.pixels[i * windowDepth.channels];
        if (d >= 1.0) {
            out.pixels[i] = std::numeric_limits<float>::infinity();
            continue;
        }
        // View-space z of the point on the view axis with this NDC depth; the view depth
        // does not depend on the pixel's x, y for perspective and orthographic projections.
        const glm::dvec4 v = inverse * glm::dvec4(0.0, 0.0, 2.0 * d - 1.0, 1.0);
        out.pixels[i] = static_cast<float>(-v.z / v.w);
    }
    return out;
}

FrameExtras captureExtras(const frame::Renderer& renderer, bool fogAov) {
    FrameExtras e;
    e.view = renderer.camera().view();
    e.projection = renderer.camera().projection(float(renderer.width()) / float(renderer.height()));
    const gpu::Texture* depth = renderer.resourceTexture("depth");
    VEIL_CHECK(depth, "the frame has no depth target");
    e.viewDepth = linearViewDepth(readDepth(*depth), e.projection);
    if (fogAov) {
        const volume::FogPass* fog = renderer.fog();
        VEIL_CHECK(fog && fog->active(), "--aov fog: the scene has no volumes or fog");
        const ImageF radiance = gpu::readTexture(fog->radianceTexture());
        const ImageF transmittance = gpu::readTexture(fog->transmittanceTexture());
        e.fogRadiance = upsample(radiance, renderer.width(), renderer.height(), 3);
        ImageF t = upsample(transmittance, renderer.width(), renderer.height(), 1);
        e.fogTransmittance = std::move(t);
    }
    return e;
}

float backgroundDepth(const glm::mat4& projection, bool half) {
    constexpr float kHalfMax = 65504.0f; // the largest finite half float
    const glm::dvec4 v = glm::inverse(glm::dmat4(projection)) * glm::dvec4(0.0, 0.0, 1.0, 1.0);
    const double far = -v.z / v.w;
    if (!std::isfinite(far) || far <= 0.0) return kHalfMax;
    return half ? std::min(static_cast<float>(far), kHalfMax) : static_cast<float>(far);
}

io::ExrImage makeExr(const ImageF& hdr, const FrameExtras& extras, const RenderMetadata& metadata,
                     bool half) {
    // Z is finite everywhere, so tools that difference every channel (idiff, oiiotool) see
    // equal files as equal: no opaque surface is the far plane's depth, named in the header.
    const float background = backgroundDepth(metadata.projection, half);
    io::ExrImage exr;
    exr.width = hdr.width;
    exr.height = hdr.height;
    exr.half = half;
    exr.channels = {"R", "G", "B", "A", "Z"};
    const bool fog = !extras.fogRadiance.pixels.empty();
    if (fog)
        for (const char* c : {"fog.R", "fog.G", "fog.B", "fog.transmittance"})
            exr.channels.push_back(c);
    const std::size_t n = exr.channels.size();
    exr.pixels.resize(std::size_t(hdr.width) * hdr.height * n);
    for (int y = 0; y < hdr.height; ++y)
        for (int x = 0; x < hdr.width; ++x) {
            float* p = &exr.pixels[(std::size_t(y) * hdr.width + x) * n];
            for (int c = 0; c < 3; ++c)
                p[c] = hdr.at(x, y, c);
            p[3] = 1.0f;
            const float z = extras.viewDepth.at(x, y, 0);
            p[4] = std::isfinite(z) ? std::min(z, background) : background;
            if (fog) {
                for (int c = 0; c < 3; ++c)
                    p[5 + c] = extras.fogRadiance.at(x, y, c);
                p[8] = extras.fogTransmittance.at(x, y, 0);
            }
        }
    for (const auto& [key, value] : metadata.strings.items())
        exr.strings.emplace_back(key, value.get<std::string>());
    exr.strings.emplace_back("veil:background_depth", fmt::format("{}", background));
    auto matrix = [](const glm::mat4& m) {
        std::array<float, 16> a{};
        std::memcpy(a.data(), glm::value_ptr(m), sizeof a);
        return a;
    };
    exr.matrices.emplace_back("worldtocamera", matrix(metadata.view));
    exr.matrices.emplace_back("worldtoscreen", matrix(metadata.projection * metadata.view));
    exr.matrices.emplace_back("veil:projection", matrix(metadata.projection));
    return exr;
}

} // namespace veil::capture

namespace veil::capture {

void addRgbLayer(io::ExrImage& exr, const std::string& layer, const ImageF& rgb) {
    VEIL_CHECK(rgb.width == exr.width && rgb.height == exr.height && rgb.channels >= 3,
               "EXR layer '{}': {}x{} image of {} channels for a {}x{} file", layer, rgb.width,
               rgb.height, rgb.channels, exr.width, exr.height);
    const std::size_t n = exr.channels.size(), m = n + 3;
    std::vector<float> pixels(std::size_t(exr.width) * exr.height * m);
    for (std::size_t p = 0; p < std::size_t(exr.width) * exr.height; ++p) {
        std::copy_n(&exr.pixels[p * n], n, &pixels[p * m]);
        for (int c = 0; c < 3; ++c)
            pixels[p * m + n + c] = rgb.pixels[p * rgb.channels + c];
    }
    exr.pixels = std::move(pixels);
    for (const char* c : {".R", ".G", ".B"})
        exr.channels.push_back(layer + c);
}

RenderMetadata describeRender(const std::filesystem::path& scene, const std::string& oit,
                              const nlohmann::json& oitProperties, const std::string& camera,
                              const FrameExtras& extras, int width, int height,
                              const std::string& glRenderer) {
    RenderMetadata m;
    for (const auto& [name, value] : io::provenanceAttributes())
        m.strings[name] = value;
    m.strings["veil:scene"] = std::filesystem::absolute(scene).string();
    m.strings["veil:scene_sha256"] = sha256File(scene);
    m.strings["veil:oit"] = oit;
    m.strings["veil:oit_properties"] = oitProperties.dump();
    m.strings["veil:camera"] = camera;
    m.strings["veil:size"] = fmt::format("{}x{}", width, height);
    m.strings["veil:gl_renderer"] = glRenderer;
    m.strings["veil:channels"] =
        "RGB linear radiance; A = 1 (background included in RGB); Z = view depth of the "
        "nearest opaque surface in scene units, veil:background_depth (the far plane) for none";
    m.view = extras.view;
    m.projection = extras.projection;
    return m;
}

nlohmann::json metadataJson(const RenderMetadata& metadata) {
    nlohmann::json j = metadata.strings;
    auto numbers = [](const glm::mat4& m) {
        std::vector<float> v(glm::value_ptr(m), glm::value_ptr(m) + 16);
        return v;
    };
    j["worldtocamera"] = numbers(metadata.view);
    j["worldtoscreen"] = numbers(metadata.projection * metadata.view);
    j["veil:projection"] = numbers(metadata.projection);
    j["matrix_layout"] = "column-major (GLM; OpenEXR m44f row-vector convention)";
    return j;
}

} // namespace veil::capture
