#include "probe/irradiance.h"

#include <algorithm>
#include <cmath>

#include "probe/cube.h"
#include "probe/error.h"
#include "probe/pyramid.h"
#include "probe/reference.h"

namespace probe {

CubeImage irradianceCube(const CubeImage& source) {
    if (source.size <= kIrradianceSourceSize) return exactIrradiance(source, kIrradianceCubeSize);
    const CubeLevels pyramid = buildPyramid(source, PyramidSettings{PyramidKind::box, PyramidWeighting::solidAngle});
    const auto reduced =
        std::find_if(pyramid.begin(), pyramid.end(), [](const CubeImage& level) { return level.size <= kIrradianceSourceSize; });
    return exactIrradiance(*reduced, kIrradianceCubeSize);
}

IrradianceDifference irradianceDifference(const CubeImage& approximation, const CubeImage& exact) {
    if (approximation.size != exact.size) throw ProbeError("irradianceDifference: the cubes differ in size");
    const CubeGeometry geometry(exact.size);
    IrradianceDifference d;
    double difference = 0.0, total = 0.0;
    for (std::size_t t = 0; t < geometry.solidAngles.size(); ++t)
        for (std::size_t c = 0; c < 3; ++c) {
            const double e = exact.rgb[3 * t + c], a = approximation.rgb[3 * t + c], error = std::abs(a - e);
            difference += geometry.solidAngles[t] * error;
            total += geometry.solidAngles[t] * std::abs(e);
            if (e > 0.0) d.maxRelative = std::max(d.maxRelative, error / e);
        }
    d.relativeL1 = total > 0.0 ? difference / total : 0.0;
    return d;
}

} // namespace probe
