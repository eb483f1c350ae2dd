#include "probe/synthetic.h"

#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "probe/error.h"

namespace probe {

namespace {

template <typename RadianceOf>
CubeImage fromDirections(int faceSize, RadianceOf radianceOf) {
    CubeImage cube(faceSize);
    const CubeGeometry geometry(faceSize);
    for (std::size_t t = 0; t < texelCount(faceSize); ++t) cube.set(t, radianceOf(geometry.directions[t]));
    return cube;
}

glm::vec3 sky(const glm::dvec3& d) {
    const float up = static_cast<float>(d.y);
    if (up >= 0.0f)
        return glm::mix(glm::vec3(0.9f, 0.95f, 1.0f), glm::vec3(0.15f, 0.35f, 0.9f), std::sqrt(up));
    return glm::mix(glm::vec3(0.5f, 0.4f, 0.3f), glm::vec3(0.2f, 0.15f, 0.1f), std::sqrt(-up));
}

} // namespace

CubeImage constantProbe(int faceSize, glm::vec3 radiance) { return CubeImage(faceSize, radiance); }

CubeImage impulseProbe(int faceSize, const Texel& texel, float value) {
    CubeImage cube(faceSize);
    cube.set(texelIndex(texel, faceSize), glm::vec3(value));
    return cube;
}

CubeImage skyProbe(int faceSize) { return fromDirections(faceSize, sky); }

CubeImage sunSkyProbe(int faceSize) {
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.4, 0.6, -0.7));
    const double cosRadius = std::cos(2.0 * 3.14159265358979 / 180.0);
    return fromDirections(faceSize, [&](const glm::dvec3& d) {
        return glm::dot(d, sun) >= cosRadius ? glm::vec3(1e4f) : sky(d);
    });
}

CubeImage roomProbe(int faceSize) {
    return fromDirections(faceSize, [](const glm::dvec3& d) {
        if (d.y > 0.8) return glm::vec3(4.0f, 3.8f, 3.5f);    // ceiling light
        if (d.y < -0.3) return glm::vec3(0.3f, 0.2f, 0.1f);   // floor
        if (d.x > 0.5) return glm::vec3(0.8f, 0.1f, 0.1f);    // red wall
        if (d.x < -0.5) return glm::vec3(0.1f, 0.6f, 0.15f);  // green wall
        if (d.z > 0.3) return glm::vec3(0.1f, 0.2f, 0.8f);    // blue wall
        return glm::vec3(0.7f, 0.7f, 0.6f);                   // grey wall
    });
}

CubeImage checkerProbe(int faceSize) {
    CubeImage cube(faceSize);
    const int square = std::max(1, faceSize / 8);
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < faceSize; ++j)
            for (int i = 0; i < faceSize; ++i)
                cube.set(texelIndex({f, i, j}, faceSize), glm::vec3(((i / square + j / square + f) % 2) ? 1.0f : 0.05f));
    return cube;
}

const std::vector<std::string>& syntheticProbeNames() {
    static const std::vector<std::string> names{"constant", "sky", "sunsky", "room", "checker"};
    return names;
}

CubeImage syntheticProbe(std::string_view name, int faceSize) {
    if (name == "constant") return constantProbe(faceSize, glm::vec3(1.0f));
    if (name == "sky") return skyProbe(faceSize);
    if (name == "sunsky") return sunSkyProbe(faceSize);
    if (name == "room") return roomProbe(faceSize);
    if (name == "checker") return checkerProbe(faceSize);
    throw ProbeError(fmt::format("unknown synthetic probe '{}' (constant, sky, sunsky, room, checker)", name));
}

} // namespace probe
