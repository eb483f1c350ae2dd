// The output and pyramid formats: RGBA16F and B10G11R11 outputs hold the RGBA32F result rounded to
// their precision in both sampling modes, values beyond a format's range are clamped to its largest
// finite value, B10G11R11 reaches the same texels through the conversion pass where the device
// cannot store it, the pyramid is RGBA16F by default (RGBA32F where the device cannot filter and store
// that) or the format asked for, a probe brighter than a half pyramid holds keeps its light, and
// formats the device or the filter cannot use are refused by name.
#include "gpu_test_support.h"

#include <fmt/format.h>

#include "device.h"
#include "probe/bc6h.h"
#include "probe/error.h"
#include "probe/pyramid.h"
#include "probe/range_scale.h"
#include "probe/reference.h"
#include "probe/shared_constants.h"
#include "probe/synthetic.h"

using namespace probe;
using probetest::GpuTest;

namespace {

constexpr int kSize = 16;

// The largest relative rounding error of a format's channels: one spacing of its mantissa, since
// Vulkan lets an image store round to nearest or toward zero (lavapipe truncates): RGBA16F 10 bits;
// B10G11R11 6 bits (R, G) and 5 (B).
double relativeRounding(VkFormat format) { return format == VK_FORMAT_R16G16B16A16_SFLOAT ? 0x1p-10 : 0x1p-5; }

CubeLevels runWith(const gpu::Device& device, gpu::FilterSettings s, VkFormat format, const CubeImage& probe) {
    s.outputFormat = format;
    gpu::Filter filter(device, s);
    return filter.run(probe);
}

void expectRounded(const CubeLevels& out, const CubeLevels& full, VkFormat format, const std::string& what) {
    ASSERT_EQ(out.size(), full.size());
    const double tolerance = relativeRounding(format);
    for (std::size_t m = 0; m < full.size(); ++m)
        for (std::size_t k = 0; k < full[m].rgb.size(); ++k) {
            const double expected = full[m].rgb[k];
            // Values below the smallest normal round to a multiple of it.
            ASSERT_NEAR(out[m].rgb[k], expected, tolerance * std::abs(expected) + 1e-7) << what << " level " << m << " [" << k << "]";
        }
}

gpu::FilterSettings fisSettings(gpu::Sampling sampling) {
    gpu::FilterSettings s;
    s.method.kind = MethodKind::fis;
    s.method.fis.samples = {16};
    s.faceSize = kSize;
    s.levelCount = defaultLevelCount(kSize);
    s.sampling = sampling;
    return s;
}

TEST_F(GpuTest, OutputFormatsHoldTheRgba32fResultRounded) {
    const CubeImage probe = sunSkyProbe(kSize);
    for (const probetest::SamplingCase& c : probetest::kSamplingCases) {
        const gpu::FilterSettings s = fisSettings(c.sampling);
        const CubeLevels full = runWith(probetest::testDevice(), s, VK_FORMAT_R32G32B32A32_SFLOAT, probe);
        for (VkFormat format : {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_B10G11R11_UFLOAT_PACK32})
            expectRounded(runWith(probetest::testDevice(), s, format, probe), full, format,
                          fmt::format("{} {}", gpu::samplingName(c.sampling), gpu::formatName(format)));
    }
}

TEST_F(GpuTest, OutputBeyondTheFormatsRangeIsItsLargestFiniteValue) {
    const CubeImage probe = constantProbe(kSize, glm::vec3(1e6f)); // beyond half's 65504
    const CubeLevels out = runWith(probetest::testDevice(), fisSettings(gpu::Sampling::hardware), VK_FORMAT_R16G16B16A16_SFLOAT, probe);
    for (const CubeImage& level : out)
        for (float v : level.rgb) ASSERT_EQ(v, 65504.0f);
}

// A device that cannot store B10G11R11 (what Device::Impl reports for one) gets the same texels
// through the conversion pass and a copy.
TEST_F(GpuTest, B10G11R11ThroughTheConversionPassEqualsTheDirectStore) {
    const gpu::Device& shared = probetest::testDevice();
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    const CubeImage probe = sunSkyProbe(kSize);
    gpu::FilterSettings s = fisSettings(gpu::Sampling::hardware);
    s.outputFormat = VK_FORMAT_B10G11R11_UFLOAT_PACK32;
    gpu::Filter direct(shared, s);
    ASSERT_FALSE(direct.outputNeedsTransfer()) << "the test device stores B10G11R11";
    const CubeLevels expected = direct.run(probe);
    device.impl().formatFeatures[VK_FORMAT_B10G11R11_UFLOAT_PACK32] &= ~VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT;
    gpu::Filter converted(device, s);
    EXPECT_TRUE(converted.outputNeedsTransfer());
    expectRounded(converted.run(probe), runWith(shared, s, VK_FORMAT_R32G32B32A32_SFLOAT, probe), s.outputFormat, "converted");
    const CubeLevels out = converted.run(probe);
    double worst = 0.0;
    for (std::size_t m = 0; m < out.size(); ++m) worst = std::max(worst, probetest::maxRelativeError(out[m], expected[m]));
    // Both round to the format: they differ at most by its spacing where the rounding modes differ.
    EXPECT_LE(worst, 2.0 * relativeRounding(s.outputFormat));
}

// Each pyramid texel rounded to half: each output blends them, so the relative error stays the
// half's, with room for the roundings of the mips that feed each other.
constexpr double kHalfPyramidTolerance = 4 * 0x1p-10;
// The same for E5B9G9R9, whose shared exponent rounds every channel of a texel to a step of its
// brightest channel's: within 2^-9 of that channel (maxErrorOfBrightest).
constexpr double kRgb9e5PyramidTolerance = 4 * 0x1p-9;

// The largest difference of a channel over all texels, relative to the brightest channel of the
// texel (at least `floor`).
double maxErrorOfBrightest(const CubeImage& out, const CubeImage& expected, double floor = 1e-3) {
    double worst = 0.0;
    for (std::size_t t = 0; t < texelCount(expected.size); ++t) {
        const glm::vec3 e = expected.texel(t), o = out.texel(t);
        const double brightest = std::max({double(std::abs(e.r)), double(std::abs(e.g)), double(std::abs(e.b)), floor});
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(o[c]) - double(e[c])) / brightest);
    }
    return worst;
}

