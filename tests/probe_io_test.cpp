// Probes in and out: EXR (every compression, half and float, RGB and RGBA), Radiance HDR, layouts,
// area-correct resampling, bad pixels, staged output.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <ImfArray.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "probe/error.h"
#include "probe/probe_io.h"
#include "probe/radiance_hdr.h"
#include "probe/synthetic.h"
#include "temp_dir.h"

using namespace probe;
using probetest::TempDir;
namespace fs = std::filesystem;

namespace {

Image rampImage(int width, int height) {
    Image image{width, height, std::vector<float>(std::size_t(width) * height * 3)};
    for (std::size_t k = 0; k < image.rgb.size(); ++k) image.rgb[k] = float(k % 97) * 0.37f + 0.01f;
    return image;
}

double energy(const CubeImage& cube) {
    const CubeGeometry g(cube.size);
    double e = 0.0;
    for (std::size_t t = 0; t < texelCount(cube.size); ++t) e += cube.texel(t).r * g.solidAngles[t];
    return e;
}

// A float EXR of `names`, channel c holding value(c, x, y).
template <typename Value>
fs::path writeChannels(const fs::path& file, int w, int h, const std::vector<std::string>& names, Value value) {
    std::vector<std::vector<float>> planes(names.size(), std::vector<float>(std::size_t(w) * h));
    Imf::Header header(w, h);
    Imf::FrameBuffer frame;
    for (std::size_t c = 0; c < names.size(); ++c) {
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) planes[c][std::size_t(y) * w + x] = value(int(c), x, y);
        header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
        frame.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[c].data()), sizeof(float), sizeof(float) * w));
    }
    Imf::OutputFile out(file.c_str(), header);
    out.setFrameBuffer(frame);
    out.writePixels(h);
    return file;
}

// A cube's faces placed in an image `columns` x `rows` faces large, face f at places[f] (column, row,
// turned by 180 degrees); the rest black.
struct Place {
    int column, row;
    bool turned;
};
Image placeFaces(const CubeImage& cube, int columns, int rows, const std::array<Place, kFaceCount>& places) {
    const int s = cube.size;
    Image image{columns * s, rows * s, std::vector<float>(std::size_t(columns) * rows * s * s * 3)};
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < s; ++j)
            for (int i = 0; i < s; ++i) {
                const Place p = places[f];
                const int x = p.column * s + (p.turned ? s - 1 - i : i), y = p.row * s + (p.turned ? s - 1 - j : j);
                const glm::vec3 v = cube.texel(texelIndex({f, i, j}, s));
                std::copy(&v.x, &v.x + 3, &image.rgb[(std::size_t(y) * image.width + x) * 3]);
            }
    return image;
}

std::string refusal(const fs::path& file) {
    try {
        readImage(file);
    } catch (const ProbeError& e) {
        return e.what();
    }
    return "accepted";
}

} // namespace

TEST(ProbeIo, FloatExrRoundTripIsExact) {
    TempDir dir;
    const Image image = rampImage(48, 8);
    writeExr(dir.path / "a.exr", image);
    const Image back = readImage(dir.path / "a.exr");
    EXPECT_EQ(back.width, 48);
    EXPECT_EQ(back.height, 8);
    EXPECT_EQ(back.rgb, image.rgb);
}

