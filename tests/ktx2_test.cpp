// KTX2 output: read back equal (RGBA32F exactly, RGBA16F to half precision, RGB9E5 to its shared
// exponent's), clamping to each format's range counted, metadata kept; Zstandard supercompression
// gives the same levels back. KTX2 input: a cube read as a probe, and every header the probe reader
// cannot read refused by name.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/common.hpp>
#include <gtest/gtest.h>
#include <unistd.h>

#include "probe/error.h"
#include "probe/ktx2.h"
#include "probe/probe_io.h"
#include "probe/reference.h"
#include "probe/synthetic.h"

using namespace probe;
namespace fs = std::filesystem;

TEST(Ktx2, RoundTrip) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_test_{}", ::getpid());
    fs::create_directories(dir);
    CubeImage source = sunSkyProbe(16);
    source.set(5, glm::vec3(1e6f, 2.0f, 70000.0f)); // two values beyond the half range
    const CubeLevels levels = referenceFilter(source, 4, RoughnessMapping::gltf);
    const KeyValues metadata{{"probefilter.mapping", "gltf"}, {"KTXwriter", "probefilter"}};

    EXPECT_EQ(writeKtx2Cube(dir / "a32.ktx2", levels, Ktx2PixelFormat::rgba32f, metadata), 0u);
    const Ktx2Cube full = readKtx2Cube(dir / "a32.ktx2");
    ASSERT_EQ(full.levels.size(), levels.size());
    for (std::size_t m = 0; m < levels.size(); ++m) EXPECT_EQ(full.levels[m].rgb, levels[m].rgb);
    EXPECT_EQ(full.metadata, (KeyValues{{"KTXwriter", "probefilter"}, {"probefilter.mapping", "gltf"}}));

    std::size_t beyondHalf = 0;
    for (const CubeImage& level : levels)
        for (float v : level.rgb) beyondHalf += v > 65504.0f;
    EXPECT_EQ(writeKtx2Cube(dir / "a16.ktx2", levels, Ktx2PixelFormat::rgba16f, metadata), beyondHalf);
    EXPECT_GE(beyondHalf, 2u);
    const Ktx2Cube half = readKtx2Cube(dir / "a16.ktx2");
    for (std::size_t m = 0; m < levels.size(); ++m)
        for (std::size_t k = 0; k < levels[m].rgb.size(); ++k) {
            const float expected = std::min(levels[m].rgb[k], 65504.0f);
            ASSERT_NEAR(half.levels[m].rgb[k], expected, expected * 1e-3f + 1e-7f);
        }
    fs::remove_all(dir);
}

// RGB9E5: every channel within half a step of the shared exponent's (2^-9 of the texel's brightest
// channel), values beyond 65408 and below 0 clamped and counted, a black texel black.
TEST(Ktx2, SharedExponentRoundTrip) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_e5_test_{}", ::getpid());
    fs::create_directories(dir);
    CubeLevels levels = referenceFilter(sunSkyProbe(16), 4, RoughnessMapping::gltf);
    levels[0].set(0, glm::vec3(1e6f, -0.5f, 3.0f)); // one value above the range, one below
    levels[0].set(1, glm::vec3(0.0f));
    levels[0].set(2, glm::vec3(65408.0f, 1e-9f, 0.25f));
    EXPECT_EQ(writeKtx2Cube(dir / "e5.ktx2", levels, Ktx2PixelFormat::rgb9e5, {}), 2u);
    const Ktx2Cube e5 = readKtx2Cube(dir / "e5.ktx2");
    EXPECT_EQ(e5.format, Ktx2PixelFormat::rgb9e5);
    ASSERT_EQ(e5.levels.size(), levels.size());
    for (std::size_t m = 0; m < levels.size(); ++m)
        for (std::size_t t = 0; t < texelCount(levels[m].size); ++t) {
            const glm::vec3 expected = glm::clamp(levels[m].texel(t), 0.0f, 65408.0f);
            const float step = std::max({expected.r, expected.g, expected.b}) / 512.0f + 1e-7f;
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(e5.levels[m].texel(t)[k], expected[k], step) << "level " << m << " texel " << t;
        }
    EXPECT_EQ(e5.levels[0].texel(1), glm::vec3(0.0f));
    EXPECT_EQ(e5.levels[0].texel(2).r, 65408.0f);
    fs::remove_all(dir);
}

