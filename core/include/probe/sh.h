// Order-2 spherical harmonics irradiance (Ramamoorthi & Hanrahan 2001).
//
// Real SH basis, no Condon-Shortley phase, coefficient order and signs (unit direction x, y, z):
//   0: Y00  = 0.282095              1: Y1-1 = 0.488603 y
//   2: Y10  = 0.488603 z            3: Y11  = 0.488603 x
//   4: Y2-2 = 1.092548 x y          5: Y2-1 = 1.092548 y z
//   6: Y20  = 0.315392 (3 z^2 - 1)  7: Y21  = 1.092548 x z
//   8: Y22  = 0.546274 (x^2 - y^2)
// Radiance coefficients are L_lm = sum_t L(t) Y_lm(l_t) dOmega_t; irradiance coefficients are
// A_l L_lm / pi with A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4, so a constant radiance L gives E = L.
#pragma once

#include <array>

#include <glm/vec3.hpp>

#include "probe/cube_image.h"

namespace probe {

inline constexpr int kShCount = 9;

// The convention above in one line, for files that carry coefficients.
inline constexpr const char* kShConvention =
    "order-2 real SH, no Condon-Shortley phase, unit direction (x, y, z) in the cube's frame (Vulkan faces; "
    "+Y up in equirectangular input); coefficient k, RGB each: 0 Y00 = 0.282095, 1 Y1-1 = 0.488603 y, "
    "2 Y10 = 0.488603 z, 3 Y11 = 0.488603 x, 4 Y2-2 = 1.092548 x y, 5 Y2-1 = 1.092548 y z, "
    "6 Y20 = 0.315392 (3 z^2 - 1), 7 Y21 = 1.092548 x z, 8 Y22 = 0.546274 (x^2 - y^2); "
    "radiance L_k = sum_t L(t) Y_k(l_t) dOmega_t; irradiance E_k = A_l L_k / pi with A_0 = pi, A_1 = 2 pi / 3, "
    "A_2 = pi / 4; E(n) = sum_k E_k Y_k(n), so a constant radiance L gives E = L";
using ShCoefficients = std::array<glm::dvec3, kShCount>; // RGB per coefficient

// The nine basis functions Y_k at a unit direction, in the order of kShConvention.
std::array<double, kShCount> shBasis(const glm::dvec3& unitDirection);

// Projects the radiance of a cube level onto the basis (double precision).
ShCoefficients projectRadiance(const CubeImage& radiance);

// Convolves radiance coefficients with the clamped cosine and divides by pi.
ShCoefficients radianceToIrradiance(const ShCoefficients& radiance);

glm::dvec3 evaluateSh(const ShCoefficients& coefficients, const glm::dvec3& unitDirection);

// The irradiance of SH coefficients at every texel centre of a level of `size`, clamped to
// [0, FLT_MAX] (order 2 rings below zero opposite a bright light).
CubeImage shToCube(const ShCoefficients& irradiance, int size);

} // namespace probe
