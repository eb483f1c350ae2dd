#include "probe/cube.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace probe {

glm::dvec3 faceUvToCubePoint(int face, double u, double v) {
    switch (face) {
    case 0: return {1.0, -v, -u};
    case 1: return {-1.0, -v, u};
    case 2: return {u, 1.0, v};
    case 3: return {u, -1.0, -v};
    case 4: return {u, -v, 1.0};
    default: return {-u, -v, -1.0};
    }
}

FaceUv directionToFaceUv(const glm::dvec3& d) {
    const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    // Ties go to X, then Y, so that every direction has exactly one face.
    if (ax >= ay && ax >= az) return d.x >= 0 ? FaceUv{0, -d.z / ax, -d.y / ax} : FaceUv{1, d.z / ax, -d.y / ax};
    if (ay >= az) return d.y >= 0 ? FaceUv{2, d.x / ay, d.z / ay} : FaceUv{3, d.x / ay, -d.z / ay};
    return d.z >= 0 ? FaceUv{4, d.x / az, -d.y / az} : FaceUv{5, -d.x / az, -d.y / az};
}

glm::dvec3 texelCubePoint(const Texel& t, int size) {
    return faceUvToCubePoint(t.face, texelCentreUv(t.i, size), texelCentreUv(t.j, size));
}

glm::dvec3 texelDirection(const Texel& t, int size) { return glm::normalize(texelCubePoint(t, size)); }

static int uvToIndex(double uv, int size) {
    const int index = static_cast<int>(std::floor((uv + 1.0) * 0.5 * size));
    return std::clamp(index, 0, size - 1);
}

Texel directionToTexel(const glm::dvec3& direction, int size) {
    const FaceUv f = directionToFaceUv(direction);
    return {f.face, uvToIndex(f.u, size), uvToIndex(f.v, size)};
}

// Solid angle of the face region [-1, x] x [-1, y] up to a constant: the standard area element
// integral on the unit cube.
static double areaElement(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0)); }

double texelSolidAngle(int i, int j, int size) {
    const double x0 = 2.0 * i / size - 1.0, x1 = 2.0 * (i + 1) / size - 1.0;
    const double y0 = 2.0 * j / size - 1.0, y1 = 2.0 * (j + 1) / size - 1.0;
    return areaElement(x0, y0) - areaElement(x0, y1) - areaElement(x1, y0) + areaElement(x1, y1);
}

bool texelNeighbour(const Texel& t, int di, int dj, int size, Texel& neighbour) {
    const int i = t.i + di, j = t.j + dj;
    const bool insideI = i >= 0 && i < size, insideJ = j >= 0 && j < size;
    if (insideI && insideJ) {
        neighbour = {t.face, i, j};
        return true;
    }
    if (!insideI && !insideJ) return false;
    // The texel centre beyond the edge, on the face's extended plane, projects into the first
    // texel row of the adjacent face at the same place along the edge.
    neighbour = directionToTexel(texelCubePoint({t.face, i, j}, size), size);
    return true;
}

CubeGeometry::CubeGeometry(int faceSize) : size(faceSize) {
    directions.resize(texelCount(size));
    solidAngles.resize(texelCount(size));
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
                const Texel t{f, i, j};
                directions[texelIndex(t, size)] = texelDirection(t, size);
                solidAngles[texelIndex(t, size)] = texelSolidAngle(i, j, size);
            }
}

} // namespace probe
