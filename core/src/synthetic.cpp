#include "probe/synthetic.h"

#include <algorithm>
#include <cmath>
#include <numbers>

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
    if (up >= 0.0f) return glm::mix(glm::vec3(0.9f, 0.95f, 1.0f), glm::vec3(0.15f, 0.35f, 0.9f), std::sqrt(up));
    return glm::mix(glm::vec3(0.5f, 0.4f, 0.3f), glm::vec3(0.2f, 0.15f, 0.1f), std::sqrt(-up));
}

glm::vec3 sunSky(const glm::dvec3& d) {
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.4, 0.6, -0.7));
    const double cosRadius = std::cos(2.0 * std::numbers::pi / 180.0);
    return glm::dot(d, sun) >= cosRadius ? glm::vec3(1e4f) : sky(d);
}

glm::vec3 room(const glm::dvec3& d) {
    if (d.y > 0.8) return glm::vec3(4.0f, 3.8f, 3.5f);   // ceiling light
    if (d.y < -0.3) return glm::vec3(0.3f, 0.2f, 0.1f);  // floor
    if (d.x > 0.5) return glm::vec3(0.8f, 0.1f, 0.1f);   // red wall
    if (d.x < -0.5) return glm::vec3(0.1f, 0.6f, 0.15f); // green wall
    if (d.z > 0.3) return glm::vec3(0.1f, 0.2f, 0.8f);   // blue wall
    return glm::vec3(0.7f, 0.7f, 0.6f);                  // grey wall
}

using RadianceFunction = glm::vec3 (*)(const glm::dvec3&);

RadianceFunction directionalProbe(std::string_view name) {
    if (name == "constant") return [](const glm::dvec3&) { return glm::vec3(1.0f); };
    if (name == "sky") return sky;
    if (name == "sunsky") return sunSky;
    if (name == "room") return room;
    return nullptr;
}

} // namespace

CubeImage constantProbe(int faceSize, glm::vec3 radiance) { return CubeImage(faceSize, radiance); }

CubeImage impulseProbe(int faceSize, const Texel& texel, float value) {
    CubeImage cube(faceSize);
    cube.set(texelIndex(texel, faceSize), glm::vec3(value));
    return cube;
}

CubeImage skyProbe(int faceSize) { return fromDirections(faceSize, sky); }

CubeImage sunSkyProbe(int faceSize) { return fromDirections(faceSize, sunSky); }

CubeImage roomProbe(int faceSize) { return fromDirections(faceSize, room); }

CubeImage checkerProbe(int faceSize) {
    CubeImage cube(faceSize);
    const int square = std::max(1, faceSize / 8);
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < faceSize; ++j)
            for (int i = 0; i < faceSize; ++i)
                cube.set(texelIndex({f, i, j}, faceSize), glm::vec3(onLightSquare({f, i, j}, square) ? 1.0f : 0.05f));
    return cube;
}

CubeImage syntheticProbe(std::string_view name, int faceSize) {
    if (name == "checker") return checkerProbe(faceSize);
    if (auto radianceOf = directionalProbe(name)) return fromDirections(faceSize, radianceOf);
    throw ProbeError(fmt::format("unknown synthetic probe '{}' (constant, sky, sunsky, room, checker)", name));
}

Image syntheticEquirect(std::string_view name, int width) {
    auto radianceOf = directionalProbe(name);
    if (!radianceOf) throw ProbeError(fmt::format("synthetic probe '{}' has no equirectangular form (constant, sky, sunsky, room)", name));
    Image image{width, width / 2, std::vector<float>(static_cast<std::size_t>(width) * (width / 2) * 3)};
#pragma omp parallel for
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < width; ++x) {
            // Inverse of the mapping in probe_io.h: column -> atan2(z, x), row -> acos(y).
            const double phi = ((x + 0.5) / width - 0.5) * 2.0 * std::numbers::pi;
            const double theta = (y + 0.5) / image.height * std::numbers::pi;
            const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            const glm::vec3 value = radianceOf(d);
            std::copy(&value.r, &value.r + 3, &image.rgb[(static_cast<std::size_t>(y) * width + x) * 3]);
        }
    return image;
}

} // namespace probe