// The error of `out` against `full`, as a pyramid format's tolerance measures it.
double pyramidError(VkFormat pyramid, const CubeImage& out, const CubeImage& full) {
    return pyramid == VK_FORMAT_E5B9G9R9_UFLOAT_PACK32 ? maxErrorOfBrightest(out, full) : probetest::maxRelativeError(out, full);
}

double pyramidTolerance(VkFormat pyramid) {
    return pyramid == VK_FORMAT_R16G16B16A16_SFLOAT      ? kHalfPyramidTolerance
           : pyramid == VK_FORMAT_E5B9G9R9_UFLOAT_PACK32 ? kRgb9e5PyramidTolerance
                                                         : 0.0;
}

// E5B9G9R9 of `c` by the Vulkan specification's conversion ("Shared Exponent Formats"), decoded:
// negative values 0, each channel rounded to nearest in steps of 2^(exponent - 24).
glm::vec3 rgb9e5Rounded(glm::vec3 c) {
    c = glm::clamp(c, glm::vec3(0.0f), glm::vec3(float(PROBE_RGB9E5_MAX)));
    const double largest = std::max({c.r, c.g, c.b});
    int exponent = std::max(-16, largest > 0.0 ? int(std::floor(std::log2(largest))) : -16) + 16;
    if (std::floor(std::ldexp(largest, 24 - exponent) + 0.5) == 512.0) ++exponent;
    glm::vec3 rounded;
    for (int k = 0; k < 3; ++k) rounded[k] = float(std::ldexp(std::floor(std::ldexp(double(c[k]), 24 - exponent) + 0.5), exponent - 24));
    return rounded;
}

