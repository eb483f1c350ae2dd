// The sheen lookup table of KHR_materials_sheen beside the GGX DFG table (probe/dfg.h): the Charlie
// distribution's two directional integrals a glTF renderer reads, for n.v and the sheen roughness.
//   red   = the IBL scale: sheen lighting is prefiltered_charlie(R, roughness) * sheenColor * red,
//           with red = integral of D V_a n.l dl, V_a = 1 / (4 (n.l + n.v - n.l n.v)) the visibility
//           of Neubelt & Pettineo 2013 (what glTF-IBL-Sampler and Filament's cmgen tabulate);
//   green = E, the directional albedo of the sheen BRDF D V_s with the visibility of Estevez & Kulla
//           2017 that KHR_materials_sheen specifies: the layer below is scaled by
//           1 - max(sheenColor) * E(n.v).
// D is Charlie's (probe/lobe.h) at alpha = lobeAlpha(Lobe::charlie, roughness^2), the alpha its
// prefiltered levels use.
#pragma once

#include <glm/vec2.hpp>

#include "probe/cube_image.h"

namespace probe {

inline constexpr const char* kSheenConvention =
    "KHR_materials_sheen lookup: column i is n.v = (i + 0.5) / size, row j (row 0 at the top) is sheen roughness (j + 0.5) / size, "
    "alpha = max(roughness^2, 0.0049); red = integral of D_charlie V_neubelt n.l (sheen = prefiltered_charlie * sheenColor * red), "
    "green = E, the sheen BRDF's directional albedo with the Estevez-Kulla visibility (base *= 1 - max(sheenColor) * E), blue = 0";

// The visibility V = G / (4 n.l n.v) of Estevez & Kulla 2017 as KHR_materials_sheen gives it (their
// fit of Lambda), for sheen alpha `alpha`; clamped to [0, 1] as the glTF sample viewer does.
double sheenVisibility(double nDotV, double nDotL, double alpha);

// (red, green) of the table for n.v in (0, 1] and sheen roughness in [0, 1], by `samples` half
// vectors spread uniformly over the hemisphere (Hammersley points): Charlie's D is broad and peaks
// at grazing half vectors, where its own importance sampling would put few samples.
glm::dvec2 sheenIntegral(double nDotV, double roughness, int samples);

// The table the tool writes: as the DFG table, 32 x 32 texels of 4096 samples each.
inline constexpr int kSheenTableSize = 32;
inline constexpr int kSheenTableSamples = 4096;

// The table as an image of size x size (layout as kSheenConvention).
Image sheenTable(int size, int samples);

} // namespace probe
