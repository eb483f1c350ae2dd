// Cube addressing: solid angles, direction <-> texel round trips, neighbours across face edges.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "probe/cube.h"

using namespace probe;

TEST(Cube, SolidAnglesSumToFourPi) {
    for (int size = 1; size <= 512; ++size) {
        double sum = 0.0;
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) sum += texelSolidAngle(i, j, size);
        EXPECT_NEAR(6.0 * sum, 4.0 * std::numbers::pi, 4.0 * std::numbers::pi * 1e-6) << "size " << size;
    }
}

TEST(Cube, SolidAngleMatchesQuadrature) {
    // The exact formula against a fine midpoint quadrature of (1 + u^2 + v^2)^(-3/2) du dv.
    const int size = 8, n = 400;
    for (auto [i, j] : {std::pair{0, 0}, {3, 4}, {7, 0}}) {
        double sum = 0.0;
        const double h = 2.0 / size / n;
        for (int b = 0; b < n; ++b)
            for (int a = 0; a < n; ++a) {
                const double u = -1.0 + i * 2.0 / size + (a + 0.5) * h, v = -1.0 + j * 2.0 / size + (b + 0.5) * h;
                sum += h * h * std::pow(1.0 + u * u + v * v, -1.5);
            }
        EXPECT_NEAR(texelSolidAngle(i, j, size), sum, 1e-6 * sum);
    }
}

TEST(Cube, VulkanFaceSelectionTable) {
    // The major axis picks the face; (s, t) follow the Vulkan spec's sc/tc table.
    struct Case {
        glm::dvec3 d;
        int face;
        double u, v;
    };
    const Case cases[] = {
        {{1, 0.5, 0.25}, 0, -0.25, -0.5}, {{-1, 0.5, 0.25}, 1, 0.25, -0.5}, {{0.5, 1, 0.25}, 2, 0.5, 0.25},
        {{0.5, -1, 0.25}, 3, 0.5, -0.25}, {{0.5, 0.25, 1}, 4, 0.5, -0.25},  {{0.5, 0.25, -1}, 5, -0.5, -0.25},
    };
    for (const Case& c : cases) {
        const FaceUv f = directionToFaceUv(c.d * 3.0);
        EXPECT_EQ(f.face, c.face);
        EXPECT_DOUBLE_EQ(f.u, c.u);
        EXPECT_DOUBLE_EQ(f.v, c.v);
        const glm::dvec3 p = faceUvToCubePoint(c.face, c.u, c.v);
        EXPECT_NEAR(glm::length(glm::normalize(p) - glm::normalize(c.d)), 0.0, 1e-15);
    }
}

TEST(Cube, DirectionTexelRoundTrip) {
    for (int size : {1, 2, 3, 16, 64}) {
        for (int f = 0; f < kFaceCount; ++f)
            for (int j = 0; j < size; ++j)
                for (int i = 0; i < size; ++i) {
                    const Texel t{f, i, j};
                    const glm::dvec3 d = texelDirection(t, size);
                    EXPECT_NEAR(glm::length(d), 1.0, 1e-14);
                    EXPECT_EQ(directionToTexel(d, size), t);
                }
    }
}

TEST(Cube, EveryTexelHasFourNeighboursAcrossEdges) {
    for (int size : {1, 2, 4, 16}) {
        const CubeGeometry geometry(size);
        for (int f = 0; f < kFaceCount; ++f)
            for (int j = 0; j < size; ++j)
                for (int i = 0; i < size; ++i) {
                    const Texel t{f, i, j};
                    const glm::dvec3 d = texelDirection(t, size);
                    for (auto [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                        Texel n;
                        ASSERT_TRUE(texelNeighbour(t, di, dj, size, n));
                        EXPECT_FALSE(n == t);
                        // Neighbourhood is symmetric: n has t among its four neighbours.
                        bool back = false;
                        for (auto [ei, ej] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                            Texel m;
                            ASSERT_TRUE(texelNeighbour(n, ei, ej, size, m));
                            back |= m == t;
                        }
                        EXPECT_TRUE(back) << "face " << f << " (" << i << ", " << j << ") step " << di << "," << dj;
                        // And it is adjacent on the sphere: one texel apart, not across the cube.
                        const double angle = std::acos(std::clamp(glm::dot(d, texelDirection(n, size)), -1.0, 1.0));
                        EXPECT_LE(angle, 2.0 * std::atan(1.0 / size) + 1e-12);
                    }
                    Texel corner;
                    const bool atCorner = (i == 0 || i == size - 1) && (j == 0 || j == size - 1);
                    const int di = i == 0 ? -1 : 1, dj = j == 0 ? -1 : 1;
                    EXPECT_EQ(texelNeighbour(t, di, dj, size, corner), !atCorner);
                }
    }
}

TEST(Cube, NeighbourAcrossPlusXRightEdgeIsOnMinusZ) {
    // +X face: u = -z, so its right edge (u = 1) is z = -1, the -Z face, whose left edge is x = +1.
    const int size = 4;
    Texel n;
    ASSERT_TRUE(texelNeighbour({0, size - 1, 1}, 1, 0, size, n));
    EXPECT_EQ(n.face, 5);
    EXPECT_EQ(n.i, 0);
    EXPECT_EQ(n.j, 1);
}