TEST_F(GpuTest, PyramidIsRgba16fByDefaultAndRgba32fWhereTheDeviceLacksIt) {
    const gpu::Device& shared = probetest::testDevice();
    const gpu::FilterSettings s = fisSettings(gpu::Sampling::hardware);
    EXPECT_EQ(gpu::Filter(shared, s).pyramidFormat(), VK_FORMAT_R16G16B16A16_SFLOAT);
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    device.impl().formatFeatures[VK_FORMAT_R16G16B16A16_SFLOAT] &= ~VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
    gpu::Filter filter(device, s);
    EXPECT_EQ(filter.pyramidFormat(), VK_FORMAT_R32G32B32A32_SFLOAT);
    gpu::FilterSettings asked = s;
    asked.pyramidFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    const CubeImage probe = sunSkyProbe(kSize);
    const CubeLevels out = filter.run(probe), full = runWith(shared, asked, VK_FORMAT_R32G32B32A32_SFLOAT, probe);
    for (std::size_t m = 0; m < out.size(); ++m) EXPECT_EQ(probetest::maxRelativeError(out[m], full[m]), 0.0) << "level " << m;
}

// run() filters a probe brighter than an RGBA16F pyramid holds scaled down by a power of two and
// scales the output back: the RGBA32F pyramid's result within half rounding, for a float32 output
// and, saturated at 65504 alike, for an RGBA16F one. Without the scaling the sun would clamp at 65504
// and every level would lose most of its light.
TEST_F(GpuTest, ProbeBrighterThanAHalfPyramidKeepsItsLight) {
    const CubeImage probe = shifted(sunSkyProbe(kSize), 20);
    ASSERT_GT(largestMagnitude(probe), 1e6f);
    gpu::FilterSettings narrow = fisSettings(gpu::Sampling::hardware), full = narrow;
    full.pyramidFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    for (VkFormat pyramid : {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_E5B9G9R9_UFLOAT_PACK32}) {
        narrow.pyramidFormat = pyramid;
        for (VkFormat format : {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT}) {
            const CubeLevels out = runWith(probetest::testDevice(), narrow, format, probe);
            const CubeLevels expected = runWith(probetest::testDevice(), full, format, probe);
            for (std::size_t m = 0; m < out.size(); ++m)
                EXPECT_LE(pyramidError(pyramid, out[m], expected[m]), pyramidTolerance(pyramid))
                    << gpu::formatName(pyramid) << " pyramid, " << gpu::formatName(format) << " output, level " << m;
        }
    }
}

