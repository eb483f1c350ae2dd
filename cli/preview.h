// Pictures that people would rather see than read: tone-mapped PNGs of linear images, and a
// filtered probe as every level as an equirectangular panorama, stacked top (level 0) to bottom
// (roughest).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "probe/cube_image.h"

namespace probefilter {

// Exposure that maps the log-average luminance of a cube level to middle grey.
float autoExposure(const probe::CubeImage& level);

// Linear RGB times `exposure`, Reinhard, sRGB-encoded: 8-bit RGB pixels.
std::vector<std::uint8_t> tonemap(const probe::Image& linear, float exposure);

// Writes 8-bit RGB pixels (width * height * 3) as a PNG. Throws ProbeError naming the file.
void writePng(const std::filesystem::path& png, int width, int height, const std::vector<std::uint8_t>& pixels);

void writeLevelsPreview(const std::filesystem::path& png, const probe::CubeLevels& levels);

} // namespace probefilter
