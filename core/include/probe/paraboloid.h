// Filtered importance sampling from a dual-paraboloid map, as Krivanek & Colbert (2008) publish it:
// the source is resampled into two paraboloid images (front: z >= 0, back: z < 0) with box-filtered
// mip chains, and each GGX sample reads the image of its hemisphere at the mip whose texels cover the
// sample's solid angle, the texel's solid angle taken from the Jacobian of the paraboloid mapping at
// the sample. The samples are FIS's (fisSamples); only the map they read differs from the
// cube pyramid.
//
// Mapping: d (unit) in the front image is (u, v) = (d.x, d.y) / (1 + d.z), in the back image
// (d.x, d.y) / (1 - d.z); the hemisphere is the disc u^2 + v^2 <= 1 and dOmega = 4 / (1 + u^2 + v^2)^2
// du dv. The image square [-1, 1]^2 holds (u, v) * PROBE_PARABOLOID_SCALE, so the disc ends inside the
// square: the texels beyond it hold the directions past the seam (the other hemisphere), and a
// bilinear read or a mip near the seam filters across it instead of into black.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "probe/cube.h"
#include "probe/cube_footprint.h"
#include "probe/cube_image.h"
#include "probe/fis.h"
#include "probe/roughness.h"
#include "probe/shared_constants.h"

namespace probe {

// Face size of each paraboloid image for a cube of face size S_0: 2 S_0, so that the texels at the
// image centre cover about the solid angle of the cube's texels at a face centre.
inline int paraboloidSize(int faceSize) { return 2 * faceSize; }

// Level k of the map: the front image then the back image, each (size >> k)^2 texels, row-major
// (row j along v, column i along u).
struct ParaboloidMap {
    int size = 0;                               // level 0's image size
    std::vector<std::vector<glm::vec3>> levels; // log2(size) + 1 levels, down to 1x1

    int levelCount() const { return static_cast<int>(levels.size()); }
};

// A position in the map: image 0 (front) or 1 (back) and continuous texel coordinates x, y in
// [0, size] of a level of `size` (texel centres at i + 0.5).
struct ParaboloidPoint {
    int image = 0;
    double x = 0.0, y = 0.0;
};
ParaboloidPoint paraboloidPoint(const glm::dvec3& direction, int size);  // any length, not zero
glm::dvec3 paraboloidDirection(int image, double x, double y, int size); // unit; past the disc: the other hemisphere

// Solid angle of one texel of level 0 (image size `size`) at a direction: the mapping's Jacobian
// times the texel's area in (u, v).
double paraboloidTexelSolidAngle(const glm::dvec3& direction, int size);

// Level 0: the source read bilinearly (seamless cube sampling) at each texel centre's direction;
// level k: the 2x2 box average of level k - 1.
ParaboloidMap buildParaboloidMap(const CubeImage& source);

// The map's level for a FIS sample (fisSamples, rotated to world space) of `cubeLevel`, the
// level FIS gives it in a cube pyramid of face size `faceSize`: the same sample solid angle over the
// map's texel solid angle at the sample instead of the cube's average texel.
double paraboloidLevel(const glm::dvec3& direction, double cubeLevel, int faceSize);

// Trilinear value of the map at a direction and a fractional level (clamped to the chain):
// bilinear in each image with clamp-to-edge addressing.
glm::dvec3 sampleParaboloid(const ParaboloidMap& map, const glm::dvec3& direction, double level);

// Filters a probe: FIS's samples (settings.samples or per level, settings.bias) read from the
// paraboloid map of the source. Levels with alpha = 0 are copies of the source.
CubeLevels paraboloidFilter(const CubeImage& source, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings);

// The impulse response of one output texel of level m (alpha > 0) over base texels (texelIndex at
// faceSize): the normalized sample weights pushed back through the map's mips and the bilinear
// resampling of the source.
class ParaboloidImpulse {
public:
    ParaboloidImpulse(int faceSize, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings);
    std::vector<double> response(int level, const Texel& texel) const;

private:
    int faceSize_, levelCount_;
    RoughnessMapping mapping_;
    std::vector<std::vector<Tap>> samples_; // per output level, in the tangent frame
    std::vector<Footprint> source_;         // per level-0 map texel, its bilinear source texels
};

} // namespace probe