// A pyramid format asked for is used as it is: RGBA16F within half rounding of RGBA32F (at 16^2, and
// at 64^2, where the first dispatch builds mips 0 to 2 from the source); a format the device cannot
// filter and store, one that is no pyramid format, or one asked of exact sampling (a float32 buffer)
// is refused by name.
TEST_F(GpuTest, PyramidFormatIsTheOneAskedFor) {
    const gpu::Device& shared = probetest::testDevice();
    gpu::FilterSettings s = fisSettings(gpu::Sampling::hardware);
    for (const int size : {kSize, 64}) {
        const CubeImage probe = sunSkyProbe(size);
        s.faceSize = size;
        s.levelCount = defaultLevelCount(size);
        s.pyramidFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
        const CubeLevels full = runWith(shared, s, VK_FORMAT_R32G32B32A32_SFLOAT, probe);
        for (VkFormat format : {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_E5B9G9R9_UFLOAT_PACK32}) {
            s.pyramidFormat = format;
            gpu::Filter filter(shared, s);
            EXPECT_EQ(filter.pyramidFormat(), format);
            const CubeLevels out = filter.run(probe);
            for (std::size_t m = 0; m < out.size(); ++m)
                EXPECT_LE(pyramidError(format, out[m], full[m]), pyramidTolerance(format))
                    << size << "^2, " << gpu::formatName(format) << " level " << m;
        }
    }
    s = fisSettings(gpu::Sampling::hardware);

    const auto refusal = [](const gpu::Device& device, const gpu::FilterSettings& settings) -> std::string {
        try {
            gpu::Filter filter(device, settings);
        } catch (const ProbeError& e) {
            return e.what();
        }
        return "accepted";
    };
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    device.impl().formatFeatures[VK_FORMAT_R32G32B32A32_SFLOAT] &= ~VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
    s.pyramidFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    const std::string unfiltered = refusal(device, s);
    EXPECT_NE(unfiltered.find("rgba32f"), std::string::npos) << unfiltered;
    EXPECT_NE(unfiltered.find("filter"), std::string::npos) << unfiltered;
    device.impl().formatFeatures[VK_FORMAT_R32_UINT] &= ~VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT;
    s.pyramidFormat = VK_FORMAT_E5B9G9R9_UFLOAT_PACK32;
    const std::string unstored = refusal(device, s);
    EXPECT_NE(unstored.find("rgb9e5"), std::string::npos) << unstored;
    s.pyramidFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
    for (gpu::FilterSettings bad : {s, fisSettings(gpu::Sampling::exact)}) {
        bad.pyramidFormat = bad.sampling == gpu::Sampling::exact ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_B10G11R11_UFLOAT_PACK32;
        try {
            gpu::Filter filter(shared, bad);
            ADD_FAILURE() << "pyramid format " << int(bad.pyramidFormat) << " accepted with " << gpu::samplingName(bad.sampling);
        } catch (const ParameterError& e) {
            EXPECT_EQ(e.parameter, "pyramidFormat");
        }
    }
    EXPECT_EQ(gpu::parsePyramidFormat("auto"), VK_FORMAT_UNDEFINED);
    EXPECT_EQ(gpu::parsePyramidFormat("rgba16f"), VK_FORMAT_R16G16B16A16_SFLOAT);
    EXPECT_EQ(gpu::parsePyramidFormat("rgb9e5"), VK_FORMAT_E5B9G9R9_UFLOAT_PACK32);
    EXPECT_THROW(gpu::parsePyramidFormat("b10g11r11"), ParameterError);
}

// An E5B9G9R9 pyramid holds each source texel as the Vulkan specification rounds it, bit for bit:
// over 36 binades, at 0, at its largest value, where rounding carries into the next exponent, and
// negative values as 0; each coarser mip, for one probe and in a batch, is the model's of the mip
// above within the sampler's precision and the format's rounding.
TEST_F(GpuTest, Rgb9e5PyramidRoundsAsTheSpecification) {
    constexpr int kFace = 32; // mips 0 and 1 a dispatch each, the tail from 8^2
    CubeImage probe = probetest::randomProbe(kFace, 23);
    for (std::size_t t = 0; t < texelCount(kFace); ++t) probe.set(t, probe.texel(t) * std::ldexp(1.0f, int(t % 36) - 20));
    probe.set(0, glm::vec3(0.0f));
    probe.set(1, glm::vec3(float(PROBE_RGB9E5_MAX)));
    probe.set(2, glm::vec3(511.75f, 1.0f, 0.5f)); // rounds to 512: the exponent goes up by one
    probe.set(3, glm::vec3(-1.0f, 2.0f, 3.0f));
    gpu::FilterSettings s = fisSettings(gpu::Sampling::hardware);
    s.faceSize = kFace;
    s.levelCount = defaultLevelCount(kFace);
    s.pyramidFormat = VK_FORMAT_E5B9G9R9_UFLOAT_PACK32;
    for (const int batch : {1, 2}) {
        s.batchSize = batch;
        gpu::Filter filter(probetest::testDevice(), s);
        filter.run(std::vector<CubeImage>(std::size_t(batch), probe));
        const CubeLevels pyramid = filter.downloadPyramid();
        int mismatches = 0;
        for (std::size_t t = 0; t < texelCount(kFace); ++t)
            if (pyramid[0].texel(t) != rgb9e5Rounded(probe.texel(t)) && mismatches++ < 4)
                ADD_FAILURE() << "batch of " << batch << ", mip 0 texel " << t << ": " << pyramid[0].texel(t).r << " "
                              << pyramid[0].texel(t).g << " " << pyramid[0].texel(t).b << " for " << probe.texel(t).r << " "
                              << probe.texel(t).g << " " << probe.texel(t).b;
        EXPECT_EQ(mismatches, 0) << "batch of " << batch;
        for (std::size_t k = 1; k < pyramid.size(); ++k)
            EXPECT_LE(maxErrorOfBrightest(pyramid[k], buildPyramid(pyramid[k - 1], PyramidSettings{})[1], 1e-30),
                      probetest::kSamplingCases[1].tolerance + 0x1p-9)
                << "batch of " << batch << ", mip " << k;
    }
}

