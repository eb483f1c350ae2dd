// KTX2 output for engines: an uncompressed RGBA16F or RGBA32F cube with every level, a basic data
// format descriptor (RGBSDA, BT.709 primaries, linear), and key/value metadata.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "probe/cube_image.h"

namespace probe {

enum class Ktx2PixelFormat { rgba16f, rgba32f };

using KeyValues = std::vector<std::pair<std::string, std::string>>;

// Writes levels[0..] (face size halving each level, alpha 1) as one cube map. RGBA16F clamps
// values above the half-float range to 65504; returns how many values were clamped. Throws
// ProbeError naming the file on failure.
std::size_t writeKtx2Cube(const std::filesystem::path& path, const CubeLevels& levels, Ktx2PixelFormat format, const KeyValues& metadata);

// Reads back a cube written by writeKtx2Cube (RGB of every level, and its metadata).
struct Ktx2Cube {
    Ktx2PixelFormat format = Ktx2PixelFormat::rgba16f;
    CubeLevels levels;
    KeyValues metadata;
};
Ktx2Cube readKtx2Cube(const std::filesystem::path& path);

} // namespace probe
