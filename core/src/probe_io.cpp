#include "probe/probe_io.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <set>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfTileDescription.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <unistd.h>

#include "probe/error.h"
#include "probe/input_file.h"
#include "probe/ktx2_image.h"
#include "probe/limits.h"
#include "probe/output_file.h"
#include "probe/radiance_hdr.h"

namespace fs = std::filesystem;

namespace probe {

namespace {

[[noreturn]] void fail(const fs::path& path, const std::string& problem) {
    throw ProbeError(fmt::format("{}: {}", path.string(), problem));
}

// A library's message on one line (OpenEXR's may hold several).
std::string firstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

std::string readMagic(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file");
    char magic[4] = {};
    in.read(magic, 4);
    return std::string(magic, static_cast<std::size_t>(in.gcount()));
}

std::string describeWindow(const Imath::Box2i& window) {
    return fmt::format("({}, {}) to ({}, {})", window.min.x, window.min.y, window.max.x, window.max.y);
}

// The header alone, read before OpenEXR opens the file: opening allocates by the data window and the
// tile count, so both are checked first.
// OpenEXR allocates the size an attribute declares before it reads the attribute, so a few hundred
// bytes could ask for gigabytes: walk the attribute list (name, type, int32 size, value; an empty
// name ends it) and refuse a size that runs past the end of the file.
void checkExrAttributeSizes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    const std::uintmax_t fileSize = fs::file_size(path);
    in.seekg(8);                             // the magic number and the version field
    auto readName = [&](std::string& name) { // names and type names are at most 255 bytes
        name.clear();
        for (char c; in.get(c) && c != '\0';)
            if (name.size() < 255) name += c;
            else return false;
        return bool(in);
    };
    std::string name, type;
    for (int k = 0;; ++k) {
        if (!readName(name)) fail(path, "EXR header ends early");
        if (name.empty()) return;
        std::int32_t size = 0;
        if (!readName(type) || !in.read(reinterpret_cast<char*>(&size), sizeof(size))) fail(path, "EXR header ends early");
        const std::uintmax_t at = static_cast<std::uintmax_t>(in.tellg());
        if (size < 0 || at + static_cast<std::uintmax_t>(size) > fileSize)
            fail(path, fmt::format("EXR header attribute {} declares {} bytes, past the end of the file", k, size));
        in.seekg(size, std::ios::cur);
    }
}

void checkExrHeader(const fs::path& path) {
    checkExrAttributeSizes(path);
    Imf::StdIFStream stream(path.c_str());
    char start[8] = {}; // the magic number and the version field; readFrom reads what follows
    stream.read(start, 8);
    int version = 0;
    std::memcpy(&version, start + 4, sizeof(version)); // little-endian on disk, as on the hosts we build for
    // A probe is one flat image: a multi-part file's later headers and deep data's per-pixel sample
    // counts would escape the checks here.
    if (version & 0x1000) fail(path, "a multi-part EXR; probefilter reads single-part files");
    if (version & 0x800) fail(path, "deep EXR data; probefilter reads flat images");
    Imf::Header header;
    header.readFrom(stream, version);
    // OpenEXR reads a file by its version field's tiled flag, whatever the header holds: a tiled
    // header without it would read as scanlines of nothing.
    const bool tiledFlag = (version & 0x200) != 0;
    if (header.hasTileDescription() != tiledFlag)
        fail(path, tiledFlag ? "EXR version field says tiled, but the header has no tile description"
                             : "EXR header has a tile description, but the version field lacks the tiled flag");
    int channelCount = 0; // ChannelList's iterator is not a standard one
    for (auto channel = header.channels().begin(); channel != header.channels().end(); ++channel) ++channelCount;
    if (channelCount > kMaxExrChannels)
        fail(path, fmt::format("EXR has {} channels, over the limit of {} (a probe needs R, G and B)", channelCount, kMaxExrChannels));
    // The panorama is the display window; the pixels are the data window's. Where they differ the
    // image would be stretched or cropped without a word.
    const Imath::Box2i window = header.dataWindow();
    if (window != header.displayWindow())
        fail(path, fmt::format("EXR data window {} differs from its display window {}; a probe's pixels must cover the display "
                               "window exactly",
                               describeWindow(window), describeWindow(header.displayWindow())));
    const std::int64_t width = std::int64_t{window.max.x} - window.min.x + 1, height = std::int64_t{window.max.y} - window.min.y + 1;
    if (const std::string problem = imageSizeProblem(width, height); !problem.empty()) fail(path, problem);
    if (header.hasTileDescription()) {
        const Imf::TileDescription& tiles = header.tileDescription();
        if (tiles.xSize < 1 || tiles.ySize < 1) fail(path, "EXR tiles have zero size");
        const std::int64_t tileCount = (width + tiles.xSize - 1) / tiles.xSize * ((height + tiles.ySize - 1) / tiles.ySize);
        if (tileCount > kMaxImagePixels / 256)
            fail(path, fmt::format("EXR has {} tiles of {} x {}, too many", tileCount, tiles.xSize, tiles.ySize));
    }
}

// The channels a probe is read from: R, G and B; else those of the one layer that has all three (a
// compositor's "beauty.R"); else a luminance image's Y, read as grey (b empty).
struct ColourChannels {
    std::string r, g, b;
};

// A name from the file, printable and short enough for a one-line message.
std::string printableName(const std::string& name) {
    std::string out;
    for (char c : name.substr(0, 40)) out += c >= 0x20 && c < 0x7f ? c : '?';
    return name.size() > 40 ? out + "..." : out;
}

ColourChannels colourChannels(const Imf::ChannelList& channels, const fs::path& path) {
    auto hasRgb = [&](const std::string& prefix) {
        return channels.findChannel(prefix + "R") && channels.findChannel(prefix + "G") && channels.findChannel(prefix + "B");
    };
    if (hasRgb("")) return {"R", "G", "B"};
    std::set<std::string> layers;
    channels.layers(layers);
    std::vector<std::string> rgbLayers;
    for (const std::string& layer : layers)
        if (hasRgb(layer + ".")) rgbLayers.push_back(layer);
    if (rgbLayers.size() == 1) return {rgbLayers[0] + ".R", rgbLayers[0] + ".G", rgbLayers[0] + ".B"};
    if (rgbLayers.size() > 1)
        fail(path,
             fmt::format("EXR has no R, G and B channels but {} layers with them ('{}', '{}'{}); probefilter reads a file "
                         "with one",
                         rgbLayers.size(), printableName(rgbLayers[0]), printableName(rgbLayers[1]), rgbLayers.size() > 2 ? ", ..." : ""));
    if (channels.findChannel("Y")) {
        if (channels.findChannel("RY") || channels.findChannel("BY"))
            fail(path, "EXR holds luminance and chroma (Y, RY, BY); probefilter reads RGB, or Y alone as grey");
        return {"Y", "", ""};
    }
    fail(path, "EXR has no R, G and B channels, no layer with them and no Y (RGB, RGBA or luminance expected)");
}

Image readExr(const fs::path& path) {
    try {
        checkExrHeader(path);
        Imf::InputFile file(path.c_str());
        if (!file.isComplete()) fail(path, "EXR is truncated: part of its pixel data is missing");
        const Imath::Box2i window = file.header().dataWindow();
        const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
        const ColourChannels colour = colourChannels(file.header().channels(), path);
        // Memory is taken as rows decode (reserved, then resized block by block), so that a file whose
        // header promises more than its data holds fails before it costs the whole image.
        const std::size_t rowFloats = static_cast<std::size_t>(width) * 3;
        Image image{width, height, {}};
        image.rgb.reserve(rowFloats * height);
        // OpenEXR addresses the buffer with absolute data-window coordinates; Slice::Make offsets the
        // base pointer by the window's origin without pointer arithmetic outside the buffer.
        float* rgb = image.rgb.data();
        Imf::FrameBuffer frame;
        const std::size_t xStride = 3 * sizeof(float), yStride = xStride * width;
        frame.insert(colour.r, Imf::Slice::Make(Imf::FLOAT, rgb, window, xStride, yStride));
        if (!colour.b.empty()) {
            frame.insert(colour.g, Imf::Slice::Make(Imf::FLOAT, rgb + 1, window, xStride, yStride));
            frame.insert(colour.b, Imf::Slice::Make(Imf::FLOAT, rgb + 2, window, xStride, yStride));
        }
        file.setFrameBuffer(frame);
        constexpr int kBlockRows = 64;
        for (int row = 0; row < height; row += kBlockRows) {
            const int rows = std::min(kBlockRows, height - row);
            image.rgb.resize(rowFloats * static_cast<std::size_t>(row + rows));
            file.readPixels(window.min.y + row, window.min.y + row + rows - 1);
        }
        if (colour.b.empty())
            for (std::size_t p = 0; p < image.rgb.size(); p += 3) image.rgb[p + 1] = image.rgb[p + 2] = image.rgb[p];
        return image;
    } catch (const ProbeError&) {
        throw;
    } catch (const std::exception& e) {
        fail(path, fmt::format("unreadable or corrupt EXR ({})", firstLine(e.what())));
    }
}

Image readHdr(const fs::path& path, std::uintmax_t size) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file");
    return readRadianceHdr(in, size, path);
}

