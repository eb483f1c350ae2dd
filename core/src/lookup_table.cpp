#include "probe/lookup_table.h"

namespace probe {

Image lookupTable(int size, const std::function<glm::dvec2(double nDotV, double roughness)>& terms) {
    Image table{size, size, std::vector<float>(static_cast<std::size_t>(size) * size * 3, 0.0f)};
#pragma omp parallel for schedule(dynamic)
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const glm::dvec2 t = terms((i + 0.5) / size, (j + 0.5) / size);
            float* p = &table.rgb[(static_cast<std::size_t>(j) * size + i) * 3];
            p[0] = static_cast<float>(t.x);
            p[1] = static_cast<float>(t.y);
        }
    return table;
}

} // namespace probe
