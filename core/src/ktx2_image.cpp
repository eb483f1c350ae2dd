#include "probe/ktx2_image.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <Imath/half.h>
#include <fmt/format.h>
#include <zstd.h>

#include "probe/error.h"
#include "probe/ktx2.h"
#include "probe/limits.h"

namespace probe {

namespace {

// The texel formats a probe is read from: float formats with at least R, G and B, each texel one
// block of `bytes`.
enum class Texel { half4, half3, float4, float3, b10g11r11, e5b9g9r9 };
struct TexelFormat {
    std::uint32_t vkFormat;
    Texel texel;
    std::uint32_t bytes;
};
constexpr TexelFormat kTexelFormats[] = {
    {vk_format::r16g16b16a16_sfloat, Texel::half4, 8},         {vk_format::r16g16b16_sfloat, Texel::half3, 6},
    {vk_format::r32g32b32a32_sfloat, Texel::float4, 16},       {vk_format::r32g32b32_sfloat, Texel::float3, 12},
    {vk_format::b10g11r11_ufloat_pack32, Texel::b10g11r11, 4}, {vk_format::e5b9g9r9_ufloat_pack32, Texel::e5b9g9r9, 4},
};
constexpr const char* kFormatNames = "R16G16B16A16_SFLOAT, R16G16B16_SFLOAT, R32G32B32A32_SFLOAT, R32G32B32_SFLOAT, "
                                     "B10G11R11_UFLOAT_PACK32 or E5B9G9R9_UFLOAT_PACK32";
// Metadata is read only for a 2D image's orientation; no writer needs more than this.
constexpr std::uint32_t kMaxMetadataBytes = 1u << 20;
constexpr std::size_t kZstdChunkBytes = 1u << 16;

template <typename T>
T load(const std::uint8_t* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
}

float halfBits(std::uint16_t bits) {
    Imath::half h;
    h.setBits(bits);
    return float(h);
}

// An unsigned 10- or 11-bit float (B10G11R11): a 5-bit exponent of bias 15 and no sign. Inf and NaN
// stay what they are, for the bad-pixel policy to see (GLM's unpackF2x11_1x10 makes them -1).
float smallFloat(std::uint32_t bits, int mantissaBits) {
    const std::uint32_t exponent = bits >> mantissaBits, mantissa = bits & ((1u << mantissaBits) - 1);
    if (exponent == 31) return mantissa ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
    if (exponent == 0) return std::ldexp(static_cast<float>(mantissa), -14 - mantissaBits);
    return std::ldexp(static_cast<float>(mantissa | (1u << mantissaBits)), static_cast<int>(exponent) - 15 - mantissaBits);
}

glm::vec3 decodeTexel(const std::uint8_t* p, Texel texel) {
    switch (texel) {
    case Texel::half4:
    case Texel::half3:
        return {halfBits(load<std::uint16_t>(p)), halfBits(load<std::uint16_t>(p + 2)), halfBits(load<std::uint16_t>(p + 4))};
    case Texel::float4:
    case Texel::float3: return {load<float>(p), load<float>(p + 4), load<float>(p + 8)};
    case Texel::b10g11r11: {
        const auto bits = load<std::uint32_t>(p);
        return {smallFloat(bits & 0x7ffu, 6), smallFloat((bits >> 11) & 0x7ffu, 6), smallFloat(bits >> 22, 5)};
    }
    case Texel::e5b9g9r9: return decodeRgb9e5(load<std::uint32_t>(p));
    }
    return {};
}

class Reader {
public:
    Reader(std::istream& in, std::uintmax_t byteCount, const std::filesystem::path& path)
        : in_(in), start_(in.tellg()), size_(byteCount), path_(path) {}

    [[noreturn]] void fail(const std::string& problem) const { throw ProbeError(fmt::format("{}: KTX2: {}", path_.string(), problem)); }

    std::uintmax_t size() const { return size_; }

    // To `offset` from the file's start, which the caller has checked lies within it.
    void seek(std::uint64_t offset) {
        in_.clear();
        in_.seekg(start_ + static_cast<std::streamoff>(offset));
    }

