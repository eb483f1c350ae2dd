// Probes the project makes itself, for tests, benchmarks and the demo: no download needed.
#pragma once

#include <string_view>

#include "probe/cube_image.h"

namespace probe {

// Constant radiance everywhere (the white furnace).
CubeImage constantProbe(int faceSize, glm::vec3 radiance);

// One texel of `value` on black.
CubeImage impulseProbe(int faceSize, const Texel& texel, float value = 1.0f);

// Smooth sky: blue gradient above the horizon, warm ground below, no sun.
CubeImage skyProbe(int faceSize);

// The smooth sky with a small sun (radius ~2 degrees) of radiance 1e4.
CubeImage sunSkyProbe(int faceSize);

// A room of big flat colour patches: the talks' worst case for the lobe's tail.
CubeImage roomProbe(int faceSize);

// A checkerboard of 8 x 8 squares per face, 0.05 and 1.
CubeImage checkerProbe(int faceSize);
// The checkerboard pattern: whether texel t lies on a light square, for squares of `square` texels
// shifted by `offset` texels along both face axes; the colours flip from face to face.
inline bool onLightSquare(const Texel& t, int square, int offset = 0) {
    return ((t.i + offset) / square + (t.j + offset) / square + t.face) % 2 != 0;
}

// By name: constant, sky, sunsky, room, checker. Throws ProbeError for an unknown name.
CubeImage syntheticProbe(std::string_view name, int faceSize);

// The same probes as equirectangular images of width x width/2 (the convention of probe_io.h),
// for testing the equirectangular path; checker is a cube-only pattern and is refused.
Image syntheticEquirect(std::string_view name, int width);

} // namespace probe
