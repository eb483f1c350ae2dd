// Finite input gives finite output. The filters add up many weighted float texels, and near
// FLT_MAX (3.4e38) those sums overflow to Inf, then NaN. A probe whose largest value is above 2^64
// is therefore filtered scaled down by a power of two, which is exact in float, and its output
// scaled back up, saturating at FLT_MAX. The CPU model and the GPU scale alike, so they stay equal,
// and a probe below 2^64 (every real one) is filtered as it is.
#pragma once

#include "probe/cube_image.h"

namespace probe {

// The largest value a probe is filtered at: 2^64.
inline constexpr float kFilterRangeLimit = 18446744073709551616.0f;

// The largest |value| of the image.
float largestMagnitude(const CubeImage& image);

// The smallest e >= 0 with largest * 2^-e <= kFilterRangeLimit: for an image, its largest magnitude.
int rangeShift(double largest);
int rangeShift(const CubeImage& image);

// Every value times 2^shift (shift may be negative), saturating at +-FLT_MAX.
CubeImage shifted(const CubeImage& image, int shift);
void shiftLevels(CubeLevels& levels, int shift);

// Every value clamped to at most kFilterRangeLimit: for outputs whose format saturates far below
// it (16-bit floats, 65504) anyway, where scaling back would lose the small values.
CubeImage rangeLimited(const CubeImage& image);

} // namespace probe