// A header attribute that declares more bytes than the file holds is refused before OpenEXR
// allocates them.
TEST(ProbeIo, ExrAttributeLargerThanTheFileIsRefused) {
    TempDir dir;
    writeExr(dir.path / "a.exr", rampImage(48, 8));
    std::ifstream in(dir.path / "a.exr", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string channels("channels\0chlist\0", 16);
    const std::size_t at = bytes.find(channels);
    ASSERT_NE(at, std::string::npos);
    const std::int32_t huge = 1634231040;
    std::memcpy(&bytes[at + channels.size()], &huge, sizeof(huge));
    std::ofstream(dir.path / "b.exr", std::ios::binary) << bytes;
    try {
        readImage(dir.path / "b.exr");
        FAIL() << "accepted";
    } catch (const ProbeError& e) {
        EXPECT_NE(std::string(e.what()).find("1634231040 bytes, past the end of the file"), std::string::npos) << e.what();
    }
}

// The image is the data window, wherever it lies: here far below and left of the origin.
TEST(ProbeIo, ExrDataWindowAwayFromTheOrigin) {
    TempDir dir;
    const int w = 16, h = 8;
    const Imath::Box2i window(Imath::V2i(-100000, 70000), Imath::V2i(-100000 + w - 1, 70000 + h - 1));
    std::vector<float> rgb;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) rgb.insert(rgb.end(), {float(x), float(y), 0.5f});
    {
        Imf::Header header(window, window);
        Imf::FrameBuffer frame;
        for (int c = 0; c < 3; ++c) {
            const char* name = c == 0 ? "R" : (c == 1 ? "G" : "B");
            header.channels().insert(name, Imf::Channel(Imf::FLOAT));
            frame.insert(name, Imf::Slice::Make(Imf::FLOAT, rgb.data() + c, window, 3 * sizeof(float), 3 * sizeof(float) * w));
        }
        Imf::OutputFile out((dir.path / "w.exr").c_str(), header);
        out.setFrameBuffer(frame);
        out.writePixels(h);
    }
    const Image image = readImage(dir.path / "w.exr");
    ASSERT_EQ(image.width, w);
    ASSERT_EQ(image.height, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) EXPECT_EQ(image.pixel(x, y), glm::vec3(float(x), float(y), 0.5f)) << x << ", " << y;
}

TEST(ProbeIo, HalfRgbaExrInEveryCompression) {
    TempDir dir;
    const int w = 64, h = 32;
    Imf::Array2D<Imf::Rgba> pixels(h, w);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) pixels[y][x] = Imf::Rgba(float(x) / w, float(y) / h, 0.5f + 0.01f * float(x % 7), 1.0f);
    const Imf::Compression compressions[] = {Imf::NO_COMPRESSION,  Imf::RLE_COMPRESSION,  Imf::ZIPS_COMPRESSION,
                                             Imf::ZIP_COMPRESSION, Imf::PIZ_COMPRESSION,  Imf::PXR24_COMPRESSION,
                                             Imf::B44_COMPRESSION, Imf::DWAA_COMPRESSION, Imf::DWAB_COMPRESSION};
    for (Imf::Compression c : compressions) {
        const fs::path file = dir.path / fmt::format("c{}.exr", int(c));
        {
            Imf::RgbaOutputFile out(file.c_str(), w, h, Imf::WRITE_RGBA, 1.0f, Imath::V2f(0, 0), 1.0f, Imf::INCREASING_Y, c);
            out.setFrameBuffer(&pixels[0][0], 1, w);
            out.writePixels(h);
        }
        const Image image = readImage(file);
        ASSERT_EQ(image.width, w);
        // Lossy codecs (B44, DWA) stay within a few percent on this smooth ramp.
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                EXPECT_NEAR(image.pixel(x, y).r, float(pixels[y][x].r), 0.03f) << "compression " << int(c);
                EXPECT_NEAR(image.pixel(x, y).b, float(pixels[y][x].b), 0.03f) << "compression " << int(c);
            }
    }
}

// Besides R, G and B: the one layer that has them, and luminance alone as grey. Several layers with
// them, or luminance with chroma, are refused with the reason.
TEST(ProbeIo, ExrColourFromALayerOrLuminance) {
    TempDir dir;
    const int w = 16, h = 8;
    auto value = [](int c, int x, int y) { return float(c + 1) * 10.0f + float(x) + 0.25f * float(y); };
    const fs::path layer = writeChannels(dir.path / "layer.exr", w, h, {"beauty.B", "beauty.G", "beauty.R", "depth.Z"}, value);
    const Image fromLayer = readImage(layer);
    const fs::path grey = writeChannels(dir.path / "grey.exr", w, h, {"A", "Y"}, value);
    const Image fromGrey = readImage(grey);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            // Each channel holds the value of its place in the list: beauty.R the third, Y the second.
            EXPECT_EQ(fromLayer.pixel(x, y), glm::vec3(value(2, x, y), value(1, x, y), value(0, x, y))) << x << ", " << y;
            EXPECT_EQ(fromGrey.pixel(x, y), glm::vec3(value(1, x, y))) << x << ", " << y;
        }
    EXPECT_NE(refusal(writeChannels(dir.path / "two.exr", w, h, {"a.R", "a.G", "a.B", "b.R", "b.G", "b.B"}, value))
                  .find("2 layers with them ('a', 'b')"),
              std::string::npos);
    EXPECT_NE(refusal(writeChannels(dir.path / "yc.exr", w, h, {"BY", "RY", "Y"}, value)).find("luminance and chroma"), std::string::npos);
    EXPECT_NE(refusal(writeChannels(dir.path / "rg.exr", w, h, {"G", "R"}, value)).find("no R, G and B channels"), std::string::npos);
}

