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

} // namespace probe
