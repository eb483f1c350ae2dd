// The layout the split-sum lookup tables share (the GGX DFG table, the sheen table): a square image
// over (n.v, roughness) holding two terms.
#pragma once

#include <functional>

#include <glm/vec2.hpp>

#include "probe/cube_image.h"

namespace probe {

// size x size texels: column i holds n.v = (i + 0.5) / size, row j (row 0 at the top) roughness
// (j + 0.5) / size; red and green the two terms at them, blue 0. All cores.
Image lookupTable(int size, const std::function<glm::dvec2(double nDotV, double roughness)>& terms);

} // namespace probe
