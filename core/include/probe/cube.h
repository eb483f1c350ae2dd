// Cube map addressing: Vulkan face order and orientation, texel centres and exact solid angles.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace probe {

// Faces in Vulkan order: +X, -X, +Y, -Y, +Z, -Z.
inline constexpr int kFaceCount = 6;

// A texel of one cube level: face, column i (along s), row j (along t).
struct Texel {
    int face = 0;
    int i = 0;
    int j = 0;
    // (written out: the public headers compile as C++17)
    bool operator==(const Texel& o) const { return face == o.face && i == o.i && j == o.j; }
    bool operator!=(const Texel& o) const { return !(*this == o); }
};

// Face coordinates (u, v) in [-1, 1] (u = 2s - 1, v = 2t - 1) to the unnormalized direction on
// the unit cube, following the Vulkan cube map face selection table.
glm::dvec3 faceUvToCubePoint(int face, double u, double v);

// Direction (any length, not zero) to its face and face coordinates (u, v) in [-1, 1].
struct FaceUv {
    int face;
    double u;
    double v;
};
// The face a direction points through and its coordinates there, u and v in [-1, 1] (design.md's
// face convention); the direction need not be unit length.
FaceUv directionToFaceUv(const glm::dvec3& direction);

// Texel centre coordinate along one axis of a face of `size` texels: (index + 0.5) / size mapped to [-1, 1].
inline double texelCentreUv(int index, int size) { return 2.0 * (index + 0.5) / size - 1.0; }

// The centre of a texel on the unit cube (an unnormalized direction). Indices may step one texel
// beyond the face, onto its extended plane.
glm::dvec3 texelCubePoint(const Texel& texel, int size);

// Unit direction through the centre of a texel.
glm::dvec3 texelDirection(const Texel& texel, int size);

// The texel whose footprint contains a direction.
Texel directionToTexel(const glm::dvec3& direction, int size);

// Exact solid angle of a texel on the unit cube (all texels of a size sum to 4 pi).
double texelSolidAngle(int i, int j, int size);

// The texel one step (di, dj) in {-1, 0, 1} away, across a face edge where needed, as a seamless
// cube sampler sees it. Returns false only for a step through a cube corner (both coordinates
// leave the face), where no such texel exists.
bool texelNeighbour(const Texel& texel, int di, int dj, int size, Texel& neighbour);

// Linear index of a texel in a face-major, row-major level of `size` texels per face side.
inline std::size_t texelIndex(const Texel& t, int size) { return (static_cast<std::size_t>(t.face) * size + t.j) * size + t.i; }
inline std::size_t texelCount(int size) { return static_cast<std::size_t>(kFaceCount) * size * size; }

// Directions and solid angles of every texel of one level, computed once and shared.
struct CubeGeometry {
    int size = 0;
    std::vector<glm::dvec3> directions; // unit, indexed by texelIndex
    std::vector<double> solidAngles;    // steradians, indexed by texelIndex

    explicit CubeGeometry(int faceSize);
};

} // namespace probe
