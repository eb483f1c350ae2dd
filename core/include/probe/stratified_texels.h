// Which output texels an error is measured on: all of them, or a stratified subset for fitting
// and quick checks (the corners, edges and frame transition band are where errors hide).
#pragma once

#include <vector>

#include "probe/cube.h"

namespace probe {

// An output texel and its weight in a mean.
struct WeightedTexel {
    Texel texel;
    double weight = 0.0;
};

// Every texel of all six faces of a level, weighted by solid angle.
std::vector<WeightedTexel> allTexels(int size);

// At most `budget` texels of a level in five strata over all six faces: the 24 corner texels, the
// other edge texels, the frame transition band (texel centres within one texel of
// max(|u|, |v|) = 0.75), the border beyond it, and the interior. Each stratum is sampled evenly in
// texel order; a sampled texel weighs its solid angle times (stratum size / samples), so the
// weighted mean estimates the all-texel mean. All texels when the level has no more than `budget`.
// Deterministic.
std::vector<WeightedTexel> stratifiedTexels(int size, int budget);

} // namespace probe