// Zstandard supercompression: the same levels back, in a smaller file (a filtered probe's levels are
// smooth); every format.
TEST(Ktx2, ZstdSupercompressionRoundTrip) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_zstd_test_{}", ::getpid());
    fs::create_directories(dir);
    const CubeLevels levels = referenceFilter(sunSkyProbe(32), 6, RoughnessMapping::gltf);
    for (const Ktx2PixelFormat format : {Ktx2PixelFormat::rgba16f, Ktx2PixelFormat::rgba32f, Ktx2PixelFormat::rgb9e5}) {
        writeKtx2Cube(dir / "plain.ktx2", levels, format, {{"KTXwriter", "probefilter"}});
        writeKtx2Cube(dir / "zstd.ktx2", levels, format, {{"KTXwriter", "probefilter"}}, Ktx2Supercompression::zstd);
        const Ktx2Cube plain = readKtx2Cube(dir / "plain.ktx2"), zstd = readKtx2Cube(dir / "zstd.ktx2");
        EXPECT_EQ(plain.supercompression, Ktx2Supercompression::none);
        EXPECT_EQ(zstd.supercompression, Ktx2Supercompression::zstd);
        ASSERT_EQ(zstd.levels.size(), levels.size());
        for (std::size_t m = 0; m < levels.size(); ++m) EXPECT_EQ(zstd.levels[m].rgb, plain.levels[m].rgb) << ktx2FormatName(format);
        EXPECT_EQ(zstd.metadata, plain.metadata);
        EXPECT_LT(fs::file_size(dir / "zstd.ktx2"), fs::file_size(dir / "plain.ktx2")) << ktx2FormatName(format);
    }
    fs::remove_all(dir);
}

// BC6H is written from its blocks: the header names VK_FORMAT_BC6H_UFLOAT_BLOCK with typeSize 1,
// each level's blocks are stored as given (a level below 4x4 in one block a face), 16-byte aligned;
// a level whose size is not its blocks' is refused naming the file, and the texel writer refuses the
// format (its blocks come from an encoder). The levels read back as written; probefilter does not
// decode their texels.
TEST(Ktx2, Bc6hWrittenFromItsBlocks) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_bc6h_test_{}", ::getpid());
    fs::create_directories(dir);
    std::vector<std::vector<std::uint8_t>> levels;
    for (int size : {8, 4, 2, 1}) {
        const std::size_t across = (std::size_t(size) + 3) / 4;
        levels.emplace_back(6 * across * across * 16);
        for (std::size_t k = 0; k < levels.back().size(); ++k) levels.back()[k] = std::uint8_t(k * 7 + size);
    }
    writeKtx2Bc6hCube(dir / "bc6h.ktx2", 8, levels, {{"KTXwriter", "probefilter"}});
    std::ifstream in(dir / "bc6h.ktx2", std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto word = [&](std::size_t offset) {
        std::uint64_t value = 0;
        std::memcpy(&value, &bytes[offset], 4);
        return value;
    };
    EXPECT_EQ(word(12), 143u); // vkFormat
    EXPECT_EQ(word(16), 1u);   // typeSize
    EXPECT_EQ(word(20), 8u);
    EXPECT_EQ(word(36), 6u); // faces
    EXPECT_EQ(word(40), 4u); // levels
    for (std::size_t m = 0; m < levels.size(); ++m) {
        std::uint64_t offset = 0, length = 0;
        std::memcpy(&offset, &bytes[80 + 24 * m], 8);
        std::memcpy(&length, &bytes[88 + 24 * m], 8);
        EXPECT_EQ(offset % 16, 0u) << "level " << m;
        ASSERT_EQ(length, levels[m].size());
        EXPECT_TRUE(std::equal(levels[m].begin(), levels[m].end(), reinterpret_cast<const std::uint8_t*>(&bytes[offset])));
    }
    // The descriptor: colour model BC6H, 4x4 blocks, 16 bytes a plane.
    const std::uint64_t dfd = word(48);
    EXPECT_EQ(word(dfd + 12) & 0xFFu, 133u); // KHR_DF_MODEL_BC6H
    EXPECT_EQ(word(dfd + 16), 3u | (3u << 8));
    EXPECT_EQ(word(dfd + 20), 16u);

    const Ktx2Levels read = readKtx2Levels(dir / "bc6h.ktx2");
    EXPECT_EQ(read.format, Ktx2PixelFormat::bc6h);
    EXPECT_EQ(read.faceSize, 8);
    EXPECT_EQ(read.levels, levels);

    levels[1].pop_back();
    EXPECT_THROW(writeKtx2Bc6hCube(dir / "short.ktx2", 8, levels, {}), ProbeError);
    EXPECT_THROW(writeKtx2Cube(dir / "texels.ktx2", referenceFilter(sunSkyProbe(8), 3, RoughnessMapping::gltf), Ktx2PixelFormat::bc6h, {}),
                 ProbeError);
    EXPECT_THROW(readKtx2Cube(dir / "bc6h.ktx2"), ProbeError);
    EXPECT_FALSE(fs::exists(dir / "short.ktx2"));
    fs::remove_all(dir);
}

