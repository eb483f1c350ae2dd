// The fit's fast objective measures an output texel's impulse-response L1 over cells instead of
// every base texel: base texels near the output direction R, where the lobe is sharp and the taps
// read fine pyramid levels, and ever larger squares of them (texels of coarser pyramid levels)
// further away, where the lobe and the response are smooth. The response's mass in a cell is the
// weight its taps put there, pushed down the pyramid only as far as the cell's level; so the cost
// of a texel grows with the number of cells (about the logarithm of the base size), not with the
// base size. `probefit eval` (every base texel) stays the judge; the test
// `LobeCells.FastObjectiveIsCloseToTheExactL1` bounds the difference.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

namespace probefit {

// A cell is one texel of pyramid level `level` (face size baseSize >> level): the base texels it
// covers. kernel: the reference's normalized mass there; tail: whether it lies beyond the tail
// radius (tail_check.h).
struct LobeCell {
    std::uint32_t index = 0;
    std::uint8_t level = 0;
    bool tail = false;
    float kernel = 0.0f;
};

// A cell is measured whole where its nearest point lies at least this many of its angular radii
// from R (closer, it splits into its four children; base texels always stand alone).
inline constexpr double kCellDistance = 3.0;
// ... and where the lobe varies across it (max - min of the density at its centre and corners) by
// less than this share of its largest value there, or by less than kCellVariation of the lobe's
// whole mass times the cell's solid angle: so a lobe that is sharp away from R (a ring) is resolved
// there too.
inline constexpr double kCellRelativeVariation = 0.5;
inline constexpr double kCellVariation = 1e-4;

// The reference's density K(R, l) (unnormalized) of a lobe about the output direction R.
using LobeDensity = std::function<double(const glm::dvec3& l)>;

struct LobeCells {
    std::vector<LobeCell> cells; // a partition of the base texels
    double kernelTail = 0.0;     // the reference's mass in the tail cells
};

// The cells of output direction R (unit) over a base of `baseSize`; tailRadius in radians (<= 0: no
// tail). The kernel of a cell is the density summed over its base texels (cells of up to 4x4 base
// texels) or over its 4x4 sub-texels (larger cells, where the lobe is smooth), times their exact
// solid angles, normalized to sum 1 over all cells.
LobeCells lobeCells(const glm::dvec3& R, int baseSize, const LobeDensity& density, double tailRadius);

// The GGX reference lobe of probe/reference.h at roughness alpha.
LobeDensity ggxLobe(const glm::dvec3& R, double alpha);

} // namespace probefit
