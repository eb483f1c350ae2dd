// A probe read from a KTX2 file, bounded: the header is checked against the limits before any pixel
// memory is taken, only level 0 is read, and it is decoded as it streams in (Zstandard included).
#pragma once

#include <cstdint>
#include <filesystem>
#include <istream>

#include "probe/cube_image.h"

namespace probe {

// Decodes level 0 of the KTX2 file that `in` holds (`byteCount` bytes from its current position): a
// cube (its faces one above the other, 1:6, in the file's +X, -X, +Y, -Y, +Z, -Z order) or a 2D
// image (turned upright by its KTXorientation), of one layer, in R16G16B16A16_SFLOAT,
// R16G16B16_SFLOAT, R32G32B32A32_SFLOAT, R32G32B32_SFLOAT, B10G11R11_UFLOAT_PACK32 or
// E5B9G9R9_UFLOAT_PACK32, stored as it is or with Zstandard (supercompression scheme 2). Alpha is
// dropped. Throws ProbeError naming `path` and the problem.
Image readKtx2Image(std::istream& in, std::uintmax_t byteCount, const std::filesystem::path& path);

} // namespace probe