    // The next `count` bytes from the current position.
    void bytes(std::uint8_t* out, std::size_t count, const char* what) {
        in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(count));
        if (static_cast<std::size_t>(in_.gcount()) != count) fail(fmt::format("file ends early ({})", what));
    }

private:
    std::istream& in_;
    std::streampos start_;
    std::uintmax_t size_;
    const std::filesystem::path& path_;
};

// Level 0's bytes in order, read from the file as they are or through a Zstandard stream, a chunk
// at a time, so that memory stays the image's.
class LevelBytes {
public:
    LevelBytes(Reader& reader, std::uint64_t storedBytes, bool zstd) : reader_(reader), storedLeft_(storedBytes) {
        if (zstd && !(stream_ = ZSTD_createDStream())) reader_.fail("out of memory for Zstandard");
        if (stream_) chunk_.resize(kZstdChunkBytes);
    }
    ~LevelBytes() { ZSTD_freeDStream(stream_); }
    LevelBytes(const LevelBytes&) = delete;
    LevelBytes& operator=(const LevelBytes&) = delete;

    void read(std::uint8_t* out, std::size_t count) {
        if (!stream_) {
            reader_.bytes(out, count, "level 0");
            return;
        }
        ZSTD_outBuffer output{out, count, 0};
        while (output.pos < count) {
            if (input_.pos == input_.size) {
                if (storedLeft_ == 0) reader_.fail("level 0's Zstandard data ends before its texels do");
                const auto take = static_cast<std::size_t>(std::min<std::uint64_t>(storedLeft_, chunk_.size()));
                reader_.bytes(chunk_.data(), take, "level 0");
                storedLeft_ -= take;
                input_ = {chunk_.data(), take, 0};
            }
            const std::size_t result = ZSTD_decompressStream(stream_, &output, &input_);
            if (ZSTD_isError(result)) reader_.fail(fmt::format("level 0's Zstandard data is corrupt ({})", ZSTD_getErrorName(result)));
        }
    }

private:
    Reader& reader_;
    std::uint64_t storedLeft_;
    ZSTD_DStream* stream_ = nullptr;
    std::vector<std::uint8_t> chunk_;
    ZSTD_inBuffer input_{nullptr, 0, 0};
};

// Whether a 2D image's rows run up and its columns left (KTXorientation "ru", "lu", ...); "rd", the
// default, is row 0 at the top, as the other formats store it.
struct Orientation {
    bool left = false, up = false;
};

Orientation readOrientation(Reader& reader, std::uint32_t offset, std::uint32_t length) {
    if (length == 0) return {};
    if (length > kMaxMetadataBytes) reader.fail(fmt::format("{} bytes of metadata, over the limit of {}", length, kMaxMetadataBytes));
    if (offset > reader.size() || length > reader.size() - offset) reader.fail("metadata lies beyond the end of the file");
    std::vector<std::uint8_t> data(length);
    reader.seek(offset);
    reader.bytes(data.data(), length, "metadata");
    const std::optional<KeyValues> entries = parseKtx2KeyValues(data.data(), data.size());
    if (!entries) reader.fail("a metadata entry runs past the metadata");
    for (const auto& [key, value] : *entries)
        if (key == "KTXorientation") return {value.size() > 0 && value[0] == 'l', value.size() > 1 && value[1] == 'u'};
    return {};
}

} // namespace

