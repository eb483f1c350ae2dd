// The Lambertian irradiance cube that glTF renderers read beside the GGX levels, from the exact cosine
// convolution, and how far the 9-coefficient SH irradiance (sh.h) is from it.
#pragma once

#include "probe/cube_image.h"

namespace probe {

inline constexpr int kIrradianceCubeSize = 32;    // its face size: irradiance varies slowly
inline constexpr int kIrradianceSourceSize = 128; // a larger source is box-averaged to this first

// E(n) = sum_t L(t) max(n.l_t, 0) dOmega_t / pi at every texel centre of a kIrradianceCubeSize cube
// (exactIrradiance). A source above kIrradianceSourceSize is first averaged to that size over each
// texel's solid angle (a box pyramid), which changes E by less than 1e-3 relative (the cosine lobe
// spans the hemisphere) and bounds the cost at about a second on two cores.
CubeImage irradianceCube(const CubeImage& source);

// An approximation of an irradiance cube against the exact one, per RGB channel over every texel:
// the solid-angle-weighted mean of |a - e| over that of e, and the largest |a - e| / e.
struct IrradianceDifference {
    double relativeL1 = 0.0;
    double maxRelative = 0.0;
};
IrradianceDifference irradianceDifference(const CubeImage& approximation, const CubeImage& exact);

} // namespace probe
