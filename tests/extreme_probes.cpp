// The largest finite inputs, and a check that outputs hold no NaN or Inf, for cli_extreme_values.sh.
//   extreme_probes make DIR      writes one_max.exr (a sky with one texel at FLT_MAX), all_max.exr
//                                (every texel FLT_MAX) and rgbe_max.hdr (every pixel the largest RGBE value)
//   extreme_probes check FILE... prints each EXR's or KTX2's non-finite value count; exit 1 if any
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "probe/ktx2.h"
#include "probe/probe_io.h"
#include "probe/synthetic.h"

using namespace probe;
namespace fs = std::filesystem;

namespace {

constexpr int kFaceSize = 16;

void writeLargestRgbe(const fs::path& path, int width, int height) {
    // Mantissas 255 with exponent byte 255: 255 * 2^(255 - 136), about 1.7e38 (the largest RGBE value).
    std::ofstream out(path, std::ios::binary);
    out << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " << height << " +X " << width << "\n";
    const std::vector<char> pixels(std::size_t(width) * height * 4, char(255));
    out.write(pixels.data(), static_cast<std::streamsize>(pixels.size()));
}

std::size_t nonFinite(const std::vector<float>& values) {
    std::size_t count = 0;
    for (float v : values) count += !std::isfinite(v);
    return count;
}

std::size_t nonFinite(const fs::path& path) {
    if (path.extension() == ".ktx2") {
        std::size_t count = 0;
        for (const CubeImage& level : readKtx2Cube(path).levels) count += nonFinite(level.rgb);
        return count;
    }
    return nonFinite(readImage(path).rgb);
}

} // namespace

int main(int argc, char** argv) {
    if (argc >= 3 && std::strcmp(argv[1], "make") == 0) {
        const fs::path dir = argv[2];
        fs::create_directories(dir);
        const float largest = std::numeric_limits<float>::max();
        Image image = cubeToStrip(skyProbe(kFaceSize));
        image.rgb[(3 * image.width + 17) * 3 + 1] = largest;
        writeExr(dir / "one_max.exr", image);
        std::fill(image.rgb.begin(), image.rgb.end(), largest);
        writeExr(dir / "all_max.exr", image);
        writeLargestRgbe(dir / "rgbe_max.hdr", 6 * kFaceSize, kFaceSize);
        return 0;
    }
    if (argc >= 3 && std::strcmp(argv[1], "check") == 0) {
        int status = 0;
        for (int k = 2; k < argc; ++k) {
            const std::size_t count = nonFinite(argv[k]);
            std::printf("%s: %zu non-finite value(s)\n", argv[k], count);
            if (count) status = 1;
        }
        return status;
    }
    std::fprintf(stderr, "usage: extreme_probes make DIR | extreme_probes check FILE...\n");
    return 2;
}
