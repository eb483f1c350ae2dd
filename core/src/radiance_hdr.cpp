#include "probe/radiance_hdr.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/limits.h"

namespace probe {

namespace {

constexpr std::size_t kMaxHeaderLine = 4096;
constexpr int kMaxHeaderLines = 1024;
constexpr int kMinRleWidth = 8, kMaxRleWidth = 0x7fff; // widths the run-length encoding can describe

class Decoder {
public:
    Decoder(std::istream& in, std::uintmax_t byteCount, const std::filesystem::path& path) : in_(in), left_(byteCount), path_(path) {}

    [[noreturn]] void fail(const std::string& problem) const {
        throw ProbeError(fmt::format("{}: Radiance HDR: {}", path_.string(), problem));
    }

    std::uintmax_t left() const { return left_; }

    std::uint8_t byte(const char* what) {
        const int c = left_ > 0 ? in_.get() : std::char_traits<char>::eof();
        if (c == std::char_traits<char>::eof()) fail(fmt::format("file ends early ({})", what));
        --left_;
        return static_cast<std::uint8_t>(c);
    }

    void bytes(std::uint8_t* out, std::size_t count, const char* what) {
        if (count > left_) fail(fmt::format("file ends early ({})", what));
        in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(count));
        if (static_cast<std::size_t>(in_.gcount()) != count) fail(fmt::format("file ends early ({})", what));
        left_ -= count;
    }

    std::string line() {
        std::string text;
        for (;;) {
            const char c = static_cast<char>(byte("in the header"));
            if (c == '\n') return text;
            if (text.size() == kMaxHeaderLine) fail(fmt::format("header line longer than {} bytes", kMaxHeaderLine));
            text += c;
        }
    }

private:
    std::istream& in_;
    std::uintmax_t left_;
    const std::filesystem::path& path_;
};

// Reads "-Y H +X W", the standard orientation (row 0 at the top, left to right).
void parseResolution(const Decoder& d, const std::string& text, int& width, int& height) {
    long long h = 0, w = 0;
    char rest = 0;
    if (std::sscanf(text.c_str(), "-Y %lld +X %lld%c", &h, &w, &rest) != 2)
        d.fail(
            fmt::format("resolution line '{}' is not '-Y <height> +X <width>' (other orientations are not supported)", text.substr(0, 64)));
    if (const std::string problem = imageSizeProblem(w, h); !problem.empty()) d.fail(problem);
    width = static_cast<int>(w);
    height = static_cast<int>(h);
}

// One run-length encoded scanline (after its 4-byte marker): each of the four components in turn,
// as runs (count > 128: the next byte count - 128 times) and literals (count <= 128 bytes).
void readRleScanline(Decoder& d, std::vector<std::uint8_t>& rgbe, int width) {
    std::vector<std::uint8_t> component(static_cast<std::size_t>(width));
    for (int c = 0; c < 4; ++c) {
        int x = 0;
        while (x < width) {
            int count = d.byte("in a scanline");
            const bool run = count > 128;
            if (run) count -= 128;
            if (count == 0 || count > width - x)
                d.fail(fmt::format("{} of {} at x={} does not fit a scanline of {}", run ? "run" : "literal", count, x, width));
            if (run) std::fill_n(component.begin() + x, count, d.byte("in a scanline"));
            else d.bytes(component.data() + x, static_cast<std::size_t>(count), "in a scanline");
            x += count;
        }
        for (int i = 0; i < width; ++i) rgbe[4 * static_cast<std::size_t>(i) + c] = component[i];
    }
}

// RGBE to float as stb_image and Radiance's own tools: mantissa times 2^(e - 136), 0 where e is 0.
void convert(const std::vector<std::uint8_t>& rgbe, float* out, int width) {
    for (int i = 0; i < width; ++i) {
        const std::uint8_t* p = &rgbe[4 * static_cast<std::size_t>(i)];
        const float scale = p[3] == 0 ? 0.0f : std::ldexp(1.0f, p[3] - (128 + 8));
        for (int c = 0; c < 3; ++c) out[3 * i + c] = p[c] * scale;
    }
}

} // namespace

Image readRadianceHdr(std::istream& in, std::uintmax_t byteCount, const std::filesystem::path& path) {
    Decoder d(in, byteCount, path);
    const std::string magic = d.line();
    if (magic != "#?RADIANCE" && magic != "#?RGBE") d.fail("does not start with #?RADIANCE or #?RGBE");
    bool rgbeFormat = false;
    for (int lines = 0;; ++lines) {
        if (lines == kMaxHeaderLines) d.fail(fmt::format("header has more than {} lines", kMaxHeaderLines));
        const std::string text = d.line();
        if (text.empty()) break;
        if (text.starts_with("FORMAT=")) {
            if (text != "FORMAT=32-bit_rle_rgbe") d.fail(fmt::format("unsupported {} (32-bit_rle_rgbe expected)", text.substr(0, 64)));
            rgbeFormat = true;
        }
    }
    if (!rgbeFormat) d.fail("header has no FORMAT=32-bit_rle_rgbe line");
    int width = 0, height = 0;
    parseResolution(d, d.line(), width, height);

    // Every scanline takes at least 4 + 8 ceil(W / 127) bytes (run-length encoded) or 4 W (flat): a
    // file too short for its size is refused before the pixels' memory is taken.
    const std::uintmax_t rleMinimum = 4 + 8 * ((static_cast<std::uintmax_t>(width) + 126) / 127);
    const bool rlePossible = width >= kMinRleWidth && width <= kMaxRleWidth;
    const std::uintmax_t lineMinimum = rlePossible ? std::min<std::uintmax_t>(rleMinimum, 4u * width) : 4u * width;
    if (d.left() / lineMinimum < static_cast<std::uintmax_t>(height))
        d.fail(fmt::format("file ends early: {} bytes cannot hold {} scanlines of {} pixels", d.left(), height, width));

    // Reserved, then resized row by row: memory follows the rows that decode.
    Image image{width, height, {}};
    image.rgb.reserve(static_cast<std::size_t>(width) * height * 3);
    std::vector<std::uint8_t> rgbe(4 * static_cast<std::size_t>(width));
    for (int y = 0; y < height; ++y) {
        std::array<std::uint8_t, 4> start{};
        d.bytes(start.data(), 4, fmt::format("scanline {} of {}", y, height).c_str());
        if (rlePossible && start[0] == 2 && start[1] == 2 && start[2] < 128) {
            if ((start[2] << 8 | start[3]) != width)
                d.fail(fmt::format("scanline {} says width {}, the header {}", y, start[2] << 8 | start[3], width));
            readRleScanline(d, rgbe, width);
        } else {
            std::copy(start.begin(), start.end(), rgbe.begin());
            d.bytes(rgbe.data() + 4, rgbe.size() - 4, fmt::format("scanline {} of {}", y, height).c_str());
        }
        image.rgb.resize(image.rgb.size() + 3 * static_cast<std::size_t>(width));
        convert(rgbe, image.rgb.data() + 3 * static_cast<std::size_t>(y) * width, width);
    }
    return image;
}

} // namespace probe
