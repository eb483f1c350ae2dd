#include "probe/stratified_texels.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace probe {

std::vector<WeightedTexel> allTexels(int size) {
    std::vector<WeightedTexel> out;
    out.reserve(texelCount(size));
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) out.push_back({{f, i, j}, texelSolidAngle(i, j, size)});
    return out;
}

std::vector<WeightedTexel> stratifiedTexels(int size, int budget) {
    if (texelCount(size) <= static_cast<std::size_t>(std::max(budget, 0))) return allTexels(size);
    enum { corner, edge, band, border, interior, strataCount };
    std::array<std::vector<Texel>, strataCount> strata;
    const double texelWidth = 2.0 / size;
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
                const bool edgeI = i == 0 || i == size - 1, edgeJ = j == 0 || j == size - 1;
                const double c = std::max(std::abs(texelCentreUv(i, size)), std::abs(texelCentreUv(j, size)));
                const int s = edgeI && edgeJ                     ? corner
                              : edgeI || edgeJ                   ? edge
                              : std::abs(c - 0.75) <= texelWidth ? band
                              : c > 0.75                         ? border
                                                                 : interior;
                strata[s].push_back({f, i, j});
            }
    // Shares of the budget after the corners: edges, band, border, interior.
    const std::array<double, strataCount> share{0.0, 0.3, 0.3, 0.15, 0.25};
    const int rest = std::max(budget - static_cast<int>(strata[corner].size()), 0);
    std::vector<WeightedTexel> out;
    for (int s = 0; s < strataCount; ++s) {
        const std::size_t n = strata[s].size();
        const std::size_t k = s == corner ? n : std::min(n, static_cast<std::size_t>(share[s] * rest));
        for (std::size_t q = 0; q < k; ++q) {
            const Texel& t =
                strata[s][static_cast<std::size_t>((static_cast<double>(q) + 0.5) * static_cast<double>(n) / static_cast<double>(k))];
            out.push_back({t, texelSolidAngle(t.i, t.j, size) * static_cast<double>(n) / static_cast<double>(k)});
        }
    }
    return out;
}

} // namespace probe