Image readKtx2(const fs::path& path, std::uintmax_t size) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file");
    return readKtx2Image(in, size, path);
}

// Bilinear read of an equirectangular image at a unit direction, wrapping in longitude and
// clamping in latitude.
glm::vec3 sampleEquirect(const Image& image, const glm::dvec3& d) {
    const double u = 0.5 + std::atan2(d.z, d.x) / (2.0 * std::numbers::pi);
    const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / std::numbers::pi;
    const double x = u * image.width - 0.5, y = v * image.height - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
    const int w = image.width, h = image.height;
    const int xa = ((static_cast<int>(x0) % w) + w) % w, xb = (xa + 1) % w;
    const int ya = std::clamp(static_cast<int>(y0), 0, h - 1), yb = std::clamp(static_cast<int>(y0) + 1, 0, h - 1);
    const glm::vec3 top = image.pixel(xa, ya) * (1.0f - fx) + image.pixel(xb, ya) * fx;
    const glm::vec3 bottom = image.pixel(xa, yb) * (1.0f - fx) + image.pixel(xb, yb) * fx;
    return top * (1.0f - fy) + bottom * fy;
}

// Where face f lies in an image of faces: its column and row in face sizes, and whether it is turned
// by 180 degrees.
struct FacePlace {
    int column, row;
    bool turned;
};

