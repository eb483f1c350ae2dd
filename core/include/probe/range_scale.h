// Finite input gives finite output. The filters add up many weighted float texels, and near
// FLT_MAX (3.4e38) those sums overflow to Inf, then NaN. A probe whose largest value is above 2^64
// is therefore filtered scaled down by a power of two, which is exact in float, and its output
// scaled back up, saturating at FLT_MAX. The CPU model and the GPU scale alike, so they stay equal,
// and a probe below 2^64 (every real one) is filtered as it is. The GPU passes also clamp every
// source value they read to +-2^64: after the scaling that changes nothing, and on the engine path
// (gpu::Filter::record), whose source never reaches the host, larger values saturate there instead.
#pragma once

#include "probe/cube_image.h"
#include "probe/shared_constants.h"

namespace probe {

// The largest magnitude a probe is filtered at: 2^64.
inline constexpr float kFilterRangeLimit = float(PROBE_FILTER_RANGE_LIMIT);

// The largest |value| of the image.
float largestMagnitude(const CubeImage& image);

// 0 where largest <= limit, else the smallest e with largest * 2^-e < limit: for an image, its largest
// magnitude.
int rangeShift(double largest, double limit = kFilterRangeLimit);
int rangeShift(const CubeImage& image);

// Every value times 2^shift (shift may be negative), saturating at +-FLT_MAX.
CubeImage shifted(const CubeImage& image, int shift);
void shiftLevels(CubeLevels& levels, int shift);

} // namespace probe