namespace {

std::vector<char> readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const std::vector<char>& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <typename T>
void put(std::vector<char>& bytes, std::size_t offset, T value) {
    std::memcpy(&bytes[offset], &value, sizeof(T));
}

} // namespace

TEST(Ktx2, CubeReadsAsAProbeOfItsFacesInAColumn) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_probe_test_{}", ::getpid());
    fs::create_directories(dir);
    const CubeLevels levels = referenceFilter(sunSkyProbe(8), 3, RoughnessMapping::gltf);
    for (const Ktx2PixelFormat format : {Ktx2PixelFormat::rgba32f, Ktx2PixelFormat::rgba16f, Ktx2PixelFormat::rgb9e5})
        for (const Ktx2Supercompression supercompression : {Ktx2Supercompression::none, Ktx2Supercompression::zstd}) {
            SCOPED_TRACE(fmt::format("{} {}", ktx2FormatName(format), supercompression == Ktx2Supercompression::zstd ? "zstd" : "plain"));
            const fs::path path = dir / "probe.ktx2";
            writeKtx2Cube(path, levels, format, {}, supercompression);
            // Level 0 as the whole-file reader decodes it, face f's texel (i, j) at (i, 8 f + j).
            const CubeImage stored = readKtx2Cube(path).levels[0];
            const Image image = readImage(path);
            ASSERT_EQ(image.width, 8);
            ASSERT_EQ(image.height, 48);
            EXPECT_EQ(detectLayout(image, path), ProbeLayout::faceColumn);
            for (int f = 0; f < kFaceCount; ++f)
                for (int j = 0; j < 8; ++j)
                    for (int i = 0; i < 8; ++i) ASSERT_EQ(image.pixel(i, 8 * f + j), stored.texel(texelIndex({f, i, j}, 8))) << f << i << j;
            if (format == Ktx2PixelFormat::rgba32f) {
                PixelRepairs repairs;
                EXPECT_EQ(loadProbe(path, 8, BadPixelPolicy::refuse, repairs).rgb, levels[0].rgb);
            }
        }
    fs::remove_all(dir);
}

