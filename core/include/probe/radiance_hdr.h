// Radiance RGBE (.hdr) reading, bounded: the size is checked against the limits before any pixel
// memory is taken, every run-length record must make progress, and a file that ends early is an error.
#pragma once

#include <cstdint>
#include <filesystem>
#include <istream>

#include "probe/cube_image.h"

namespace probe {

// Decodes the image that `in` holds (`byteCount` bytes from its current position): the header
// ("#?RADIANCE" or "#?RGBE", FORMAT=32-bit_rle_rgbe, resolution "-Y H +X W"), then H scanlines,
// each flat RGBE or new-style run-length encoded. Throws ProbeError naming `path` and the problem.
Image readRadianceHdr(std::istream& in, std::uintmax_t byteCount, const std::filesystem::path& path);

} // namespace probe
