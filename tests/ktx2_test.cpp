// KTX2 output: read back equal (RGBA32F exactly, RGBA16F to half precision, RGB9E5 to its shared
// exponent's), clamping to each format's range counted, metadata kept; Zstandard supercompression
// gives the same levels back.
#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
#include <glm/common.hpp>
#include <gtest/gtest.h>
#include <unistd.h>

#include "probe/ktx2.h"
#include "probe/reference.h"
#include "probe/synthetic.h"

using namespace probe;
namespace fs = std::filesystem;

TEST(Ktx2, RoundTrip) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_test_{}", ::getpid());
    fs::create_directories(dir);
    CubeImage source = sunSkyProbe(16);
    source.set(5, glm::vec3(1e6f, 2.0f, 70000.0f)); // two values beyond the half range
    const CubeLevels levels = referenceFilter(source, 4, RoughnessMapping::gltf);
    const KeyValues metadata{{"probefilter.mapping", "gltf"}, {"KTXwriter", "probefilter"}};

    EXPECT_EQ(writeKtx2Cube(dir / "a32.ktx2", levels, Ktx2PixelFormat::rgba32f, metadata), 0u);
    const Ktx2Cube full = readKtx2Cube(dir / "a32.ktx2");
    ASSERT_EQ(full.levels.size(), levels.size());
    for (std::size_t m = 0; m < levels.size(); ++m) EXPECT_EQ(full.levels[m].rgb, levels[m].rgb);
    EXPECT_EQ(full.metadata, (KeyValues{{"KTXwriter", "probefilter"}, {"probefilter.mapping", "gltf"}}));

    std::size_t beyondHalf = 0;
    for (const CubeImage& level : levels)
        for (float v : level.rgb) beyondHalf += v > 65504.0f;
    EXPECT_EQ(writeKtx2Cube(dir / "a16.ktx2", levels, Ktx2PixelFormat::rgba16f, metadata), beyondHalf);
    EXPECT_GE(beyondHalf, 2u);
    const Ktx2Cube half = readKtx2Cube(dir / "a16.ktx2");
    for (std::size_t m = 0; m < levels.size(); ++m)
        for (std::size_t k = 0; k < levels[m].rgb.size(); ++k) {
            const float expected = std::min(levels[m].rgb[k], 65504.0f);
            ASSERT_NEAR(half.levels[m].rgb[k], expected, expected * 1e-3f + 1e-7f);
        }
    fs::remove_all(dir);
}

// RGB9E5: every channel within half a step of the shared exponent's (2^-9 of the texel's brightest
// channel), values beyond 65408 and below 0 clamped and counted, a black texel black.
TEST(Ktx2, SharedExponentRoundTrip) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_e5_test_{}", ::getpid());
    fs::create_directories(dir);
    CubeLevels levels = referenceFilter(sunSkyProbe(16), 4, RoughnessMapping::gltf);
    levels[0].set(0, glm::vec3(1e6f, -0.5f, 3.0f)); // one value above the range, one below
    levels[0].set(1, glm::vec3(0.0f));
    levels[0].set(2, glm::vec3(65408.0f, 1e-9f, 0.25f));
    EXPECT_EQ(writeKtx2Cube(dir / "e5.ktx2", levels, Ktx2PixelFormat::rgb9e5, {}), 2u);
    const Ktx2Cube e5 = readKtx2Cube(dir / "e5.ktx2");
    EXPECT_EQ(e5.format, Ktx2PixelFormat::rgb9e5);
    ASSERT_EQ(e5.levels.size(), levels.size());
    for (std::size_t m = 0; m < levels.size(); ++m)
        for (std::size_t t = 0; t < texelCount(levels[m].size); ++t) {
            const glm::vec3 expected = glm::clamp(levels[m].texel(t), 0.0f, 65408.0f);
            const float step = std::max({expected.r, expected.g, expected.b}) / 512.0f + 1e-7f;
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(e5.levels[m].texel(t)[k], expected[k], step) << "level " << m << " texel " << t;
        }
    EXPECT_EQ(e5.levels[0].texel(1), glm::vec3(0.0f));
    EXPECT_EQ(e5.levels[0].texel(2).r, 65408.0f);
    fs::remove_all(dir);
}

// Zstandard supercompression: the same levels back, in a smaller file (a filtered probe's levels are
// smooth); every format.
TEST(Ktx2, ZstdSupercompressionRoundTrip) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_zstd_test_{}", ::getpid());
    fs::create_directories(dir);
    const CubeLevels levels = referenceFilter(sunSkyProbe(32), 6, RoughnessMapping::gltf);
    for (const Ktx2PixelFormat format : {Ktx2PixelFormat::rgba16f, Ktx2PixelFormat::rgba32f, Ktx2PixelFormat::rgb9e5}) {
        writeKtx2Cube(dir / "plain.ktx2", levels, format, {{"KTXwriter", "probefilter"}});
        writeKtx2Cube(dir / "zstd.ktx2", levels, format, {{"KTXwriter", "probefilter"}}, Ktx2Supercompression::zstd);
        const Ktx2Cube plain = readKtx2Cube(dir / "plain.ktx2"), zstd = readKtx2Cube(dir / "zstd.ktx2");
        EXPECT_EQ(plain.supercompression, Ktx2Supercompression::none);
        EXPECT_EQ(zstd.supercompression, Ktx2Supercompression::zstd);
        ASSERT_EQ(zstd.levels.size(), levels.size());
        for (std::size_t m = 0; m < levels.size(); ++m) EXPECT_EQ(zstd.levels[m].rgb, plain.levels[m].rgb) << ktx2FormatName(format);
        EXPECT_EQ(zstd.metadata, plain.metadata);
        EXPECT_LT(fs::file_size(dir / "zstd.ktx2"), fs::file_size(dir / "plain.ktx2")) << ktx2FormatName(format);
    }
    fs::remove_all(dir);
}
