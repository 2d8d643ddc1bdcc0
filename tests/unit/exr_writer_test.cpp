// EXR writing (src/io/exr_writer.h) and the half conversion it uses (src/base/half.h), read
// back through OpenImageIO; SHA-256 (src/base/sha256.h) against FIPS 180-4's examples.
#include "base/half.h"
#include "base/sha256.h"
#include "io/exr_writer.h"
#include "io/image_io.h"
#include "support/test_support.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace veil::test {

namespace fs = std::filesystem;

TEST(HalfTest, RoundsToNearestEven) {
    // 0.7 lies 0.6 of a step (2^-11) above 1433 / 2048: nearest is 1434 / 2048.
    EXPECT_EQ(halfToFloat(floatToHalf(0.7f)), 1434.0f / 2048.0f);
    EXPECT_EQ(halfToFloat(floatToHalf(1.0001f)), 1.0f);
    // Exactly halfway between 1 and 1 + 2^-10 goes to the even mantissa (1); 3 halfway steps
    // go up to 1 + 2^-9 (even).
    EXPECT_EQ(halfToFloat(floatToHalf(1.0f + 0.5f / 1024.0f)), 1.0f);
    EXPECT_EQ(halfToFloat(floatToHalf(1.0f + 1.5f / 1024.0f)), 1.0f + 2.0f / 1024.0f);
    EXPECT_EQ(halfToFloat(floatToHalf(-2.5f)), -2.5f);
    EXPECT_EQ(halfToFloat(floatToHalf(65504.0f)), 65504.0f);
    EXPECT_TRUE(std::isinf(halfToFloat(floatToHalf(65520.0f))));
    EXPECT_EQ(halfToFloat(floatToHalf(65519.0f)), 65504.0f);
    EXPECT_TRUE(std::isinf(halfToFloat(floatToHalf(INFINITY))));
    EXPECT_TRUE(std::isnan(halfToFloat(floatToHalf(NAN))));
    // Subnormals: 2^-24 is the smallest; 2^-25 is a tie and goes to 0, just above it to 2^-24.
    EXPECT_EQ(halfToFloat(floatToHalf(std::ldexp(1.0f, -24))), std::ldexp(1.0f, -24));
    EXPECT_EQ(halfToFloat(floatToHalf(std::ldexp(1.0f, -25))), 0.0f);
    EXPECT_EQ(halfToFloat(floatToHalf(std::ldexp(1.2f, -25))), std::ldexp(1.0f, -24));
    EXPECT_EQ(halfToFloat(floatToHalf(std::ldexp(3.0f, -20))), std::ldexp(3.0f, -20));
    // The carry out of the mantissa: just under 2 rounds up to 2.
    EXPECT_EQ(halfToFloat(floatToHalf(1.99995f)), 2.0f);
}

// Round-toward-zero (llvmpipe's conversion) gives -2e-4 at 0.7. Rounded to nearest, the mean error
// over values spread through [0.5, 1) is far below half a step (2.4e-4) and every error is
// at most half a step.
TEST(HalfTest, NoBiasOverAnOctave) {
    double sum = 0.0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        const float v = 0.5f + 0.5f * (float(i) + 0.37f) / float(n);
        const double e = double(halfToFloat(floatToHalf(v))) - double(v);
        EXPECT_LE(std::abs(e), std::ldexp(1.0, -12) + 1e-12) << v;
        sum += e;
    }
    EXPECT_LT(std::abs(sum / n), 1e-5);
}

namespace {

std::vector<float> readChannels(const fs::path& path, OIIO::ImageSpec& spec) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    spec = in->spec();
    std::vector<float> data(std::size_t(spec.width) * spec.height * spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()));
    return data;
}

io::ExrImage smallImage(bool half) {
    io::ExrImage exr;
    exr.width = 3;
    exr.height = 2;
    exr.channels = {"R", "G", "B", "A", "Z", "fog.R"};
    exr.half = half;
    for (int i = 0; i < 3 * 2 * 6; ++i)
        exr.pixels.push_back(1.0001f + 0.125f * float(i));
    exr.strings = {{"veil:scene", "/x/scene.json"}, {"veil:oit", "wboit"}};
    std::array<float, 16> m{};
    for (int i = 0; i < 16; ++i)
        m[i] = float(i) + 0.5f;
    exr.matrices = {{"worldtocamera", m}};
    return exr;
}

} // namespace

TEST(ExrWriterTest, Float32KeepsWhatHalfCannotAndNamesChannels) {
    const fs::path dir = outputDir() / "exr_writer";
    fs::create_directories(dir);
    const io::ExrImage exr = smallImage(false);
    io::writeExr(dir / "float.exr", exr);
    OIIO::ImageSpec spec;
    const std::vector<float> back = readChannels(dir / "float.exr", spec);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    ASSERT_EQ(spec.nchannels, 6);
    EXPECT_EQ(spec.channelformat(4), OIIO::TypeDesc::FLOAT);
    // Reading in file order gives R, G, B, A first; OpenEXR sorts the rest by name.
    EXPECT_EQ(spec.channelnames[0], "R");
    EXPECT_EQ(spec.channelnames[3], "A");
    const int z = spec.channelindex("Z"), fog = spec.channelindex("fog.R");
    ASSERT_GE(z, 0);
    ASSERT_GE(fog, 0);
    for (int p = 0; p < 6; ++p) {
        EXPECT_EQ(back[p * 6 + 0], exr.pixels[p * 6 + 0]); // 1.0001 exactly at p = 0
        EXPECT_EQ(back[p * 6 + z], exr.pixels[p * 6 + 4]);
        EXPECT_EQ(back[p * 6 + fog], exr.pixels[p * 6 + 5]);
    }
    EXPECT_EQ(spec.get_string_attribute("veil:scene"), "/x/scene.json");
    EXPECT_EQ(spec.get_string_attribute("veil:oit"), "wboit");
    const OIIO::ParamValue* m = spec.find_attribute("worldtocamera", OIIO::TypeDesc::TypeMatrix44);
    ASSERT_TRUE(m);
    const float* v = static_cast<const float*>(m->data());
    for (int i = 0; i < 16; ++i)
        EXPECT_EQ(v[i], float(i) + 0.5f);

    io::writeExr(dir / "half.exr", smallImage(true));
    const std::vector<float> halfBack = readChannels(dir / "half.exr", spec);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::HALF);
    ASSERT_FALSE(halfBack.empty());
    EXPECT_EQ(halfBack[0], 1.0f); // half cannot hold 1.0001
    // 0.7 through the plain image writer: rounded to nearest.
    ImageF img(2, 1, 3);
    std::fill(img.pixels.begin(), img.pixels.end(), 0.7f);
    io::writeImage(dir / "plain.exr", img);
    const std::vector<float> plain = readChannels(dir / "plain.exr", spec);
    ASSERT_FALSE(plain.empty());
    EXPECT_EQ(plain[0], 1434.0f / 2048.0f);
}

TEST(Sha256Test, MatchesTheStandardsExamples) {
    // FIPS 180-4 / NIST CSRC examples: one block, two blocks, and the empty message.
    EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    // A million 'a' through the file path (several 64 KiB reads).
    const fs::path p = outputDir() / "sha256-million-a.txt";
    std::ofstream(p, std::ios::binary) << std::string(1000000, 'a');
    EXPECT_EQ(sha256File(p), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    EXPECT_THROW(sha256File(outputDir() / "no-such-file"), std::exception);
}

} // namespace veil::test
