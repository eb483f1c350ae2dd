// What the GPU tests share: one validated Vulkan device per test binary (Mesa's lavapipe in CI),
// a check that the validation layer said nothing during each test, random probes, and the
// relative comparison of GPU results with their CPU models.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "probe/cube_image.h"
#include "probe/runtime.h"

namespace probetest {

// The device of the whole binary, with VK_LAYER_KHRONOS_validation on; PROBE_TEST_DEVICE picks
// another than the default (lavapipe in CI).
inline probe::gpu::Device& testDevice() {
    static probe::gpu::Device device([] {
        probe::gpu::DeviceOptions options;
        options.validation = true;
        if (const char* choice = std::getenv("PROBE_TEST_DEVICE")) options.choice = choice;
        return options;
    }());
    return device;
}

// Fails a test during which the validation layer reported anything.
class GpuTest : public ::testing::Test {
protected:
    void SetUp() override { messagesBefore_ = testDevice().validationMessages().size(); }
    void TearDown() override {
        const std::vector<std::string> messages = testDevice().validationMessages();
        for (std::size_t k = messagesBefore_; k < messages.size(); ++k) ADD_FAILURE() << "validation: " << messages[k];
    }

private:
    std::size_t messagesBefore_ = 0;
};

// The settings that run a table as it was fitted: its size, level count, mapping and pyramid.
inline probe::gpu::FilterSettings tableSettings(const probe::TapTable& table, probe::gpu::Sampling sampling = probe::gpu::Sampling::exact) {
    probe::gpu::FilterSettings s;
    s.method = {probe::MethodKind::table, &table, {}, table.lobe};
    s.faceSize = table.faceSize;
    s.levelCount = table.levelCount;
    s.mapping = table.mapping;
    s.sampling = sampling;
    return s;
}

// The sampling modes that the GPU-equals-model tests run, with how far each may be from the CPU
// model, relative to the brightest texel that a read blends (maxRelativeError):
// - exact: the shader's float arithmetic on the same texels as the double model: float rounding of
//   positions (~1e-7 texel), weights and sums.
// - hardware: the sampler's bilinear and between-mip weights carry 8 fractional bits on the GPUs
//   the runtime targets (the Vulkan minimum is 4: subTexelPrecisionBits, mipmapPrecisionBits), and
//   Vulkan leaves their rounding open, so a read may be off by 2^-8 of the contrast of the texels it
//   blends in each of its three linear steps: at most 3 x 2^-8 = 1.2% on probes of contrast 1. An
//   NVIDIA H200 (driver 580) measures 0.61% at worst (FIS beside a FLT_MAX spike), above the 0.59%
//   that rounding to nearest would allow; lavapipe's float weights come far closer (each test
//   records what it measures).
struct SamplingCase {
    probe::gpu::Sampling sampling;
    double tolerance;
};
inline constexpr SamplingCase kSamplingCases[] = {{probe::gpu::Sampling::exact, 1e-5}, {probe::gpu::Sampling::hardware, 1.2e-2}};

// The copy regions of `mips` levels of a cube image (every face of a level in one region) from face
// size `size`, packed one after another in a buffer of `texelBytes`-byte texels.
inline std::vector<VkBufferImageCopy> levelRegions(int size, int mips, std::size_t texelBytes, int cubes = 1) {
    std::vector<VkBufferImageCopy> regions;
    VkDeviceSize offset = 0;
    for (int m = 0; m < mips; ++m) {
        VkBufferImageCopy region{};
        region.bufferOffset = offset;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, uint32_t(6 * cubes)};
        region.imageExtent = {uint32_t(size >> m), uint32_t(size >> m), 1};
        regions.push_back(region);
        offset += probe::texelCount(size >> m) * texelBytes * std::size_t(cubes);
    }
    return regions;
}

// Independent uniform radiance in [0, 1) per texel and channel.
inline probe::CubeImage randomProbe(int faceSize, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    probe::CubeImage probe(faceSize);
    for (float& c : probe.rgb) c = uniform(random);
    return probe;
}

// max |gpu - cpu| / max(|cpu|, floor) over texels and channels: the relative error, with `floor`
// keeping near-black texels from dividing by ~0.
inline double maxRelativeError(const probe::CubeImage& gpu, const probe::CubeImage& cpu, double floor = 1e-3) {
    double worst = 0.0;
    for (std::size_t k = 0; k < cpu.rgb.size(); ++k)
        worst = std::max(worst, std::abs(double(gpu.rgb[k]) - cpu.rgb[k]) / std::max(std::abs(double(cpu.rgb[k])), floor));
    return worst;
}

} // namespace probetest