Image readKtx2Image(std::istream& in, std::uintmax_t byteCount, const std::filesystem::path& path) {
    Reader reader(in, byteCount, path);
    // The header and level 0's entry in the level index, which every file has.
    std::array<std::uint8_t, 80 + 24> header{};
    if (byteCount < header.size()) reader.fail(fmt::format("file ends within its header ({} bytes)", byteCount));
    reader.bytes(header.data(), header.size(), "header");
    if (!std::equal(kKtx2Identifier.begin(), kKtx2Identifier.end(), header.begin()))
        reader.fail(header[5] == '1' && header[6] == '1' ? "KTX version 1; probefilter reads KTX2" : "not a KTX2 identifier");
    const auto field = [&](int index) { return load<std::uint32_t>(&header[12 + 4 * index]); };
    const std::uint32_t vkFormat = field(0), width = field(2), height = field(3), depth = field(4), layers = field(5), faces = field(6),
                        scheme = field(8), metadataOffset = field(11), metadataLength = field(12);

    const auto* format =
        std::find_if(std::begin(kTexelFormats), std::end(kTexelFormats), [&](const TexelFormat& f) { return f.vkFormat == vkFormat; });
    if (vkFormat == vk_format::bc6h_ufloat_block || vkFormat == vk_format::bc6h_sfloat_block)
        reader.fail(fmt::format("BC6H blocks; probefilter reads a probe in {}", kFormatNames));
    if (format == std::end(kTexelFormats)) reader.fail(fmt::format("VkFormat {}; probefilter reads a probe in {}", vkFormat, kFormatNames));
    if (depth != 0) reader.fail(fmt::format("a 3D texture (depth {}); a probe is a cube or a 2D image", depth));
    if (layers > 1) reader.fail(fmt::format("an array of {} layers; probefilter reads one cube or image a file", layers));
    if (faces != 1 && faces != 6) reader.fail(fmt::format("{} faces (1 or 6 expected)", faces));
    if (height == 0) reader.fail("a 1D texture (height 0); a probe is a cube or a 2D image");
    if (faces == 6 && width != height) reader.fail(fmt::format("cube faces of {} x {}, not square", width, height));
    const std::int64_t imageHeight = std::int64_t{height} * faces;
    if (const std::string problem = imageSizeProblem(width, imageHeight); !problem.empty()) reader.fail(problem);
    if (scheme != 0 && scheme != kKtx2ZstdScheme)
        reader.fail(fmt::format("supercompression scheme {}; probefilter reads levels stored as they are or with Zstandard", scheme));

    // Level 0: each face's rows in turn, every texel one block of the format.
    const std::uint64_t offset = load<std::uint64_t>(&header[80]), storedBytes = load<std::uint64_t>(&header[88]),
                        uncompressed = load<std::uint64_t>(&header[96]);
    const std::uint64_t texelBytes = std::uint64_t{width} * static_cast<std::uint64_t>(imageHeight) * format->bytes;
    if (uncompressed != texelBytes)
        reader.fail(fmt::format("level 0 declares {} bytes; {} face(s) of {} x {} texels of {} bytes take {}", uncompressed, faces, width,
                                height, format->bytes, texelBytes));
    if (scheme == 0 && storedBytes != texelBytes) reader.fail(fmt::format("level 0 stores {} bytes, not its {}", storedBytes, texelBytes));
    if (offset > byteCount || storedBytes > byteCount - offset) reader.fail("level 0 lies beyond the end of the file");
    const Orientation orientation = faces == 1 ? readOrientation(reader, metadataOffset, metadataLength) : Orientation{};

    // Rows arrive in the order they are stored (a cube's faces one above the other). The image is
    // reserved within the size limit and grows row by row, so the memory touched follows the rows
    // that decode: a Zstandard level may promise more than it holds.
    const int w = static_cast<int>(width), rows = static_cast<int>(height * faces);
    Image image{w, rows, {}};
    image.rgb.reserve(static_cast<std::size_t>(w) * rows * 3);
    std::vector<std::uint8_t> stored(static_cast<std::size_t>(w) * format->bytes);
    reader.seek(offset);
    LevelBytes level(reader, storedBytes, scheme == kKtx2ZstdScheme);
    for (int y = 0; y < rows; ++y) {
        level.read(stored.data(), stored.size());
        image.rgb.resize(image.rgb.size() + 3 * static_cast<std::size_t>(w));
        for (int i = 0; i < w; ++i) {
            const glm::vec3 c = decodeTexel(&stored[static_cast<std::size_t>(i) * format->bytes], format->texel);
            const int x = orientation.left ? w - 1 - i : i;
            std::copy(&c[0], &c[0] + 3, &image.rgb[3 * (static_cast<std::size_t>(y) * w + x)]);
        }
    }
    if (orientation.up)
        for (int y = 0; y < rows / 2; ++y)
            std::swap_ranges(image.rgb.begin() + 3 * static_cast<std::ptrdiff_t>(y) * w,
                             image.rgb.begin() + 3 * static_cast<std::ptrdiff_t>(y + 1) * w,
                             image.rgb.begin() + 3 * static_cast<std::ptrdiff_t>(rows - 1 - y) * w);
    return image;
}

} // namespace probe
