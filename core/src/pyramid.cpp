#include "probe/pyramid.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/roughness.h"
#include "probe/shared_constants.h"

namespace probe {

PyramidKind parsePyramidKind(std::string_view name) {
    if (name == "bspline") return PyramidKind::bspline;
    if (name == "box") return PyramidKind::box;
    throw ProbeError(fmt::format("unknown pyramid kind '{}' (expected bspline or box)", name));
}

std::string_view pyramidKindName(PyramidKind kind) { return kind == PyramidKind::bspline ? "bspline" : "box"; }

PyramidWeighting parsePyramidWeighting(std::string_view name) {
    if (name == "solid-angle") return PyramidWeighting::solidAngle;
    if (name == "inverse-solid-angle") return PyramidWeighting::inverseSolidAngle;
    throw ProbeError(fmt::format("unknown pyramid weighting '{}' (expected solid-angle or inverse-solid-angle)", name));
}

std::string_view pyramidWeightingName(PyramidWeighting weighting) {
    return weighting == PyramidWeighting::solidAngle ? "solid-angle" : "inverse-solid-angle";
}

void DownsampleOperator::apply(const std::vector<double>& fine, std::vector<double>& coarse) const {
    for (std::size_t r = 0; r + 1 < rowStart.size(); ++r) {
        double sum = 0.0;
        for (std::uint32_t e = rowStart[r]; e < rowStart[r + 1]; ++e) sum += entries[e].weight * fine[entries[e].index];
        coarse[r] = sum;
    }
}

void DownsampleOperator::applyTranspose(const std::vector<double>& coarse, std::vector<double>& fine) const {
    for (std::size_t r = 0; r + 1 < rowStart.size(); ++r) {
        const double c = coarse[r];
        if (c == 0.0) continue;
        for (std::uint32_t e = rowStart[r]; e < rowStart[r + 1]; ++e) fine[entries[e].index] += entries[e].weight * c;
    }
}

namespace {

double jacobianWeight(double u, double v, PyramidWeighting weighting) {
    const double density = std::pow(1.0 + u * u + v * v, -1.5);
    return weighting == PyramidWeighting::solidAngle ? density : 1.0 / density;
}

// Weights on fine texels of one coarse texel, duplicates merged, sorted by index.
std::vector<TexelWeight> bsplineRow(const Texel& coarse, int fineSize, PyramidWeighting weighting) {
    std::vector<TexelWeight> row;
    std::array<double, 4> j{};
    std::array<Footprint, 4> footprints;
    double jSum = 0.0;
    for (int k = 0; k < 4; ++k) {
        const double x = 2.0 * coarse.i + 1.0 + ((k & 1) ? PROBE_PYRAMID_TAP_OFFSET : -PROBE_PYRAMID_TAP_OFFSET);
        const double y = 2.0 * coarse.j + 1.0 + ((k >> 1) ? PROBE_PYRAMID_TAP_OFFSET : -PROBE_PYRAMID_TAP_OFFSET);
        footprints[k] = bilinearFootprint(fineSize, coarse.face, x, y);
        j[k] = jacobianWeight(2.0 * x / fineSize - 1.0, 2.0 * y / fineSize - 1.0, weighting);
        jSum += j[k];
    }
    for (int k = 0; k < 4; ++k) {
        const double tapWeight = PROBE_PYRAMID_JACOBIAN_SHARE * j[k] / jSum + PROBE_PYRAMID_BASE_WEIGHT;
        for (int t = 0; t < footprints[k].count; ++t)
            row.push_back({footprints[k].taps[t].index, footprints[k].taps[t].weight * tapWeight});
    }
    return row;
}

std::vector<TexelWeight> boxRow(const Texel& coarse, int fineSize, PyramidWeighting weighting) {
    std::vector<TexelWeight> row;
    double sum = 0.0;
    for (int k = 0; k < 4; ++k) {
        const Texel child{coarse.face, 2 * coarse.i + (k & 1), 2 * coarse.j + (k >> 1)};
        const double area = texelSolidAngle(child.i, child.j, fineSize);
        const double w = weighting == PyramidWeighting::solidAngle ? area : 1.0 / area;
        row.push_back({static_cast<std::uint32_t>(texelIndex(child, fineSize)), w});
        sum += w;
    }
    for (TexelWeight& e : row) e.weight /= sum;
    return row;
}

} // namespace

DownsampleOperator downsampleOperator(int fineSize, PyramidSettings settings) {
    if (log2Exact(fineSize) < 1) throw ProbeError(fmt::format("pyramid: cannot downsample a face of size {}", fineSize));
    const int coarseSize = fineSize / 2;
    DownsampleOperator op;
    op.fineSize = fineSize;
    op.rowStart.reserve(texelCount(coarseSize) + 1);
    op.rowStart.push_back(0);
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < coarseSize; ++j)
            for (int i = 0; i < coarseSize; ++i) {
                const Texel coarse{f, i, j};
                std::vector<TexelWeight> row = settings.kind == PyramidKind::bspline ? bsplineRow(coarse, fineSize, settings.weighting)
                                                                                     : boxRow(coarse, fineSize, settings.weighting);
                std::sort(row.begin(), row.end(), [](const TexelWeight& a, const TexelWeight& b) { return a.index < b.index; });
                for (const TexelWeight& e : row) {
                    if (op.entries.size() > op.rowStart.back() && op.entries.back().index == e.index) op.entries.back().weight += e.weight;
                    else op.entries.push_back(e);
                }
                op.rowStart.push_back(static_cast<std::uint32_t>(op.entries.size()));
            }
    return op;
}

int pyramidLevelCount(int faceSize) { return maxLevelCount(faceSize); }

std::vector<DownsampleOperator> pyramidOperators(int faceSize, PyramidSettings settings) {
    validateSizeAndLevels(faceSize, 1);
    std::vector<DownsampleOperator> ops;
    for (int size = faceSize; size > 1; size /= 2) ops.push_back(downsampleOperator(size, settings));
    return ops;
}

CubeLevels buildPyramid(const CubeImage& source, const std::vector<DownsampleOperator>& operators) {
    CubeLevels levels{source};
    std::vector<double> fine, coarse;
    for (const DownsampleOperator& op : operators) {
        const CubeImage& previous = levels.back();
        if (op.fineSize != previous.size)
            throw ProbeError(fmt::format("pyramid: operator for size {} applied to size {}", op.fineSize, previous.size));
        CubeImage next(previous.size / 2);
        fine.resize(texelCount(previous.size));
        coarse.resize(texelCount(next.size));
        for (int c = 0; c < 3; ++c) {
            for (std::size_t t = 0; t < fine.size(); ++t) fine[t] = previous.rgb[3 * t + c];
            op.apply(fine, coarse);
            for (std::size_t t = 0; t < coarse.size(); ++t) next.rgb[3 * t + c] = static_cast<float>(coarse[t]);
        }
        levels.push_back(std::move(next));
    }
    return levels;
}

CubeLevels buildPyramid(const CubeImage& source, PyramidSettings settings) {
    return buildPyramid(source, pyramidOperators(source.size, settings));
}

void pushBackToBase(const std::vector<DownsampleOperator>& operators, std::vector<std::vector<double>>& levelWeights, int topLevel) {
    for (int k = topLevel; k > 0; --k) operators[k - 1].applyTranspose(levelWeights[k], levelWeights[k - 1]);
}

void pullUpFromBase(const std::vector<DownsampleOperator>& operators, std::vector<std::vector<double>>& levels, int topLevel) {
    for (int k = 1; k <= topLevel; ++k) operators[k - 1].apply(levels[k - 1], levels[k]);
}

} // namespace probe
