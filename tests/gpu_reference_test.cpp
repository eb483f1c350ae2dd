// The GPU reference (shaders/reference.comp) equals the CPU reference (probe::referenceFilter) on
// random probes, every level and face, and keeps a constant probe constant.
#include <fmt/format.h>

#include "gpu_test_support.h"
#include "probe/reference.h"
#include "probe/synthetic.h"

using namespace probe;
using probetest::GpuTest;

namespace {

// Both compute every kernel value in float from the same float directions and solid angles; the
// CPU sums rows in float and rows in double, the GPU rows in float and rows with Kahan in float, so
// they differ by float rounding of sums over S texels: ~1e-6 relative.
constexpr double kTolerance = 1e-5;

void expectGpuEqualsCpu(int size, RoughnessMapping mapping, unsigned seed) {
    const CubeImage source = probetest::randomProbe(size, seed);
    const int levels = defaultLevelCount(size);
    gpu::FilterSettings settings;
    settings.method = gpu::Method::reference;
    settings.faceSize = size;
    settings.levelCount = levels;
    settings.mapping = mapping;
    gpu::Filter filter(probetest::testDevice(), settings);
    const CubeLevels gpuLevels = filter.run(source);
    const CubeLevels cpuLevels = referenceFilter(source, levels, mapping);
    ASSERT_EQ(gpuLevels.size(), cpuLevels.size());
    for (int m = 0; m < levels; ++m) {
        const double error = probetest::maxRelativeError(gpuLevels[m], cpuLevels[m]);
        ::testing::Test::RecordProperty(fmt::format("level{}_relative_error", m), fmt::format("{:.3g}", error));
        EXPECT_LT(error, kTolerance) << "size " << size << " level " << m;
    }
}

} // namespace

TEST_F(GpuTest, ReferenceEqualsCpuReference32) { expectGpuEqualsCpu(32, RoughnessMapping::gltf, 1); }
TEST_F(GpuTest, ReferenceEqualsCpuReference64) { expectGpuEqualsCpu(64, RoughnessMapping::gltf, 2); }
TEST_F(GpuTest, ReferenceEqualsCpuReferenceAuthorsMapping) { expectGpuEqualsCpu(32, RoughnessMapping::authors, 3); }

TEST_F(GpuTest, ReferenceWhiteFurnace) {
    const glm::vec3 radiance(0.25f, 1.0f, 3.0f);
    gpu::FilterSettings settings;
    settings.method = gpu::Method::reference;
    settings.faceSize = 32;
    settings.levelCount = maxLevelCount(32);
    gpu::Filter filter(probetest::testDevice(), settings);
    const CubeLevels levels = filter.run(constantProbe(32, radiance));
    for (int m = 0; m < settings.levelCount; ++m)
        EXPECT_LT(probetest::maxRelativeError(levels[m], CubeImage(32 >> m, radiance)), 1e-5) << "level " << m;
}