TEST(ProbeIo, RadianceHdr) {
    TempDir dir;
    const Image image = rampImage(32, 16);
    const fs::path file = dir.path / "a.hdr";
    ASSERT_TRUE(stbi_write_hdr(file.c_str(), image.width, image.height, 3, image.rgb.data()));
    const Image back = readImage(file);
    ASSERT_EQ(back.width, 32);
    ASSERT_EQ(back.height, 16);
    // RGBE shares one exponent per pixel: 8 bits of mantissa relative to the brightest channel.
    for (std::size_t k = 0; k < image.rgb.size(); ++k) {
        const std::size_t p = k / 3 * 3;
        const float brightest = std::max({image.rgb[p], image.rgb[p + 1], image.rgb[p + 2]});
        EXPECT_NEAR(back.rgb[k], image.rgb[k], brightest / 128.0f);
    }
}

// Widths under 8 cannot be run-length encoded: the scanlines are flat RGBE. Mantissa times 2^(e - 136).
TEST(ProbeIo, RadianceHdrFlatScanlines) {
    std::string file = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
    for (int p = 0; p < 8; ++p) file += std::string{char(128), char(64), char(32 * (p % 2)), char(129 + p / 4)};
    std::istringstream in(file);
    const Image image = readRadianceHdr(in, file.size(), "flat.hdr");
    ASSERT_EQ(image.width, 4);
    ASSERT_EQ(image.height, 2);
    EXPECT_EQ(image.pixel(1, 0), glm::vec3(1.0f, 0.5f, 0.25f));
    EXPECT_EQ(image.pixel(2, 1), glm::vec3(2.0f, 1.0f, 0.0f));

    // The same file one byte short is refused, not padded.
    std::istringstream shorter(file);
    try {
        readRadianceHdr(shorter, file.size() - 1, "flat.hdr");
        ADD_FAILURE() << "a truncated file was accepted";
    } catch (const ProbeError& e) {
        EXPECT_NE(std::string(e.what()).find("flat.hdr: Radiance HDR: file ends early"), std::string::npos) << e.what();
    }
}

TEST(ProbeIo, StripOfTheSameSizeIsACopy) {
    const CubeImage cube = roomProbe(16);
    const Image strip = cubeToStrip(cube);
    EXPECT_EQ(detectLayout(strip, "x"), ProbeLayout::faceStrip);
    EXPECT_EQ(imageToCube(strip, ProbeLayout::faceStrip, 16).rgb, cube.rgb);
}

// Faces one above the other read as the same faces side by side, at the size and shrunk.
TEST(ProbeIo, FaceColumnReadsAsTheStrip) {
    const CubeImage fine = checkerProbe(32);
    const Image column =
        placeFaces(fine, 1, 6, {{{0, 0, false}, {0, 1, false}, {0, 2, false}, {0, 3, false}, {0, 4, false}, {0, 5, false}}});
    EXPECT_EQ(detectLayout(column, "x"), ProbeLayout::faceColumn);
    EXPECT_EQ(imageToCube(column, ProbeLayout::faceColumn, 32).rgb, fine.rgb);
    EXPECT_EQ(imageToCube(column, ProbeLayout::faceColumn, 16).rgb, imageToCube(cubeToStrip(fine), ProbeLayout::faceStrip, 16).rgb);
}

