#include "probe/cube_footprint.h"

namespace probe {

glm::dvec3 sampleBilinear(const CubeImage& level, const glm::dvec3& direction) {
    const Footprint f = bilinearFootprint(level.size, toArray(direction));
    glm::dvec3 sum(0.0);
    for (int k = 0; k < f.count; ++k) sum += f.taps[k].weight * glm::dvec3(level.texel(f.taps[k].index));
    return sum;
}

glm::dvec3 sampleTrilinear(const CubeLevels& pyramid, const glm::dvec3& direction, double level) {
    const TrilinearFootprint f = trilinearFootprint(pyramid[0].size, static_cast<int>(pyramid.size()), toArray(direction), level);
    glm::dvec3 sum(0.0);
    for (int k = 0; k < f.count; ++k) sum += f.taps[k].weight * glm::dvec3(pyramid[f.taps[k].level].texel(f.taps[k].index));
    return sum;
}

} // namespace probe