std::array<FacePlace, kFaceCount> facePlaces(ProbeLayout layout) {
    switch (layout) {
    case ProbeLayout::faceStrip: return {{{0, 0, false}, {1, 0, false}, {2, 0, false}, {3, 0, false}, {4, 0, false}, {5, 0, false}}};
    case ProbeLayout::faceColumn: return {{{0, 0, false}, {0, 1, false}, {0, 2, false}, {0, 3, false}, {0, 4, false}, {0, 5, false}}};
    case ProbeLayout::horizontalCross: return {{{2, 1, false}, {0, 1, false}, {1, 0, false}, {1, 2, false}, {1, 1, false}, {3, 1, false}}};
    default: return {{{2, 1, false}, {0, 1, false}, {1, 0, false}, {1, 2, false}, {1, 1, false}, {1, 3, true}}}; // vertical cross
    }
}

// The face size of an image of faces.
int faceSizeOf(const Image& image, ProbeLayout layout) {
    switch (layout) {
    case ProbeLayout::faceStrip: return image.height;
    case ProbeLayout::horizontalCross: return image.width / 4;
    default: return image.width / (layout == ProbeLayout::verticalCross ? 3 : 1); // column, vertical cross
    }
}

// Bilinear read of an image of faces at a unit direction, clamped to the face (used only to
// resample).
glm::vec3 sampleFaces(const Image& image, int s, const std::array<FacePlace, kFaceCount>& places, const glm::dvec3& d) {
    const FaceUv f = directionToFaceUv(d);
    const double x = (f.u + 1.0) * 0.5 * s - 0.5, y = (f.v + 1.0) * 0.5 * s - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
    const int xa = std::clamp(static_cast<int>(x0), 0, s - 1), xb = std::clamp(static_cast<int>(x0) + 1, 0, s - 1);
    const int ya = std::clamp(static_cast<int>(y0), 0, s - 1), yb = std::clamp(static_cast<int>(y0) + 1, 0, s - 1);
    const FacePlace place = places[f.face];
    auto texel = [&](int i, int j) {
        if (place.turned) i = s - 1 - i, j = s - 1 - j;
        return image.pixel(place.column * s + i, place.row * s + j);
    };
    const glm::vec3 top = texel(xa, ya) * (1.0f - fx) + texel(xb, ya) * fx;
    const glm::vec3 bottom = texel(xa, yb) * (1.0f - fx) + texel(xb, yb) * fx;
    return top * (1.0f - fy) + bottom * fy;
}

