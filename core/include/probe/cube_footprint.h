// Seamless bilinear and trilinear sampling of cube levels, as a Vulkan cube sampler with seamless
// filtering does it, written as weights on texels so that the same code gives values (filtering),
// impulse responses (fitting, error measures) and derivatives (T = ceres::Jet in the optimizer).
//
// Conventions: a level of face size S has continuous texel coordinates x, y in [0, S] with texel
// centres at i + 0.5; from a direction, x = (u + 1) / 2 * S with (face, u, v) from
// directionToFaceUv. A footprint texel beyond one face edge is read from the adjacent face
// (texelNeighbour). At a cube corner, where one of the four texels does not exist, the Vulkan rule
// applies: the missing texel is the average of the other three, so its weight goes 1/3 to each.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "probe/cube.h"
#include "probe/cube_image.h"

namespace probe {

// The value of a scalar: itself for arithmetic types, the `.a` member for autodiff types such as
// ceres::Jet. Discrete decisions (face, texel, level) are taken on it, so derivatives flow only
// through the continuous weights.
template <typename T>
inline double scalarValue(const T& x) {
    if constexpr (std::is_arithmetic_v<T>) return static_cast<double>(x);
    else return x.a;
}

// One texel of a level (index = texelIndex in that level) and its weight.
template <typename T>
struct TexelWeightT {
    std::uint32_t index = 0;
    T weight{};
};
using TexelWeight = TexelWeightT<double>;

// A bilinear footprint: at most 4 texels, weights >= 0 summing to 1.
template <typename T>
struct FootprintT {
    std::array<TexelWeightT<T>, 4> taps{};
    int count = 0;
};
using Footprint = FootprintT<double>;

// Bilinear footprint at continuous texel coordinates (x, y) of `face` in a level of `size`;
// x and y are clamped to [0, size].
template <typename T>
FootprintT<T> bilinearFootprint(int size, int face, T x, T y) {
    if (scalarValue(x) < 0.0) x = T(0.0);
    if (scalarValue(x) > size) x = T(double(size));
    if (scalarValue(y) < 0.0) y = T(0.0);
    if (scalarValue(y) > size) y = T(double(size));
    const int i0 = static_cast<int>(std::floor(scalarValue(x) - 0.5));
    const int j0 = static_cast<int>(std::floor(scalarValue(y) - 0.5));
    const T fx = x - T(i0 + 0.5), fy = y - T(j0 + 0.5);
    const std::array<T, 4> w{(T(1.0) - fx) * (T(1.0) - fy), fx * (T(1.0) - fy), (T(1.0) - fx) * fy, fx * fy};

    FootprintT<T> out;
    int missing = -1;
    for (int k = 0; k < 4; ++k) {
        const int i = i0 + (k & 1), j = j0 + (k >> 1);
        const int ci = std::clamp(i, 0, size - 1), cj = std::clamp(j, 0, size - 1);
        Texel texel;
        if (!texelNeighbour(Texel{face, ci, cj}, i - ci, j - cj, size, texel)) {
            missing = k;
            continue;
        }
        out.taps[out.count++] = {static_cast<std::uint32_t>(texelIndex(texel, size)), w[k]};
    }
    if (missing >= 0)
        for (int k = 0; k < out.count; ++k) out.taps[k].weight += w[missing] * T(1.0 / 3.0);
    return out;
}

// Face coordinates of a direction on a given face: u = U.d / N.d, v = V.d / N.d with N the face
// centre and U, V its axes, all taken from faceUvToCubePoint so the face table exists only once.
template <typename T>
inline void faceCoordinates(int face, const std::array<T, 3>& d, T& u, T& v) {
    const glm::dvec3 n = faceUvToCubePoint(face, 0.0, 0.0);
    const glm::dvec3 du = faceUvToCubePoint(face, 1.0, 0.0) - n, dv = faceUvToCubePoint(face, 0.0, 1.0) - n;
    const T depth = T(n.x) * d[0] + T(n.y) * d[1] + T(n.z) * d[2];
    u = (T(du.x) * d[0] + T(du.y) * d[1] + T(du.z) * d[2]) / depth;
    v = (T(dv.x) * d[0] + T(dv.y) * d[1] + T(dv.z) * d[2]) / depth;
}

// Bilinear footprint at a direction (any length, not zero) in a level of `size`.
template <typename T>
FootprintT<T> bilinearFootprint(int size, const std::array<T, 3>& direction) {
    const int face = directionToFaceUv({scalarValue(direction[0]), scalarValue(direction[1]), scalarValue(direction[2])}).face;
    T u, v;
    faceCoordinates(face, direction, u, v);
    const T half(0.5 * size);
    return bilinearFootprint(size, face, (u + T(1.0)) * half, (v + T(1.0)) * half);
}

// A texel of a pyramid level and its weight.
template <typename T>
struct PyramidWeightT {
    int level = 0;
    std::uint32_t index = 0;
    T weight{};
};
using PyramidWeight = PyramidWeightT<double>;

// A trilinear footprint: the bilinear footprints of levels floor(level) and floor(level) + 1.
template <typename T>
struct TrilinearFootprintT {
    std::array<PyramidWeightT<T>, 8> taps{};
    int count = 0;
};
using TrilinearFootprint = TrilinearFootprintT<double>;

// Trilinear footprint in a pyramid of `levelCount` levels (level k has face size faceSize >> k):
// the level is clamped to [0, levelCount - 1] and the floor and ceiling levels are lerped.
template <typename T>
TrilinearFootprintT<T> trilinearFootprint(int faceSize, int levelCount, const std::array<T, 3>& direction, T level) {
    if (scalarValue(level) < 0.0) level = T(0.0);
    if (scalarValue(level) > levelCount - 1) level = T(double(levelCount - 1));
    const int lower = static_cast<int>(std::floor(scalarValue(level)));
    const T upperWeight = level - T(double(lower));
    TrilinearFootprintT<T> out;
    auto add = [&](int k, const T& levelWeight) {
        const FootprintT<T> f = bilinearFootprint(faceSize >> k, direction);
        for (int t = 0; t < f.count; ++t) out.taps[out.count++] = {k, f.taps[t].index, f.taps[t].weight * levelWeight};
    };
    add(lower, T(1.0) - upperWeight);
    if (lower + 1 < levelCount && scalarValue(upperWeight) > 0.0) add(lower + 1, upperWeight);
    return out;
}

inline std::array<double, 3> toArray(const glm::dvec3& d) { return {d.x, d.y, d.z}; }

// Bilinear value of a cube level at a direction.
glm::dvec3 sampleBilinear(const CubeImage& level, const glm::dvec3& direction);

// Trilinear value of a pyramid (level k of face size pyramid[0].size >> k) at a direction and a
// fractional level, clamped to [0, levels - 1].
glm::dvec3 sampleTrilinear(const CubeLevels& pyramid, const glm::dvec3& direction, double level);

} // namespace probe
