// The impulse-response L1 of docs/design.md for any method given as taps (a table or FIS): e(R) of its
// normalized weights over base texels against the reference kernel, over a set of output texels.
#pragma once

#include <functional>
#include <vector>

#include "probe/error_measures.h"
#include "probe/lobe.h"
#include "probe/roughness.h"
#include "probe/stratified_texels.h"
#include "probe/tap_sum.h"

namespace probe {

// Mean (weighted as the texel set says) and worst e(R) over `texels` of output level m, against the
// lobe's reference; all cores. A copy level (GGX alpha = 0) is compared with the reference's copy.
ImpulseError impulseError(const TapGenerator& generator, const std::vector<DownsampleOperator>& operators, int faceSize, int levelCount,
                          const RoughnessMapping& mapping, Lobe lobe, int level, const std::vector<WeightedTexel>& texels);

// The same for a method given by its impulse response (weights over base texels) at an output texel
// of level m; `response` runs on every core at once.
using ImpulseResponse = std::function<std::vector<double>(const Texel& texel)>;
ImpulseError impulseError(const ImpulseResponse& response, int faceSize, int levelCount, const RoughnessMapping& mapping, Lobe lobe,
                          int level, const std::vector<WeightedTexel>& texels);

} // namespace probe