template <typename Sampler>
CubeImage resample(int faceSize, int subsamples, Sampler sample) {
    CubeImage cube(faceSize);
    const double texelWidth = 2.0 / faceSize, step = texelWidth / subsamples;
#pragma omp parallel for collapse(2) schedule(dynamic)
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < faceSize; ++j)
            for (int i = 0; i < faceSize; ++i) {
                glm::dvec3 sum(0.0);
                double weightSum = 0.0;
                for (int b = 0; b < subsamples; ++b)
                    for (int a = 0; a < subsamples; ++a) {
                        const double u = -1.0 + i * texelWidth + (a + 0.5) * step;
                        const double v = -1.0 + j * texelWidth + (b + 0.5) * step;
                        // Solid angle per unit face area: (1 + u^2 + v^2)^(-3/2).
                        const double r2 = 1.0 + u * u + v * v;
                        const double weight = 1.0 / (r2 * std::sqrt(r2));
                        sum += weight * glm::dvec3(sample(glm::normalize(faceUvToCubePoint(f, u, v))));
                        weightSum += weight;
                    }
                cube.set(texelIndex({f, i, j}, faceSize), glm::vec3(sum / weightSum));
            }
    return cube;
}

} // namespace

Image readImage(const fs::path& path) {
    // Images are read as they stream in; the pixel limits bound the memory, not the file size.
    const std::uintmax_t size = checkInputFile(path, std::numeric_limits<std::uintmax_t>::max());
    if (size == 0) fail(path, "file is empty (zero-size image)");
    const std::string magic = readMagic(path);
    if (magic == std::string("\x76\x2f\x31\x01", 4)) return readExr(path);
    if (magic.rfind("#?", 0) == 0) return readHdr(path, size);
    if (magic == "\xABKTX") return readKtx2(path, size);
    fail(path, "not an OpenEXR, Radiance HDR or KTX2 file");
}

PixelRepairs checkPixels(Image& image, const fs::path& path, BadPixelPolicy policy) {
    PixelRepairs repairs;
    std::size_t first = 0;
    for (std::size_t p = 0; p < image.rgb.size() / 3; ++p) {
        bool negative = false, nonFinite = false;
        for (int c = 0; c < 3; ++c) {
            const float value = image.rgb[3 * p + c];
            nonFinite = nonFinite || !std::isfinite(value);
            negative = negative || value < 0.0f;
        }
        if (nonFinite && repairs.nonFinite++ == 0) first = p;
        else if (negative) ++repairs.negative;
    }
    if (repairs.nonFinite && policy == BadPixelPolicy::refuse) {
        const int x = static_cast<int>(first % image.width), y = static_cast<int>(first / image.width);
        const glm::vec3 value = image.pixel(x, y);
        fail(path, fmt::format("{} pixel(s) are NaN or Inf, first at x={} y={} ({}, {}, {}); --repair-pixels sets them to 0",
                               repairs.nonFinite, x, y, value.r, value.g, value.b));
    }
    // Each channel on its own: a pixel with one bad channel keeps the others.
    for (float& value : image.rgb)
        if (!std::isfinite(value) || value < 0.0f) value = 0.0f;
    return repairs;
}

