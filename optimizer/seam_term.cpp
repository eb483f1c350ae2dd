#include "seam_term.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "probe/cube.h"

namespace probefit {

using namespace probe;

std::vector<SeamPair> prepareSeamPairs(int faceSize, int level, const LevelLobe& lobe, int budget, const MomentBasis& basis) {
    const int size = faceSize >> level;
    // Every unordered pair of edge neighbours once: from the texel with the lower index.
    std::vector<std::pair<Texel, Texel>> edgePairs;
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i)
                for (auto [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                    const Texel t{f, i, j};
                    Texel n;
                    if (texelNeighbour(t, di, dj, size, n) && n.face != f && texelIndex(t, size) < texelIndex(n, size))
                        edgePairs.emplace_back(t, n);
                }
    const std::size_t count = std::min(edgePairs.size(), static_cast<std::size_t>(std::max(budget, 0)));
    std::vector<SeamPair> pairs(count);
    const CubeGeometry geometry(faceSize);
#pragma omp parallel for schedule(dynamic, 2)
    for (std::size_t n = 0; n < count; ++n) {
        const auto& [a, b] = edgePairs[n * edgePairs.size() / count];
        SeamPair& pair = pairs[n];
        pair.a = makeOutputTexel({a, 0.0}, geometry, level, lobe);
        pair.b = makeOutputTexel({b, 0.0}, geometry, level, lobe);
        const std::array<double, kMomentCount> ra = kernelMoments(pair.a, basis), rb = kernelMoments(pair.b, basis);
        for (int j = 0; j < kMomentCount; ++j) pair.referenceStep[j] = ra[j] - rb[j];
        // (a new vector frees the kernel's storage: `= {}` assigns an empty list and keeps it, 25 MiB
        // per texel at 1024^2)
        pair.a.kernel = std::vector<float>();
        pair.b.kernel = std::vector<float>();
    }
    return pairs;
}

double seamError(const ImpulseModel& model, const double* const* blocks, const SeamPair& pair, const MomentBasis& basis, double* gradient,
                 std::vector<double>& scratch) {
    std::array<double, kMomentCount> ma, mb, slope;
    model.moments(blocks, pair.a, basis, ma.data());
    model.moments(blocks, pair.b, basis, mb.data());
    double s = 0.0;
    for (int j = 0; j < kMomentCount; ++j) {
        const double d = (ma[j] - mb[j]) - pair.referenceStep[j];
        s += std::abs(d);
        slope[j] = d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
    }
    if (gradient) {
        const std::size_t p = static_cast<std::size_t>(model.blockCount() * model.blockSize());
        scratch.resize(p);
        model.moments(blocks, pair.a, basis, nullptr, slope.data(), gradient);
        model.moments(blocks, pair.b, basis, nullptr, slope.data(), scratch.data());
        for (std::size_t q = 0; q < p; ++q) gradient[q] -= scratch[q];
    }
    return s;
}

} // namespace probefit