// The crosses as docs/usage.md lays them out read as their faces, at the size and shrunk; and as
// Filament's cmgen reads the same files (an independent reader: `cmgen --no-mirror --extract` writes
// the faces it finds, in half floats).
TEST(ProbeIo, CrossesReadAsCmgenReadsThem) {
    TempDir dir;
    const int s = 32;
    CubeImage faces(s);
    std::mt19937 random(7);
    std::uniform_real_distribution<float> uniform(0.1f, 1.0f);
    for (float& v : faces.rgb) v = uniform(random); // texels that match in one orientation only
    const struct {
        const char* name;
        ProbeLayout layout;
        Image image;
    } crosses[] = {
        {"horizontal", ProbeLayout::horizontalCross,
         placeFaces(faces, 4, 3, {{{2, 1, false}, {0, 1, false}, {1, 0, false}, {1, 2, false}, {1, 1, false}, {3, 1, false}}})},
        {"vertical", ProbeLayout::verticalCross,
         placeFaces(faces, 3, 4, {{{2, 1, false}, {0, 1, false}, {1, 0, false}, {1, 2, false}, {1, 1, false}, {1, 3, true}}})},
    };
    const char* cmgenFaces[kFaceCount] = {"px", "nx", "py", "ny", "pz", "nz"};
    for (const auto& cross : crosses) {
        SCOPED_TRACE(cross.name);
        EXPECT_EQ(detectLayout(cross.image, "x"), cross.layout);
        const CubeImage read = imageToCube(cross.image, cross.layout, s);
        EXPECT_EQ(read.rgb, faces.rgb);
        EXPECT_EQ(imageToCube(cross.image, cross.layout, s / 2).rgb, imageToCube(cubeToStrip(faces), ProbeLayout::faceStrip, s / 2).rgb);

        const fs::path file = dir.path / fmt::format("{}.exr", cross.name), out = dir.path / cross.name;
        writeExr(file, cross.image);
        const std::string command =
            fmt::format("cmgen -q -s{} --format=exr -cRAW --no-mirror --extract='{}' '{}'", s, out.string(), file.string());
        ASSERT_EQ(std::system(command.c_str()), 0) << command << " (cmgen: Debian's libfilament-tools, which scripts/setup installs)";
        for (int f = 0; f < kFaceCount; ++f) {
            // A face is square, no probe: OpenEXR reads it.
            Imf::RgbaInputFile in((out / cross.name / fmt::format("{}.exr", cmgenFaces[f])).c_str());
            const Imath::Box2i window = in.dataWindow();
            ASSERT_EQ(window.max.x - window.min.x + 1, s);
            ASSERT_EQ(window.max.y - window.min.y + 1, s);
            Imf::Array2D<Imf::Rgba> pixels(s, s);
            in.setFrameBuffer(&pixels[0][0] - window.min.x - window.min.y * s, 1, s);
            in.readPixels(window.min.y, window.max.y);
            double worst = 0.0;
            for (int j = 0; j < s; ++j)
                for (int i = 0; i < s; ++i) {
                    const Imf::Rgba& c = pixels[j][i];
                    const glm::vec3 difference = glm::vec3(float(c.r), float(c.g), float(c.b)) - read.texel(texelIndex({f, i, j}, s));
                    worst =
                        std::max({worst, double(std::abs(difference.r)), double(std::abs(difference.g)), double(std::abs(difference.b))});
                }
            EXPECT_LT(worst, 1e-3) << "face " << cmgenFaces[f]; // half floats: 2^-11 of values below 1
        }
    }
}

TEST(ProbeIo, ShrinkingAStripIsASolidAngleWeightedBoxFilter) {
    const CubeImage fine = checkerProbe(32);
    const CubeImage coarse = imageToCube(cubeToStrip(fine), ProbeLayout::faceStrip, 16);
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) {
                double sum = 0.0, weight = 0.0;
                for (int b = 0; b < 2; ++b)
                    for (int a = 0; a < 2; ++a) {
                        const double w = texelSolidAngle(2 * i + a, 2 * j + b, 32);
                        sum += w * fine.texel(texelIndex({f, 2 * i + a, 2 * j + b}, 32)).r;
                        weight += w;
                    }
                // Subsample weights are the Jacobian at the fine texel centres, close to their solid angles.
                EXPECT_NEAR(coarse.texel(texelIndex({f, i, j}, 16)).r, sum / weight, 2e-3 * sum / weight);
            }
}

TEST(ProbeIo, EquirectangularConstantStaysConstant) {
    const Image image = syntheticEquirect("constant", 256);
    EXPECT_EQ(detectLayout(image, "x"), ProbeLayout::equirectangular);
    const CubeImage cube = imageToCube(image, ProbeLayout::equirectangular, 16);
    for (float v : cube.rgb) EXPECT_NEAR(v, 1.0f, 1e-5f);
}