ProbeLayout detectLayout(const Image& image, const fs::path& path) {
    if (const std::optional<ProbeLayout> layout = layoutOfShape(image.width, image.height)) return *layout;
    fail(path, fmt::format("wrong aspect ratio {}x{}: expected {}", image.width, image.height, kProbeShapes));
}

CubeImage imageToCube(const Image& image, ProbeLayout layout, int faceSize) {
    if (layout != ProbeLayout::equirectangular) {
        // Subsamples land exactly on source texel centres when the sizes divide.
        const int sourceSize = faceSizeOf(image, layout);
        const int subsamples = std::max(1, (sourceSize + faceSize - 1) / faceSize);
        const std::array<FacePlace, kFaceCount> places = facePlaces(layout);
        return resample(faceSize, subsamples, [&](const glm::dvec3& d) { return sampleFaces(image, sourceSize, places, d); });
    }
    // A face texel spans about height / (2 S) source rows; take two subsamples per source pixel.
    const int subsamples = std::max(2, (image.height + faceSize - 1) / faceSize);
    return resample(faceSize, subsamples, [&](const glm::dvec3& d) { return sampleEquirect(image, d); });
}

CubeImage loadProbe(const fs::path& path, int faceSize, BadPixelPolicy policy, PixelRepairs& repairs) {
    Image image = readImage(path);
    const ProbeLayout layout = detectLayout(image, path);
    repairs = checkPixels(image, path, policy);
    return imageToCube(image, layout, faceSize);
}

namespace {

// An EXR's file, every write checked. OpenEXR writes the line offsets as its OutputFile closes, in a
// destructor that swallows errors, so the stream keeps its first error for writeExr to report.
class CheckedExrStream final : public Imf::OStream {
public:
    explicit CheckedExrStream(const fs::path& path)
        : Imf::OStream(path.c_str()), fd_(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666)) {
        if (fd_ < 0) error_ = errno;
    }
    ~CheckedExrStream() override {
        if (fd_ >= 0) ::close(fd_);
    }
    CheckedExrStream(const CheckedExrStream&) = delete;
    CheckedExrStream& operator=(const CheckedExrStream&) = delete;

    void write(const char c[], int n) override {
        if (!error_) error_ = writeAll(fd_, std::string_view(c, static_cast<std::size_t>(n)));
        if (error_) throw std::runtime_error(std::strerror(error_));
    }
    uint64_t tellp() override { return fd_ < 0 ? 0 : static_cast<uint64_t>(::lseek(fd_, 0, SEEK_CUR)); }
    void seekp(uint64_t pos) override {
        if (!error_ && ::lseek(fd_, static_cast<off_t>(pos), SEEK_SET) < 0) error_ = errno;
    }

    // The first error of any write, the close included; 0 if none.
    int close() {
        if (fd_ >= 0 && ::close(fd_) != 0 && !error_) error_ = errno;
        fd_ = -1;
        return error_;
    }

private:
    int fd_;
    int error_ = 0;
};

} // namespace

void writeExr(const fs::path& path, const Image& image) {
    CheckedExrStream stream(path);
    try {
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        Imf::OutputFile file(stream, header);
        Imf::FrameBuffer frame;
        char* base = const_cast<char*>(reinterpret_cast<const char*>(image.rgb.data()));
        const std::size_t xStride = 3 * sizeof(float), yStride = xStride * image.width;
        frame.insert("R", Imf::Slice(Imf::FLOAT, base, xStride, yStride));
        frame.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xStride, yStride));
        frame.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xStride, yStride));
        file.setFrameBuffer(frame);
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        // A failed write is the stream's error, reported below; any other is OpenEXR's.
        if (!stream.close()) fail(path, fmt::format("cannot write EXR ({})", e.what()));
    }
    if (const int error = stream.close()) fail(path, fmt::format("cannot write ({})", std::strerror(error)));
}

std::string levelFileName(int level) { return fmt::format("level_{}.exr", level); }

} // namespace probe
