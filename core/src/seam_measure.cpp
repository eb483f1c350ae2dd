#include "probe/seam_measure.h"

#include <algorithm>

#include <glm/common.hpp>

#include "probe/cube.h"
#include "probe/reference.h"
#include "probe/synthetic.h"

namespace probe {

namespace {

constexpr double kSeamMargin = 1.1;
constexpr int kCapFaceSize = 64;

} // namespace

SeamSteps steepestSteps(const CubeImage& level) {
    const int s = level.size;
    SeamSteps steps;
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < s; ++j)
            for (int i = 0; i < s; ++i)
                for (auto [di, dj] : {std::pair{1, 0}, {0, 1}}) {
                    Texel n;
                    if (!texelNeighbour({f, i, j}, di, dj, s, n)) continue;
                    const glm::vec3 d = glm::abs(level.texel(texelIndex({f, i, j}, s)) - level.texel(texelIndex(n, s)));
                    const double step = std::max({d.r, d.g, d.b});
                    double& steepest = n.face == f ? steps.interior : steps.edge;
                    steepest = std::max(steepest, step);
                    if (n.face == f && (di ? i : j) == s / 4 - 1) steps.quarterLine = std::max(steps.quarterLine, step);
                }
    return steps;
}

double seamRatio(const CubeImage& level) {
    if (level.size < 4) return 0.0;
    const SeamSteps steps = steepestSteps(level);
    return steps.interior > 0.0 ? steps.edge / steps.interior : 0.0;
}

CubeLevels skyReference(int faceSize, int levelCount, const RoughnessMapping& mapping, Lobe lobe) {
    return referenceFilter(skyProbe(faceSize), levelCount, mapping, {}, lobe);
}

double seamBoundCap(Lobe lobe) {
    double largest = 0.0;
    for (const CubeImage& level : skyReference(kCapFaceSize, defaultLevelCount(kCapFaceSize), RoughnessMapping::gltf, lobe))
        largest = std::max(largest, seamRatio(level));
    return kSeamMargin * largest;
}

std::vector<double> seamBounds(const CubeLevels& reference, double cap) {
    std::vector<double> bounds;
    for (const CubeImage& level : reference) bounds.push_back(level.size >= 4 ? std::min(kSeamMargin * seamRatio(level), cap) : 0.0);
    return bounds;
}

bool withinSeamBound(const CubeImage& level, double bound, const CubeImage* reference) {
    if (bound == 0.0 || seamRatio(level) <= bound) return true;
    if (!reference) return false;
    const SeamSteps steps = steepestSteps(level), exact = steepestSteps(*reference);
    // How much steeper than the reference the level steps inside its faces, where it has no edge.
    const double inside = exact.quarterLine > 0.0 ? std::max(1.0, steps.quarterLine / exact.quarterLine) : 1.0;
    return steps.edge <= kSeamMargin * inside * exact.edge;
}

} // namespace probe
