#include "preview.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>

#include <fmt/format.h>

#include "probe/cube_footprint.h"
#include "probe/error.h"
#include "probe/output_file.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace probefilter {

namespace {

std::uint8_t encodeSrgb(float linear) {
    const float c = std::clamp(linear, 0.0f, 1.0f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return static_cast<std::uint8_t>(std::lround(s * 255.0f));
}

} // namespace

float autoExposure(const probe::CubeImage& level) {
    double logSum = 0.0;
    const std::size_t n = probe::texelCount(level.size);
    for (std::size_t t = 0; t < n; ++t) {
        const glm::vec3 c = level.texel(t);
        logSum += std::log(1e-4 + 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b);
    }
    return static_cast<float>(0.18 / std::exp(logSum / static_cast<double>(n)));
}

std::vector<std::uint8_t> tonemap(const probe::Image& linear, float exposure) {
    std::vector<std::uint8_t> pixels(linear.rgb.size());
    for (std::size_t k = 0; k < linear.rgb.size(); ++k) {
        const float c = linear.rgb[k] * exposure;
        pixels[k] = encodeSrgb(c / (1.0f + c)); // Reinhard
    }
    return pixels;
}

void writePng(const std::filesystem::path& png, int width, int height, const std::vector<std::uint8_t>& pixels) {
    // Encoded in memory: stb's file writer does not report a failed write.
    int bytes = 0;
    unsigned char* encoded = stbi_write_png_to_mem(pixels.data(), width * 3, width, height, 3, &bytes);
    if (!encoded) throw probe::ProbeError(fmt::format("{}: cannot encode PNG", png.string()));
    const std::unique_ptr<unsigned char, decltype(&std::free)> owned(encoded, &std::free);
    probe::writeFile(png, std::string_view(reinterpret_cast<const char*>(encoded), std::size_t(bytes)));
}

void writeLevelsPreview(const std::filesystem::path& png, const probe::CubeLevels& levels) {
    const int width = 512, height = 256;
    probe::Image panoramas{width, static_cast<int>(height * levels.size()),
                           std::vector<float>(std::size_t(width) * height * 3 * levels.size())};
    for (std::size_t m = 0; m < levels.size(); ++m)
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                // The equirectangular convention of probe_io.h.
                const double phi = ((x + 0.5) / width - 0.5) * 2.0 * std::numbers::pi;
                const double theta = (y + 0.5) / height * std::numbers::pi;
                const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
                const probe::CubeImage& level = levels[m];
                const glm::vec3 c(probe::sampleBilinear(level, d));
                float* p = &panoramas.rgb[((m * height + y) * width + x) * 3];
                for (int k = 0; k < 3; ++k) p[k] = c[k];
            }
    writePng(png, panoramas.width, panoramas.height, tonemap(panoramas, autoExposure(levels.front())));
}

} // namespace probefilter