TEST(Ktx2, ProbeReaderRefusesWhatItCannotRead) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("ktx2_refuse_test_{}", ::getpid());
    fs::create_directories(dir);
    writeKtx2Cube(dir / "plain.ktx2", {sunSkyProbe(8)}, Ktx2PixelFormat::rgba16f, {});
    writeKtx2Cube(dir / "zstd.ktx2", {sunSkyProbe(8)}, Ktx2PixelFormat::rgba16f, {}, Ktx2Supercompression::zstd);
    const std::vector<char> plain = readBytes(dir / "plain.ktx2"), zstd = readBytes(dir / "zstd.ktx2");
    // Header fields: 12 vkFormat, 20 width, 24 height, 28 depth, 32 layers, 36 faces, 44 scheme;
    // level 0's entry: 80 offset, 88 stored bytes, 96 bytes.
    struct Case {
        const char* name;
        std::vector<char> bytes;
        const char* expected;
    };
    std::vector<Case> cases;
    auto edited = [&](const char* name, const std::vector<char>& base, const char* expected, auto edit) {
        std::vector<char> bytes = base;
        edit(bytes);
        cases.push_back({name, bytes, expected});
    };
    edited("bc6h", plain, "BC6H blocks", [](auto& b) { put<std::uint32_t>(b, 12, 143); });
    edited("rgba8", plain, "VkFormat 37", [](auto& b) { put<std::uint32_t>(b, 12, 37); });
    edited("volume", plain, "3D texture", [](auto& b) { put<std::uint32_t>(b, 28, 4); });
    edited("array", plain, "array of 2 layers", [](auto& b) { put<std::uint32_t>(b, 32, 2); });
    edited("faces", plain, "3 faces", [](auto& b) { put<std::uint32_t>(b, 36, 3); });
    edited("line", plain, "1D texture", [](auto& b) { put<std::uint32_t>(b, 24, 0); });
    edited("oblong", plain, "not square", [](auto& b) { put<std::uint32_t>(b, 24, 4); });
    edited("huge", plain, "over the limit", [](auto& b) { put<std::uint32_t>(b, 20, 40000), put<std::uint32_t>(b, 24, 40000); });
    edited("basis", plain, "supercompression scheme 1", [](auto& b) { put<std::uint32_t>(b, 44, 1); });
    edited("declared", plain, "level 0 declares", [](auto& b) { put<std::uint64_t>(b, 96, 100); });
    edited("stored", plain, "level 0 stores", [](auto& b) { put<std::uint64_t>(b, 88, 100); });
    edited("beyond", plain, "beyond the end", [](auto& b) { put<std::uint64_t>(b, 80, 1u << 30); });
    edited("truncated", plain, "beyond the end", [](auto& b) { b.resize(b.size() - 1); });
    edited("version1", plain, "KTX version 1", [](auto& b) { b[5] = '1', b[6] = '1'; });
    edited("short", plain, "ends within its header", [](auto& b) { b.resize(100); });
    // Zstandard: a corrupt frame, and a frame of a 4^2 cube where an 8^2 one is declared (its
    // header's sizes kept, so that only the data is short).
    const std::size_t zstdOffset = [&] {
        std::uint64_t offset;
        std::memcpy(&offset, &zstd[80], 8);
        return static_cast<std::size_t>(offset);
    }();
    edited("corrupt-zstd", zstd, "Zstandard data is corrupt", [&](auto& b) {
        for (std::size_t k = zstdOffset; k < b.size(); ++k) b[k] = static_cast<char>(0x5a);
    });
    writeKtx2Cube(dir / "small.ktx2", {sunSkyProbe(4)}, Ktx2PixelFormat::rgba16f, {}, Ktx2Supercompression::zstd);
    edited("short-zstd", readBytes(dir / "small.ktx2"), "ends before its texels",
           [](auto& b) { put<std::uint32_t>(b, 20, 8), put<std::uint32_t>(b, 24, 8), put<std::uint64_t>(b, 96, 6 * 64 * 8); });
    for (const Case& c : cases) {
        const fs::path path = dir / (std::string(c.name) + ".ktx2");
        writeBytes(path, c.bytes);
        try {
            readImage(path);
            ADD_FAILURE() << c.name << ": read";
        } catch (const ProbeError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(path.string() + ": KTX2: "), std::string::npos) << c.name << ": " << message;
            EXPECT_NE(message.find(c.expected), std::string::npos) << c.name << ": " << message;
        }
    }
    // Unedited, both read.
    EXPECT_EQ(readImage(dir / "plain.ktx2").height, 48);
    EXPECT_EQ(readImage(dir / "zstd.ktx2").height, 48);
    fs::remove_all(dir);
}
