// KTX2 output: read back equal (RGBA32F exactly, RGBA16F to half precision), half-range clamping
// counted, metadata kept.
#include <filesystem>

#include <fmt/format.h>
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
