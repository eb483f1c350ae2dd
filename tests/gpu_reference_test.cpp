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

// Random radiance in [0, 1) scaled by 1 + face: a chunk of the source summed twice, left out or read
// from the wrong face shows at every level.
CubeImage structuredProbe(int size, unsigned seed) {
    CubeImage probe = probetest::randomProbe(size, seed);
    for (std::size_t t = 0; t < texelCount(size); ++t) probe.set(t, probe.texel(t) * float(1 + t / (std::size_t(size) * size)));
    return probe;
}

// The GPU reference at `levels` (empty: every level) against probe::referenceLevel.
void expectGpuEqualsCpu(int size, const RoughnessMapping& mapping, unsigned seed, std::vector<int> levels = {}, Lobe lobe = Lobe::ggx) {
    const CubeImage source = structuredProbe(size, seed);
    const int levelCount = defaultLevelCount(size);
    gpu::FilterSettings settings;
    settings.method.kind = MethodKind::reference;
    settings.method.lobe = lobe;
    settings.faceSize = size;
    settings.levelCount = levelCount;
    settings.mapping = mapping;
    settings.computedLevels = levels;
    gpu::Filter filter(probetest::testDevice(), settings);
    const CubeLevels gpuLevels = filter.run(source);
    if (levels.empty())
        for (int m = 0; m < levelCount; ++m) levels.push_back(m);
    for (int m : levels) {
        const CubeImage cpu = referenceLevel(source, size >> m, levelAlpha(mapping, m, levelCount), lobe);
        const double error = probetest::maxRelativeError(gpuLevels[m], cpu);
        ::testing::Test::RecordProperty(fmt::format("level{}_relative_error", m), fmt::format("{:.3g}", error));
        EXPECT_LT(error, kTolerance) << "size " << size << " level " << m;
    }
}

} // namespace

TEST_F(GpuTest, ReferenceEqualsCpuReference32) { expectGpuEqualsCpu(32, RoughnessMapping::gltf, 1); }
TEST_F(GpuTest, ReferenceEqualsCpuReference64) { expectGpuEqualsCpu(64, RoughnessMapping::gltf, 2); }
// Charlie: every level filtered (none is a copy), with its kernel's own constants.
TEST_F(GpuTest, CharlieReferenceEqualsCpuReference32) { expectGpuEqualsCpu(32, RoughnessMapping::gltf, 6, {}, Lobe::charlie); }
TEST_F(GpuTest, ReferenceEqualsCpuReferenceAuthorsMapping) { expectGpuEqualsCpu(32, RoughnessMapping::authors, 3); }
// From 128^2 the source is summed in several chunks per face (reference_pass.cpp), and a whole
// source exceeds what one lavapipe invocation may loop over: every level at 128^2, and at 256^2 every
// texel of levels 3-7 (each output texel sums all 393216 source texels; the finer levels cost minutes
// on lavapipe).
TEST_F(GpuTest, ReferenceEqualsCpuReference128) { expectGpuEqualsCpu(128, RoughnessMapping::gltf, 4); }
TEST_F(GpuTest, ReferenceEqualsCpuReference256CoarseLevels) { expectGpuEqualsCpu(256, RoughnessMapping::gltf, 5, {3, 4, 5, 6, 7}); }

TEST_F(GpuTest, ReferenceWhiteFurnace) {
    const glm::vec3 radiance(0.25f, 1.0f, 3.0f);
    gpu::FilterSettings settings;
    settings.method.kind = MethodKind::reference;
    settings.faceSize = 32;
    settings.levelCount = maxLevelCount(32);
    gpu::Filter filter(probetest::testDevice(), settings);
    const CubeLevels levels = filter.run(constantProbe(32, radiance));
    for (int m = 0; m < settings.levelCount; ++m)
        EXPECT_LT(probetest::maxRelativeError(levels[m], CubeImage(32 >> m, radiance)), 1e-5) << "level " << m;
}