TEST_F(GpuTest, UnusableFormatsAreRefusedByName) {
    gpu::FilterSettings s = fisSettings(gpu::Sampling::hardware);
    s.outputFormat = VK_FORMAT_R8G8B8A8_UNORM;
    try {
        gpu::Filter filter(probetest::testDevice(), s);
        ADD_FAILURE() << "an RGBA8 output was accepted";
    } catch (const ParameterError& e) {
        EXPECT_EQ(e.parameter, "outputFormat");
    }
    const gpu::Device& shared = probetest::testDevice();
    const gpu::Device device(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    device.impl().formatFeatures[VK_FORMAT_R16G16B16A16_SFLOAT] &= ~VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT;
    s.outputFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
    try {
        gpu::Filter filter(device, s);
        ADD_FAILURE() << "an output format the device cannot store was accepted";
    } catch (const ProbeError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("rgba16f"), std::string::npos) << message;
        EXPECT_NE(message.find("storage"), std::string::npos) << message;
    }
}

} // namespace

// The BC6H encoder: each level's blocks (six faces of ceil(S / 4)^2, 16 bytes each), none in a
// reserved mode (which a decoder reads as black), the same bytes every time; a level not computed
// encodes as black; levels of another size or count are refused. tests/bc6h_independent_decoder.sh
// decodes the blocks with bcdec.
TEST_F(GpuTest, Bc6hEncoderWritesEveryLevelsBlocks) {
    const int size = 16, levelCount = 5;
    gpu::Bc6hEncoder encoder(probetest::testDevice(), size, levelCount);
    CubeLevels levels = referenceFilter(sunSkyProbe(size), levelCount, RoughnessMapping::gltf);
    const std::vector<std::vector<uint8_t>> blocks = encoder.encode(levels);
    ASSERT_EQ(blocks.size(), std::size_t(levelCount));
    for (int m = 0; m < levelCount; ++m) {
        EXPECT_EQ(blocks[m].size(), bc6hLevelBytes(size >> m)) << "level " << m;
        for (std::size_t b = 0; b < blocks[m].size(); b += 16) {
            const unsigned mode = (blocks[m][b] & 3u) < 2 ? blocks[m][b] & 3u : blocks[m][b] & 31u;
            EXPECT_TRUE(mode != 0x13 && mode != 0x17 && mode != 0x1B && mode != 0x1F) << "level " << m << ", block " << b / 16;
        }
    }
    EXPECT_EQ(bc6hLevelBytes(2), 6u * 16u);
    EXPECT_EQ(encoder.encode(levels), blocks);
    EXPECT_FALSE(encoder.timings().empty());

    CubeLevels partial = levels;
    partial[2] = CubeImage();
    CubeLevels black = levels;
    black[2] = CubeImage(size >> 2);
    EXPECT_EQ(encoder.encode(partial)[2], encoder.encode(black)[2]);

    CubeLevels wrong = levels;
    wrong[1] = CubeImage(size);
    EXPECT_THROW(encoder.encode(wrong), ProbeError);

    // On a device whose storage-buffer range holds two faces of level 0 (the test device, wrapped), the
    // encoder reads the levels through windows, a dispatch each: the same blocks.
    const gpu::Device& shared = probetest::testDevice();
    const gpu::Device narrow(shared.instance(), shared.physicalDevice(), shared.device(), shared.queueFamily(), shared.queue());
    narrow.impl().limits.maxStorageBufferRange = uint32_t(2 * size * size * 16);
    gpu::Bc6hEncoder windowed(narrow, size, levelCount);
    EXPECT_EQ(windowed.encode(levels), blocks);
    levels.pop_back();
    EXPECT_THROW(encoder.encode(levels), ProbeError);
}
