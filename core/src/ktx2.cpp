#include "probe/ktx2.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numeric>
#include <span>

#include <Imath/half.h>
#include <fmt/format.h>
#include <zstd.h>

#include "probe/bc6h.h"
#include "probe/error.h"
#include "probe/limits.h"
#include "probe/output_file.h"
#include "probe/shared_constants.h"

namespace probe {

namespace {

constexpr float kHalfMax = float(PROBE_HALF_MAX);
// RGB9E5 (the Vulkan specification's shared exponent): 9 mantissa bits, exponent bias 15, largest
// exponent 31, so the largest value is 511 / 512 * 2^16.
constexpr int kMantissaBits = 9, kExponentBias = 15, kMaxExponent = 31;
constexpr float kRgb9e5Max = 65408.0f;

std::uint32_t vkFormatOf(Ktx2PixelFormat format) {
    switch (format) {
    case Ktx2PixelFormat::rgba16f: return vk_format::r16g16b16a16_sfloat;
    case Ktx2PixelFormat::rgba32f: return vk_format::r32g32b32a32_sfloat;
    case Ktx2PixelFormat::rgb9e5: return vk_format::e5b9g9r9_ufloat_pack32;
    case Ktx2PixelFormat::bc6h: return vk_format::bc6h_ufloat_block;
    }
    return 0;
}

// Bytes of one texel block (a KTX2 level's alignment unit) and of the format's components
// (typeSize: 1 for a block-compressed format).
std::uint32_t texelBytesOf(Ktx2PixelFormat format) {
    switch (format) {
    case Ktx2PixelFormat::rgba16f: return 8;
    case Ktx2PixelFormat::rgba32f:
    case Ktx2PixelFormat::bc6h: return 16;
    case Ktx2PixelFormat::rgb9e5: return 4;
    }
    return 0;
}
std::uint32_t typeSizeOf(Ktx2PixelFormat format) {
    return format == Ktx2PixelFormat::rgba16f ? 2 : format == Ktx2PixelFormat::bc6h ? 1 : 4;
}

// The Vulkan specification's encoding: the exponent that fits the brightest channel, every channel
// rounded to nearest on it. c is clamped to [0, kRgb9e5Max] already.
std::uint32_t encodeRgb9e5(const glm::vec3& c) {
    const float brightest = std::max({c.r, c.g, c.b});
    int e = 0;
    std::frexp(brightest, &e); // brightest = f 2^e with f in [0.5, 1): floor(log2(brightest)) = e - 1
    int exponent = std::max(-kExponentBias - 1, brightest > 0.0f ? e - 1 : -kExponentBias - 1) + 1 + kExponentBias;
    const auto mantissa = [&](float v) {
        return static_cast<std::uint32_t>(std::floor(std::ldexp(v, kMantissaBits + kExponentBias - exponent) + 0.5f));
    };
    if (mantissa(brightest) == (1u << kMantissaBits)) ++exponent;
    return mantissa(c.r) | mantissa(c.g) << 9 | mantissa(c.b) << 18 | static_cast<std::uint32_t>(std::min(exponent, kMaxExponent)) << 27;
}

std::size_t align(std::size_t offset, std::size_t alignment) { return (offset + alignment - 1) / alignment * alignment; }

class ByteWriter {
public:
    std::vector<std::uint8_t> bytes;
    template <typename T>
    void put(T value) {
        const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
        bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    void padTo(std::size_t alignment) { bytes.resize(align(bytes.size(), alignment), 0); }
};

// The basic data format descriptor of RGB9E5 (KDFG 1.3, as KTX-Software describes
// VK_FORMAT_E5B9G9R9_UFLOAT_PACK32): per channel a 9-bit mantissa (1.0 at 8448) and the shared 5-bit
// exponent (bias 15, largest 31).
std::vector<std::uint8_t> rgb9e5Descriptor() {
    ByteWriter w;
    const std::uint32_t samples = 6, blockSize = 24 + 16 * samples;
    w.put<std::uint32_t>(4 + blockSize);
    w.put<std::uint32_t>(0);
    w.put<std::uint32_t>(2u | (blockSize << 16));
    w.put<std::uint32_t>(1u | (1u << 8) | (1u << 16)); // RGBSDA, BT709, LINEAR
    w.put<std::uint32_t>(0);                           // 1x1x1x1
    w.put<std::uint32_t>(4);                           // bytesPlane0
    w.put<std::uint32_t>(0);
    constexpr std::uint32_t kExponent = 0x20; // KHR_DF_SAMPLE_DATATYPE_EXPONENT
    for (std::uint32_t c = 0; c < 3; ++c) {
        w.put<std::uint32_t>((9 * c) | (8u << 16) | (c << 24)); // mantissa: bits 9c .. 9c + 8
        w.put<std::uint32_t>(0);
        w.put<std::uint32_t>(0);
        w.put<std::uint32_t>(8448);
        w.put<std::uint32_t>(27u | (4u << 16) | ((c | kExponent) << 24)); // exponent: bits 27 .. 31
        w.put<std::uint32_t>(0);
        w.put<std::uint32_t>(15);
        w.put<std::uint32_t>(31);
    }
    return w.bytes;
}

// The basic data format descriptor of BC6H's unsigned blocks (KDFG 1.3, as KTX-Software describes
// VK_FORMAT_BC6H_UFLOAT_BLOCK): 4x4 texels in 16 bytes, one 128-bit float sample.
std::vector<std::uint8_t> bc6hDescriptor() {
    ByteWriter w;
    const std::uint32_t samples = 1, blockSize = 24 + 16 * samples;
    w.put<std::uint32_t>(4 + blockSize);
    w.put<std::uint32_t>(0);
    w.put<std::uint32_t>(2u | (blockSize << 16));
    w.put<std::uint32_t>(133u | (1u << 8) | (1u << 16)); // KHR_DF_MODEL_BC6H, BT709, LINEAR
    w.put<std::uint32_t>(3u | (3u << 8));                // 4x4x1x1
    w.put<std::uint32_t>(16);                            // bytesPlane0
    w.put<std::uint32_t>(0);
    w.put<std::uint32_t>((127u << 16) | (0x80u << 24)); // bits 0 .. 127, BC6H colour, FLOAT (unsigned)
    w.put<std::uint32_t>(0);
    w.put<std::uint32_t>(0);          // sampleLower 0.0f
    w.put<std::uint32_t>(0x3F800000); // sampleUpper 1.0f
    return w.bytes;
}

// The basic data format descriptor of four float channels, R G B A (KDFG 1.3, section 5).
std::vector<std::uint8_t> dataFormatDescriptor(std::uint32_t bytesPerChannel) {
    ByteWriter w;
    const std::uint32_t samples = 4, blockSize = 24 + 16 * samples;
    w.put<std::uint32_t>(4 + blockSize);               // dfdTotalSize
    w.put<std::uint32_t>(0);                           // vendorId 0 (Khronos), descriptorType 0 (basic)
    w.put<std::uint32_t>(2u | (blockSize << 16));      // versionNumber 2, descriptorBlockSize
    w.put<std::uint32_t>(1u | (1u << 8) | (1u << 16)); // colorModel RGBSDA, primaries BT709, transfer LINEAR, flags 0
    w.put<std::uint32_t>(0);                           // texelBlockDimension 1x1x1x1 (stored minus one)
    w.put<std::uint32_t>(4 * bytesPerChannel);         // bytesPlane0
    w.put<std::uint32_t>(0);                           // bytesPlane4..7
    const std::uint8_t channels[] = {0, 1, 2, 15};     // R, G, B, A
    for (std::uint32_t c = 0; c < samples; ++c) {
        const std::uint32_t bits = 8 * bytesPerChannel;
        const std::uint32_t channelType = channels[c] | 0x80u | 0x40u; // FLOAT | SIGNED
        w.put<std::uint32_t>((c * bits) | ((bits - 1) << 16) | (channelType << 24));
        w.put<std::uint32_t>(0);          // sample position
        w.put<std::uint32_t>(0xBF800000); // sampleLower -1.0f
        w.put<std::uint32_t>(0x3F800000); // sampleUpper 1.0f
    }
    return w.bytes;
}

std::vector<std::uint8_t> keyValueData(KeyValues metadata) {
    std::sort(metadata.begin(), metadata.end()); // the format requires keys in byte order
    ByteWriter w;
    for (const auto& [key, value] : metadata) {
        w.put<std::uint32_t>(static_cast<std::uint32_t>(key.size() + 1 + value.size() + 1));
        w.bytes.insert(w.bytes.end(), key.begin(), key.end());
        w.put<std::uint8_t>(0);
        w.bytes.insert(w.bytes.end(), value.begin(), value.end());
        w.put<std::uint8_t>(0);
        w.padTo(4);
    }
    return w.bytes;
}

std::vector<std::uint8_t> levelData(const CubeImage& level, Ktx2PixelFormat format, std::size_t& clamped) {
    ByteWriter w;
    for (std::size_t t = 0; t < texelCount(level.size); ++t) {
        const glm::vec3 c = level.texel(t);
        if (format == Ktx2PixelFormat::rgb9e5) {
            glm::vec3 kept;
            for (int k = 0; k < 3; ++k) {
                kept[k] = std::clamp(c[k], 0.0f, kRgb9e5Max);
                if (kept[k] != c[k]) ++clamped;
            }
            w.put<std::uint32_t>(encodeRgb9e5(kept));
            continue;
        }
        for (int k = 0; k < 4; ++k) {
            float value = k < 3 ? c[k] : 1.0f;
            if (format == Ktx2PixelFormat::rgba32f) {
                w.put<float>(value);
            } else {
                if (value > kHalfMax) {
                    value = kHalfMax;
                    ++clamped;
                }
                w.put<std::uint16_t>(Imath::half(value).bits());
            }
        }
    }
    return w.bytes;
}

float halfBitsToFloat(std::uint16_t bits) {
    Imath::half h;
    h.setBits(bits);
    return float(h);
}

template <typename T>
T readAt(const std::vector<std::uint8_t>& bytes, std::size_t offset, const std::filesystem::path& path) {
    if (offset + sizeof(T) > bytes.size()) throw ProbeError(fmt::format("{}: truncated KTX2 file", path.string()));
    T value;
    std::memcpy(&value, &bytes[offset], sizeof(T));
    return value;
}

// Each level is compressed at this Zstandard level: a filtered probe gains little beyond it, and a
// 1024^2 RGBA32F chain stays within seconds.
constexpr int kZstdLevel = 9;

std::vector<std::uint8_t> zstdCompress(const std::vector<std::uint8_t>& data, const std::filesystem::path& path) {
    std::vector<std::uint8_t> out(ZSTD_compressBound(data.size()));
    const std::size_t size = ZSTD_compress(out.data(), out.size(), data.data(), data.size(), kZstdLevel);
    if (ZSTD_isError(size)) throw ProbeError(fmt::format("{}: Zstandard: {}", path.string(), ZSTD_getErrorName(size)));
    out.resize(size);
    return out;
}

std::vector<std::uint8_t> zstdDecompress(const std::vector<std::uint8_t>& data, std::uint64_t size, const std::filesystem::path& path) {
    // A level holds at most a kMaxFaceSize^2 RGBA32F cube: a larger size is a bad file, not an allocation.
    if (size > std::uint64_t{6} * kMaxFaceSize * kMaxFaceSize * 16)
        throw ProbeError(fmt::format("{}: a level of {} bytes", path.string(), size));
    std::vector<std::uint8_t> out(size);
    const std::size_t got = ZSTD_decompress(out.data(), out.size(), data.data(), data.size());
    if (ZSTD_isError(got) || got != size)
        throw ProbeError(fmt::format("{}: a level's Zstandard data does not give its {} bytes", path.string(), size));
    return out;
}

} // namespace

glm::vec3 decodeRgb9e5(std::uint32_t bits) {
    const int exponent = static_cast<int>(bits >> 27) - kExponentBias - kMantissaBits;
    return {std::ldexp(static_cast<float>(bits & 511u), exponent), std::ldexp(static_cast<float>((bits >> 9) & 511u), exponent),
            std::ldexp(static_cast<float>((bits >> 18) & 511u), exponent)};
}

std::optional<KeyValues> parseKtx2KeyValues(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> block(data, size);
    KeyValues entries;
    for (std::size_t p = 0; p + 4 <= block.size();) {
        std::uint32_t length;
        std::memcpy(&length, &block[p], sizeof(length));
        if (length > block.size() - p - 4) return std::nullopt;
        const std::string entry(block.begin() + static_cast<std::ptrdiff_t>(p + 4),
                                block.begin() + static_cast<std::ptrdiff_t>(p + 4 + length));
        const std::size_t nul = entry.find('\0');
        std::string value = nul == std::string::npos ? std::string() : entry.substr(nul + 1);
        if (!value.empty() && value.back() == '\0') value.pop_back();
        entries.emplace_back(entry.substr(0, nul), std::move(value));
        p = align(p + 4 + length, 4);
    }
    return entries;
}

std::string_view ktx2FormatName(Ktx2PixelFormat format) {
    switch (format) {
    case Ktx2PixelFormat::rgba16f: return "rgba16f";
    case Ktx2PixelFormat::rgba32f: return "rgba32f";
    case Ktx2PixelFormat::rgb9e5: return "rgb9e5";
    case Ktx2PixelFormat::bc6h: return "bc6h";
    }
    return "";
}

std::optional<Ktx2PixelFormat> parseKtx2PixelFormat(std::string_view name) {
    for (const Ktx2PixelFormat f : {Ktx2PixelFormat::rgba16f, Ktx2PixelFormat::rgba32f, Ktx2PixelFormat::rgb9e5, Ktx2PixelFormat::bc6h})
        if (name == ktx2FormatName(f)) return f;
    return std::nullopt;
}

namespace {

// The container around levels already in the format (each a face after another): the header, the
// level index, the data format descriptor, the metadata and the levels, smallest first, each
// compressed with Zstandard where asked.
void writeContainer(const std::filesystem::path& path, Ktx2PixelFormat format, int faceSize,
                    const std::vector<std::vector<std::uint8_t>>& data, const KeyValues& metadata, Ktx2Supercompression supercompression) {
    const bool zstd = supercompression == Ktx2Supercompression::zstd;
    const auto levelCount = static_cast<std::uint32_t>(data.size());
    const std::vector<std::uint8_t> dfd = format == Ktx2PixelFormat::rgb9e5 ? rgb9e5Descriptor()
                                          : format == Ktx2PixelFormat::bc6h ? bc6hDescriptor()
                                                                            : dataFormatDescriptor(typeSizeOf(format)),
                                    kvd = keyValueData(metadata);
    std::vector<std::vector<std::uint8_t>> stored;
    for (const std::vector<std::uint8_t>& level : data) stored.push_back(zstd ? zstdCompress(level, path) : level);

    const std::size_t dfdOffset = 80 + 24 * levelCount, kvdOffset = dfdOffset + dfd.size();
    // Level data, smallest level first, each aligned to lcm(texel block size, 4) (supercompressed: to 1).
    std::vector<std::size_t> offsets(levelCount);
    std::size_t end = kvdOffset + kvd.size();
    for (std::uint32_t m = levelCount; m-- > 0;) {
        offsets[m] = align(end, zstd ? 1 : std::lcm<std::size_t>(texelBytesOf(format), 4));
        end = offsets[m] + stored[m].size();
    }

    ByteWriter w;
    w.bytes.assign(kKtx2Identifier.begin(), kKtx2Identifier.end());
    for (std::uint32_t v : {vkFormatOf(format), typeSizeOf(format), std::uint32_t(faceSize), std::uint32_t(faceSize), 0u /*depth*/,
                            0u /*layers*/, 6u /*faces*/, levelCount, zstd ? kKtx2ZstdScheme : 0u})
        w.put<std::uint32_t>(v);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(dfdOffset));
    w.put<std::uint32_t>(static_cast<std::uint32_t>(dfd.size()));
    w.put<std::uint32_t>(static_cast<std::uint32_t>(kvdOffset));
    w.put<std::uint32_t>(static_cast<std::uint32_t>(kvd.size()));
    w.put<std::uint64_t>(0); // no supercompression global data
    w.put<std::uint64_t>(0);
    for (std::uint32_t m = 0; m < levelCount; ++m) {
        w.put<std::uint64_t>(offsets[m]);
        w.put<std::uint64_t>(stored[m].size());
        w.put<std::uint64_t>(data[m].size());
    }
    w.bytes.insert(w.bytes.end(), dfd.begin(), dfd.end());
    w.bytes.insert(w.bytes.end(), kvd.begin(), kvd.end());
    for (std::uint32_t m = levelCount; m-- > 0;) {
        w.bytes.resize(offsets[m], 0);
        w.bytes.insert(w.bytes.end(), stored[m].begin(), stored[m].end());
    }
    writeFile(path, std::string_view(reinterpret_cast<const char*>(w.bytes.data()), w.bytes.size()));
}

} // namespace

std::size_t writeKtx2Cube(const std::filesystem::path& path, const CubeLevels& levels, Ktx2PixelFormat format, const KeyValues& metadata,
                          Ktx2Supercompression supercompression) {
    if (format == Ktx2PixelFormat::bc6h)
        throw ProbeError(fmt::format("{}: BC6H levels are written from their blocks (writeKtx2Bc6hCube)", path.string()));
    std::size_t clamped = 0;
    std::vector<std::vector<std::uint8_t>> data;
    for (const CubeImage& level : levels) data.push_back(levelData(level, format, clamped));
    writeContainer(path, format, levels[0].size, data, metadata, supercompression);
    return clamped;
}

void writeKtx2Bc6hCube(const std::filesystem::path& path, int faceSize, const std::vector<std::vector<std::uint8_t>>& levels,
                       const KeyValues& metadata, Ktx2Supercompression supercompression) {
    for (std::size_t m = 0; m < levels.size(); ++m) {
        const std::size_t bytes = bc6hLevelBytes(std::max(faceSize >> m, 1));
        if (levels[m].size() != bytes)
            throw ProbeError(
                fmt::format("{}: BC6H level {} has {} bytes, not the {} of its blocks", path.string(), m, levels[m].size(), bytes));
    }
    writeContainer(path, Ktx2PixelFormat::bc6h, faceSize, levels, metadata, supercompression);
}

Ktx2Levels readKtx2Levels(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ProbeError(fmt::format("{}: cannot open KTX2 file", path.string()));
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() < 80 || !std::equal(kKtx2Identifier.begin(), kKtx2Identifier.end(), bytes.begin()))
        throw ProbeError(fmt::format("{}: not a KTX2 file", path.string()));
    const auto vkFormat = readAt<std::uint32_t>(bytes, 12, path);
    const auto width = readAt<std::uint32_t>(bytes, 20, path);
    const auto faces = readAt<std::uint32_t>(bytes, 36, path);
    const auto levelCount = readAt<std::uint32_t>(bytes, 40, path);
    const auto scheme = readAt<std::uint32_t>(bytes, 44, path);
    if (scheme != 0 && scheme != kKtx2ZstdScheme)
        throw ProbeError(fmt::format("{}: supercompression scheme {} (probefilter reads none and Zstandard)", path.string(), scheme));
    Ktx2Levels k;
    const Ktx2PixelFormat formats[] = {Ktx2PixelFormat::rgba16f, Ktx2PixelFormat::rgba32f, Ktx2PixelFormat::rgb9e5, Ktx2PixelFormat::bc6h};
    const auto format = std::find_if(std::begin(formats), std::end(formats), [&](Ktx2PixelFormat f) { return vkFormatOf(f) == vkFormat; });
    if (format == std::end(formats) || faces != 6)
        throw ProbeError(fmt::format("{}: not an RGBA16F, RGBA32F, RGB9E5 or BC6H cube", path.string()));
    k.format = *format;
    k.supercompression = scheme == kKtx2ZstdScheme ? Ktx2Supercompression::zstd : Ktx2Supercompression::none;
    k.faceSize = static_cast<int>(width);
    for (std::uint32_t m = 0; m < levelCount; ++m) {
        const auto offset = readAt<std::uint64_t>(bytes, 80 + 24 * m, path), length = readAt<std::uint64_t>(bytes, 88 + 24 * m, path),
                   uncompressed = readAt<std::uint64_t>(bytes, 96 + 24 * m, path);
        if (offset > bytes.size() || length > bytes.size() - offset)
            throw ProbeError(fmt::format("{}: level {} lies beyond the file", path.string(), m));
        std::vector<std::uint8_t> stored(bytes.begin() + static_cast<std::ptrdiff_t>(offset),
                                         bytes.begin() + static_cast<std::ptrdiff_t>(offset + length));
        k.levels.push_back(scheme == kKtx2ZstdScheme ? zstdDecompress(stored, uncompressed, path) : std::move(stored));
    }
    const auto kvdOffset = readAt<std::uint32_t>(bytes, 56, path), kvdLength = readAt<std::uint32_t>(bytes, 60, path);
    std::optional<KeyValues> metadata;
    if (kvdOffset <= bytes.size() && kvdLength <= bytes.size() - kvdOffset)
        metadata = parseKtx2KeyValues(bytes.data() + kvdOffset, kvdLength);
    if (!metadata) throw ProbeError(fmt::format("{}: truncated KTX2 metadata", path.string()));
    k.metadata = std::move(*metadata);
    return k;
}

