#include "probe/cube_image.h"

#include <algorithm>

namespace probe {

Image cubeToStrip(const CubeImage& cube) {
    const int s = cube.size;
    Image strip{kFaceCount * s, s, std::vector<float>(cube.rgb.size())};
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < s; ++j) {
            const float* row = &cube.rgb[texelIndex({f, 0, j}, s) * 3];
            std::copy(row, row + 3 * s, &strip.rgb[(static_cast<std::size_t>(j) * strip.width + f * s) * 3]);
        }
    return strip;
}

std::optional<ProbeLayout> layoutOfShape(std::int64_t width, std::int64_t height) {
    if (width == 2 * height) return ProbeLayout::equirectangular;
    if (width == 6 * height) return ProbeLayout::faceStrip;
    if (height == 6 * width) return ProbeLayout::faceColumn;
    if (3 * width == 4 * height) return ProbeLayout::horizontalCross;
    if (4 * width == 3 * height) return ProbeLayout::verticalCross;
    return std::nullopt;
}

const char* layoutName(ProbeLayout layout) {
    switch (layout) {
    case ProbeLayout::equirectangular: return "equirectangular";
    case ProbeLayout::faceStrip: return "face strip";
    case ProbeLayout::faceColumn: return "face column";
    case ProbeLayout::horizontalCross: return "horizontal cross";
    default: return "vertical cross";
    }
}

} // namespace probe