TEST(ProbeIo, EquirectangularOrientation) {
    // +Y is the top row; column u = 0.5 + atan2(z, x) / (2 pi).
    Image image{64, 32, std::vector<float>(64 * 32 * 3, 0.0f)};
    auto paint = [&](int x0, int y0, float value) {
        for (int y = y0; y < y0 + 2; ++y)
            for (int x = x0; x < x0 + 2; ++x) image.rgb[(std::size_t(y) * 64 + x) * 3] = value;
    };
    paint(31, 15, 1.0f); // u = 0.5, horizon: +X
    paint(47, 15, 2.0f); // u = 0.75: atan2(z, x) = pi / 2, +Z
    const CubeImage cube = imageToCube(image, ProbeLayout::equirectangular, 8);
    EXPECT_GT(cube.texel(texelIndex(directionToTexel({1, 0, 0}, 8), 8)).r, 0.1f);
    EXPECT_GT(cube.texel(texelIndex(directionToTexel({0, 0, 1}, 8), 8)).r, 0.2f);
    EXPECT_EQ(cube.texel(texelIndex(directionToTexel({-1, 0, 0}, 8), 8)).r, 0.0f);
}

TEST(ProbeIo, SmallSunKeepsItsEnergyAtEverySize) {
    // A 2 degree sun of 1e4 in a 2048 x 1024 image: its energy must not alias away when shrinking.
    const Image image = syntheticEquirect("sunsky", 2048);
    const Image sky = syntheticEquirect("sky", 2048);
    double pixelEnergy = 0.0;
    for (int y = 0; y < image.height; ++y) {
        const double theta0 = double(y) / image.height * std::numbers::pi, theta1 = double(y + 1) / image.height * std::numbers::pi;
        const double solidAngle = (std::cos(theta0) - std::cos(theta1)) * 2.0 * std::numbers::pi / image.width;
        for (int x = 0; x < image.width; ++x) pixelEnergy += (image.pixel(x, y).r - sky.pixel(x, y).r) * solidAngle;
    }
    for (int size : {4, 8, 16, 32, 64, 128}) {
        const double sun =
            energy(imageToCube(image, ProbeLayout::equirectangular, size)) - energy(imageToCube(sky, ProbeLayout::equirectangular, size));
        EXPECT_NEAR(sun, pixelEnergy, 0.01 * pixelEnergy) << "face size " << size;
    }
}

TEST(ProbeIo, NanAndInfAreRefusedWithCountAndPosition) {
    Image image = rampImage(12, 6);
    image.rgb[(2 * 12 + 5) * 3 + 1] = std::numeric_limits<float>::quiet_NaN();
    image.rgb[(4 * 12 + 1) * 3 + 0] = -1.0f;
    image.rgb[(5 * 12 + 0) * 3 + 2] = std::numeric_limits<float>::infinity();
    try {
        Image copy = image;
        checkPixels(copy, "probe.exr", BadPixelPolicy::refuse);
        FAIL() << "NaN and Inf accepted";
    } catch (const ProbeError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("probe.exr"), std::string::npos) << message;
        EXPECT_NE(message.find("2 pixel"), std::string::npos) << message;
        EXPECT_NE(message.find("x=5 y=2"), std::string::npos) << message;
    }
    const PixelRepairs repairs = checkPixels(image, "probe.exr", BadPixelPolicy::repair);
    EXPECT_EQ(repairs.nonFinite, 2u);
    EXPECT_EQ(repairs.negative, 1u);
    for (float v : image.rgb) EXPECT_TRUE(std::isfinite(v) && v >= 0.0f);
}

TEST(ProbeIo, NegativePixelsAreClampedAndCounted) {
    Image image = rampImage(12, 6);
    image.rgb[(1 * 12 + 3) * 3 + 0] = -1900.0f;
    image.rgb[(1 * 12 + 3) * 3 + 2] = -0.5f; // the same pixel: counted once
    image.rgb[(3 * 12 + 7) * 3 + 1] = -1e-3f;
    const float kept = image.rgb[(1 * 12 + 3) * 3 + 1];
    const PixelRepairs repairs = checkPixels(image, "probe.exr", BadPixelPolicy::refuse);
    EXPECT_EQ(repairs.negative, 2u);
    EXPECT_EQ(repairs.nonFinite, 0u);
    EXPECT_EQ(image.rgb[(1 * 12 + 3) * 3 + 0], 0.0f);
    EXPECT_EQ(image.rgb[(1 * 12 + 3) * 3 + 1], kept);
    EXPECT_EQ(image.rgb[(3 * 12 + 7) * 3 + 1], 0.0f);
}

TEST(ProbeIo, WrongAspectRatioIsRefused) {
    const Image image = rampImage(30, 20);
    EXPECT_THROW(detectLayout(image, "x.exr"), ProbeError);
}