Ktx2Cube readKtx2Cube(const std::filesystem::path& path) {
    Ktx2Levels k = readKtx2Levels(path);
    if (k.format == Ktx2PixelFormat::bc6h)
        throw ProbeError(fmt::format("{}: BC6H blocks (probefilter reads their levels as stored, not their texels)", path.string()));
    Ktx2Cube cube{k.format, k.supercompression, {}, std::move(k.metadata)};
    for (std::size_t m = 0; m < k.levels.size(); ++m) {
        const std::vector<std::uint8_t>& data = k.levels[m];
        CubeImage level(std::max(1, k.faceSize >> m));
        for (std::size_t t = 0; t < texelCount(level.size); ++t) {
            if (cube.format == Ktx2PixelFormat::rgb9e5) {
                level.set(t, decodeRgb9e5(readAt<std::uint32_t>(data, 4 * t, path)));
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                const std::size_t channel = 4 * t + c;
                level.rgb[3 * t + c] = cube.format == Ktx2PixelFormat::rgba32f
                                           ? readAt<float>(data, 4 * channel, path)
                                           : halfBitsToFloat(readAt<std::uint16_t>(data, 2 * channel, path));
            }
        }
        cube.levels.push_back(std::move(level));
    }
    return cube;
}

} // namespace probe
