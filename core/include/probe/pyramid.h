// Pass 1: the mip pyramid of the source cube, levels 0 (the source, S_0) down to 1x1, and the
// linear operator of each downsampling step as sparse rows, so that weights on pyramid texels can
// be pushed back to base texels (the transpose) and images pulled up (the operator itself).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "probe/cube_footprint.h"
#include "probe/cube_image.h"

namespace probe {

// bspline: the Jacobian-weighted quadratic B-spline of docs/design.md (four seamless bilinear taps at
// +-0.75 fine texels, tap i weighing 0.5 J_i / sum(J) + 0.125).
// box: each coarse texel averages its 2x2 children on the same face, child i weighing J_i / sum(J)
// with J_i the child's exact solid angle (or its inverse).
enum class PyramidKind { bspline, box };

// J = (1 + u^2 + v^2)^(-3/2) at the tap (the solid angle density), or its inverse.
enum class PyramidWeighting { solidAngle, inverseSolidAngle };

struct PyramidSettings {
    PyramidKind kind = PyramidKind::bspline;
    PyramidWeighting weighting = PyramidWeighting::solidAngle;
    bool operator==(const PyramidSettings& o) const { return kind == o.kind && weighting == o.weighting; }
    bool operator!=(const PyramidSettings& o) const { return !(*this == o); }
};

// "bspline" / "box" and "solid-angle" / "inverse-solid-angle"; parsing throws ProbeError naming the value.
PyramidKind parsePyramidKind(std::string_view name);
std::string_view pyramidKindName(PyramidKind kind);
PyramidWeighting parsePyramidWeighting(std::string_view name);
std::string_view pyramidWeightingName(PyramidWeighting weighting);

// One downsampling step from a level of face size `fineSize` to fineSize / 2: row r (a coarse
// texel index) holds weights on fine texels in entries[rowStart[r], rowStart[r + 1]). Every row sums to 1.
struct DownsampleOperator {
    int fineSize = 0;
    std::vector<std::uint32_t> rowStart;
    std::vector<TexelWeight> entries;

    // coarse = D fine (one scalar per texel).
    void apply(const std::vector<double>& fine, std::vector<double>& coarse) const;
    // fine += D^T coarse.
    void applyTranspose(const std::vector<double>& coarse, std::vector<double>& fine) const;
};

// The operator that builds the level of face size fineSize / 2 from a level of face size fineSize.
DownsampleOperator downsampleOperator(int fineSize, PyramidSettings settings);

// The operators of every step of a pyramid over a base of `faceSize`: element k maps level k to k + 1.
std::vector<DownsampleOperator> pyramidOperators(int faceSize, PyramidSettings settings);

// Number of pyramid levels for a face size: log2(S) + 1 (down to 1x1).
int pyramidLevelCount(int faceSize);

// The pyramid of an RGB cube: element 0 is the source, the last is 1x1.
CubeLevels buildPyramid(const CubeImage& source, const std::vector<DownsampleOperator>& operators);
CubeLevels buildPyramid(const CubeImage& source, PyramidSettings settings);

// Weights on the texels of every pyramid level (element k has texelCount(faceSize >> k) entries)
// pushed back to base texels through the transposed operators, coarsest first; the result is in
// element 0 and the coarser elements are left modified. Levels above `topLevel` must be zero.
void pushBackToBase(const std::vector<DownsampleOperator>& operators, std::vector<std::vector<double>>& levelWeights, int topLevel);

// The scalar pyramid of a base image up to `topLevel` (element 0 is the image itself); the
// adjoint of pushBackToBase: d(sum_t g_t w_t) / d(weight on pyramid texel p) = levels[k][p].
void pullUpFromBase(const std::vector<DownsampleOperator>& operators, std::vector<std::vector<double>>& levels, int topLevel);

} // namespace probe
