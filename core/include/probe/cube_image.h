// Plain float RGB images: a 2D image as read from disk and a cube level in texel order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "probe/cube.h"

namespace probe {

// Row-major RGB, row 0 at the top, as image files store it.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<float> rgb; // width * height * 3

    glm::vec3 pixel(int x, int y) const {
        const std::size_t k = (static_cast<std::size_t>(y) * width + x) * 3;
        return {rgb[k], rgb[k + 1], rgb[k + 2]};
    }
};

// One level of a cube map: faces in Vulkan order, each row-major (row j along t, column i along s).
struct CubeImage {
    int size = 0;
    std::vector<float> rgb; // texelCount(size) * 3, indexed by texelIndex

    CubeImage() = default;
    explicit CubeImage(int faceSize, glm::vec3 fill = glm::vec3(0.0f)) : size(faceSize), rgb(texelCount(faceSize) * 3) {
        for (std::size_t t = 0; t < texelCount(size); ++t) set(t, fill);
    }

    glm::vec3 texel(std::size_t index) const { return {rgb[3 * index], rgb[3 * index + 1], rgb[3 * index + 2]}; }
    void set(std::size_t index, glm::vec3 value) {
        rgb[3 * index] = value.r;
        rgb[3 * index + 1] = value.g;
        rgb[3 * index + 2] = value.b;
    }
};

// The filtered probe: level m has face size S_0 >> m.
using CubeLevels = std::vector<CubeImage>;

// A 6S x S horizontal strip of the faces in Vulkan order, as level files store a cube.
Image cubeToStrip(const CubeImage& cube);

// The layouts a probe image may have: equirectangular (2:1); six S x S faces in Vulkan order side by
// side (a strip, 6:1) or one above the other (a column, 1:6); the faces unfolded in a cross,
// horizontal (4:3: -X +Z +X -Z across the middle, +Y above +Z, -Y below) or vertical (3:4: -X +Z +X
// across, +Y above +Z, -Y and -Z below, -Z turned by 180 degrees), as Filament's cmgen reads them.
enum class ProbeLayout { equirectangular, faceStrip, faceColumn, horizontalCross, verticalCross };

// The layout of an image of that shape, if any.
std::optional<ProbeLayout> layoutOfShape(std::int64_t width, std::int64_t height);
// What layoutOfShape accepts, for messages.
inline constexpr const char* kProbeShapes = "2:1 equirectangular, faces in a 6:1 strip or a 1:6 column, or a 4:3 or 3:4 cross";
// Its name in reports.
const char* layoutName(ProbeLayout layout);

} // namespace probe
