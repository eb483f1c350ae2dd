#include "tail_check.h"

#include <cmath>
#include <numbers>
#include <tuple>

#include "probe/cube.h"
#include "probe/reference.h"
#include "probe/table_filter.h"

namespace probefit {

using namespace probe;

std::vector<TailLevel> checkTail(const TapTable& table) {
    if (table.lobe != Lobe::ggx) return {};
    const CubeGeometry geometry(table.faceSize);
    const std::vector<DownsampleOperator> operators = pyramidOperators(table.faceSize, table.pyramid);
    std::vector<TailLevel> levels;
    for (int m = 0; m < table.levelCount; ++m) {
        const double alpha = tableLevelAlpha(table, m);
        if (alpha <= 0.0) continue;
        const int size = table.faceSize >> m;
        TailLevel level{m, tailRadius(size), {}};
        const double cosRadius = std::cos(level.radius);
        for (const auto& [where, i, j] : {std::tuple{"face centre", size / 2, size / 2}, {"edge", 0, size / 2}, {"corner", 0, 0}}) {
            const Texel texel{0, i, j};
            const glm::dvec3 R = texelDirection(texel, size);
            const std::vector<double> reference = referenceKernel(R, geometry, tableLevelLobe(table, m));
            const std::vector<double> response = tableImpulseResponse(table, operators, m, texel);
            TailSample sample{where};
            for (std::size_t t = 0; t < reference.size(); ++t)
                if (glm::dot(geometry.directions[t], R) < cosRadius) {
                    sample.referenceMass += reference[t];
                    sample.tableMass += response[t];
                }
            level.samples.push_back(sample);
        }
        levels.push_back(level);
    }
    return levels;
}

} // namespace probefit
