// The split-sum DFG lookup table (Karis 2013, "Real Shading in Unreal Engine 4"), with Filament's
// height-correlated Smith visibility. Specular lighting under the split-sum approximation is
//   specular = prefiltered(R, roughness) * (F0 * A + B)
// where, over light directions l for view v and normal n, with Schlick's Fresnel
// F = F0 + (1 - F0) (1 - v.h)^5 and V = G / (4 n.l n.v) the visibility:
//   A = integral of D V (1 - (1 - v.h)^5) n.l dl,   B = integral of D V (1 - v.h)^5 n.l dl,
//   V = 0.5 / (n.v sqrt(n.l^2 (1 - a2) + a2) + n.l sqrt(n.v^2 (1 - a2) + a2)),  a2 = alpha^2.
// alpha = perceptual roughness^2, as everywhere in this project. A + B is the directional albedo
// of a white (F0 = 1) GGX surface: at most 1, and 1 at roughness 0.
#pragma once

#include <glm/vec2.hpp>

#include "probe/cube_image.h"

namespace probe {

// The convention of dfgTable in one line, for files that carry the table.
inline constexpr const char* kDfgConvention =
    "split-sum DFG (Karis 2013) with Filament's height-correlated Smith visibility: column i is n.v = (i + 0.5) / size, "
    "row j (row 0 at the top) is perceptual roughness (j + 0.5) / size, alpha = roughness^2; red = A, green = B, blue = 0; "
    "specular = prefiltered * (F0 * A + B)";

// (A, B) for n.v in (0, 1] and perceptual roughness in [0, 1], by `samples` GGX importance
// samples of the half vector (Hammersley points, probe/ggx.h).
glm::dvec2 dfgIntegral(double nDotV, double roughness, int samples);

// The table the tool writes and renders with: 32 x 32 texels of 4096 samples each (within ~2e-3
// of the exact integral; the worst seen is at grazing n.v).
inline constexpr int kDfgTableSize = 32;
inline constexpr int kDfgTableSamples = 4096;

// The table as an image of size x size: column i holds n.v = (i + 0.5) / size, row j holds
// perceptual roughness (j + 0.5) / size (row 0 at the top is the smoothest); red = A (the scale of
// F0), green = B (the bias), blue = 0.
Image dfgTable(int size, int samples);

} // namespace probe
