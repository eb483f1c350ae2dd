// KTX2 output for engines: an uncompressed RGBA16F, RGBA32F or shared-exponent RGB9E5 cube, or a
// BC6H one from its blocks, with every level, a basic data format descriptor (BT.709 primaries,
// linear), and key/value metadata. What KTX2 reading and writing share.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "probe/cube_image.h"

namespace probe {

// The file's first 12 bytes.
inline constexpr std::array<std::uint8_t, 12> kKtx2Identifier{0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
// The VkFormat values a KTX2 header records, named here so that the tools need no Vulkan headers.
namespace vk_format {
inline constexpr std::uint32_t r16g16b16_sfloat = 90, r16g16b16a16_sfloat = 97, r32g32b32_sfloat = 106, r32g32b32a32_sfloat = 109,
                               b10g11r11_ufloat_pack32 = 122, e5b9g9r9_ufloat_pack32 = 123, bc6h_ufloat_block = 143,
                               bc6h_sfloat_block = 144;
}
// KTX2's supercompression scheme 2: each level compressed with Zstandard on its own.
inline constexpr std::uint32_t kKtx2ZstdScheme = 2;

// An E5B9G9R9 texel by the Vulkan specification's formula.
glm::vec3 decodeRgb9e5(std::uint32_t bits);

// rgb9e5: VK_FORMAT_E5B9G9R9_UFLOAT_PACK32, 4 bytes a texel with no alpha, which every Vulkan
// device samples: three 9-bit mantissas sharing a 5-bit exponent (about 3 significant digits of the
// brightest channel), values 0 to 65408. bc6h: VK_FORMAT_BC6H_UFLOAT_BLOCK, 16 bytes a 4x4 block
// (1 byte a texel), values 0 to 65504, which desktop GPUs sample; its blocks come from an encoder
// (probe::gpu::Bc6hEncoder), so writeKtx2Bc6hCube writes it.
enum class Ktx2PixelFormat { rgba16f, rgba32f, rgb9e5, bc6h };

// "rgba16f", "rgba32f", "rgb9e5", "bc6h"; and back (nullopt for any other name).
std::string_view ktx2FormatName(Ktx2PixelFormat format);
std::optional<Ktx2PixelFormat> parseKtx2PixelFormat(std::string_view name);

// How the levels are stored: as they are, or each compressed with Zstandard (KTX2 supercompression
// scheme 2), which a loader undoes before the upload.
enum class Ktx2Supercompression { none, zstd };

// What a tool writes: the texel format and how the levels are stored.
struct Ktx2Settings {
    Ktx2PixelFormat format = Ktx2PixelFormat::rgba16f;
    Ktx2Supercompression supercompression = Ktx2Supercompression::none;
};

using KeyValues = std::vector<std::pair<std::string, std::string>>;
// The entries of a KTX2 key/value block of `size` bytes (each a byte count, a key, NUL, the value and
// its NUL, padded to 4 bytes); std::nullopt when an entry runs past the block.
std::optional<KeyValues> parseKtx2KeyValues(const std::uint8_t* block, std::size_t size);

// Writes levels[0..] (face size halving each level, alpha 1) as one cube map. Values outside the
// format's range are clamped to it (RGBA16F above 65504; RGB9E5 above 65408 or below 0); returns
// how many were. Throws ProbeError naming the file on failure.
std::size_t writeKtx2Cube(const std::filesystem::path& path, const CubeLevels& levels, Ktx2PixelFormat format, const KeyValues& metadata,
                          Ktx2Supercompression supercompression = Ktx2Supercompression::none);

// Writes a BC6H cube from each level's blocks: the faces in order, each face's 4x4 blocks row by row
// (a level smaller than 4x4 in one block). Throws ProbeError naming the file when a level's size is
// not its blocks'.
void writeKtx2Bc6hCube(const std::filesystem::path& path, int faceSize, const std::vector<std::vector<std::uint8_t>>& levels,
                       const KeyValues& metadata, Ktx2Supercompression supercompression = Ktx2Supercompression::none);

// A cube as a KTX2 file stores it (any format above): each level's bytes, decompressed, and the
// metadata. Throws ProbeError naming the file for anything else.
struct Ktx2Levels {
    Ktx2PixelFormat format = Ktx2PixelFormat::rgba16f;
    Ktx2Supercompression supercompression = Ktx2Supercompression::none;
    int faceSize = 0;
    std::vector<std::vector<std::uint8_t>> levels;
    KeyValues metadata;
};
Ktx2Levels readKtx2Levels(const std::filesystem::path& path);

// Reads back a cube written by writeKtx2Cube (RGB of every level, and its metadata); ProbeError for BC6H.
struct Ktx2Cube {
    Ktx2PixelFormat format = Ktx2PixelFormat::rgba16f;
    Ktx2Supercompression supercompression = Ktx2Supercompression::none;
    CubeLevels levels;
    KeyValues metadata;
};
Ktx2Cube readKtx2Cube(const std::filesystem::path& path);

} // namespace probe
