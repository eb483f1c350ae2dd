#include "probe/range_scale.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace probe {

int rangeShift(double largest, double limit) {
    if (!(largest > limit)) return 0;
    int exponent = 0; // largest / limit = f * 2^exponent, 0.5 <= f < 1, so largest * 2^-exponent < limit
    std::frexp(largest / limit, &exponent);
    return exponent;
}

float largestMagnitude(const CubeImage& image) {
    float largest = 0.0f;
    for (float v : image.rgb) largest = std::max(largest, std::abs(v));
    return largest;
}

int rangeShift(const CubeImage& image) { return rangeShift(largestMagnitude(image)); }

CubeImage shifted(const CubeImage& image, int shift) {
    CubeImage out = image;
    if (shift == 0) return out;
    constexpr float largest = std::numeric_limits<float>::max();
    for (float& v : out.rgb) v = std::clamp(std::ldexp(v, shift), -largest, largest);
    return out;
}

void shiftLevels(CubeLevels& levels, int shift) {
    for (CubeImage& level : levels) level = shifted(level, shift);
}

} // namespace probe
