// Pass 2's common core, shared by the table filter and filtered importance sampling: an output
// texel is a normalized weighted sum of trilinear taps into the pyramid. Value form (filter a
// probe) and impulse-response form (weights over base texels, for the error measures and the fit).
#pragma once

#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "probe/cube_image.h"
#include "probe/pyramid.h"

namespace probe {

// A trilinear read of the pyramid: direction (any length), absolute level (the sampler clamps it
// to the pyramid), weight (any sign).
struct Tap {
    glm::dvec3 direction{0.0};
    double level = 0.0;
    double weight = 0.0;
};

// sum_i w_i trilinear(pyramid, d_i, level_i) / sum_i w_i, clamped to >= 0; black when the weights sum to 0.
glm::vec3 sumTaps(const CubeLevels& pyramid, const std::vector<Tap>& taps);

// The same sum as a linear map: weights over base texels (texelIndex at faceSize), normalized by
// sum_i w_i, pushed back through the transposed downsampling operators. No clamp.
std::vector<double> tapImpulseResponse(const std::vector<DownsampleOperator>& operators, int faceSize, const std::vector<Tap>& taps);

// The taps of one output texel of output level m (face size S_0 >> m); returns false where that
// level is a copy of the source (alpha = 0).
using TapGenerator = std::function<bool(int level, const Texel& texel, std::vector<Tap>& taps)>;

// Every output level m = 0..levelCount-1 of a probe, all cores. `pyramid` is the source's pyramid.
CubeLevels filterWithTaps(const CubeLevels& pyramid, int levelCount, const TapGenerator& generator);

// The impulse response of one output texel: weights over base texels (sum 1 unless the taps'
// weights cancel); a copy level puts weight 1 on the base texel containing the texel's centre.
std::vector<double> impulseWithTaps(const std::vector<DownsampleOperator>& operators, int faceSize, int level, const Texel& texel,
                                    const TapGenerator& generator);

} // namespace probe
