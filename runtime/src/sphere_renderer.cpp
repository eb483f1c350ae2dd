// The sphere renderer (shaders/spheres.comp): packs the filtered levels, the background and the
// Charlie levels (bordered, for seamless bilinear reads), the DFG and sheen tables, the irradiance and
// the materials into the four storage buffers and runs one dispatch per batch of spheres.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/format.h>
#include <spheres.spv.h>

#include "compute_pipeline.h"
#include "probe/error.h"
#include "probe/range_scale.h"
#include "submission.h"

namespace probe::gpu {

namespace {

struct SphereConstants {
    int32_t cellSize;
    int32_t materialCount;
    int32_t faceSize;
    int32_t levelCount;
    int32_t backgroundSize;
    int32_t dfgSize;
    int32_t sheenFirst; // the Charlie levels' first texel in the cube buffer (0: none)
    int32_t sheenSize;  // the sheen table's size (after the DFG table in the lookup buffer)
    float tanHalfFov;
    float distance;
};

// The storage buffer range Vulkan guarantees on every device (maxStorageBufferRange >= 2^27).
constexpr std::size_t kGuaranteedStorageRange = std::size_t{1} << 27;

// The unit sphere seen from 4 units away fills about 80% of its cell.
constexpr float kCameraDistance = 4.0f;
constexpr float kTanHalfFov = 0.32f;

// The filtered levels packed from S_0 in the pyramid buffer's layout (footprint.glsl reads them), the
// empty ones as zeros (no material reads them).
std::vector<float> packedLevels(const CubeLevels& levels, int faceSize) {
    std::vector<float> texels;
    for (std::size_t m = 0; m < levels.size(); ++m) {
        const int size = faceSize >> m;
        if (levels[m].size == 0) {
            texels.resize(texels.size() + 4 * pyramidLevelTexels(size), 0.0f);
            continue;
        }
        if (levels[m].size != size)
            throw ProbeError(fmt::format("sphere renderer: level {} has face size {}, not {}", m, levels[m].size, size));
        const std::vector<float> level = borderedRgbaTexels(levels[m]);
        texels.insert(texels.end(), level.begin(), level.end());
    }
    return texels;
}

// Radiance above 2^64 is rendered scaled down by 2^shift and scaled back (probe/range_scale.h), so
// that the shading sums stay finite.
int sceneShift(const SphereScene& scene) {
    double largest = largestMagnitude(*scene.background);
    for (const CubeImage& level : *scene.prefiltered) largest = std::max<double>(largest, largestMagnitude(level));
    if (scene.sheen)
        for (const CubeImage& level : *scene.sheen) largest = std::max<double>(largest, largestMagnitude(level));
    for (const glm::dvec3& c : scene.irradiance) largest = std::max({largest, std::abs(c.r), std::abs(c.g), std::abs(c.b)});
    return rangeShift(largest);
}

// A lookup table as spheres.comp reads it: RGBA texels, its two terms in R and G (one black texel
// when there is no table).
void appendLookup(std::vector<float>& lookup, const Image* table, const char* name) {
    if (!table) {
        lookup.insert(lookup.end(), {0.0f, 0.0f, 0.0f, 0.0f});
        return;
    }
    if (table->height != table->width) throw ProbeError(fmt::format("sphere renderer: the {} table must be square", name));
    for (std::size_t p = 0; p < table->rgb.size(); p += 3) lookup.insert(lookup.end(), {table->rgb[p], table->rgb[p + 1], 0.0f, 0.0f});
}

// A batch's row of cells (RGBA, scaled down by 2^shift) into its place in the whole row, scaled back.
void placeBatch(Image& out, const std::vector<float>& rgba, std::size_t first, std::size_t count, int cellSize, int shift) {
    constexpr float largestFloat = std::numeric_limits<float>::max();
    const std::size_t batchWidth = count * static_cast<std::size_t>(cellSize);
    for (std::size_t y = 0; y < static_cast<std::size_t>(out.height); ++y)
        for (std::size_t x = 0; x < batchWidth; ++x)
            for (std::size_t c = 0; c < 3; ++c)
                out.rgb[3 * (y * out.width + first * cellSize + x) + c] =
                    std::min(std::ldexp(rgba[4 * (y * batchWidth + x) + c], shift), largestFloat);
}

} // namespace

Image renderSpheres(const Device& device, const SphereScene& scene) {
    if (!scene.prefiltered || scene.prefiltered->empty() || !scene.background || scene.materials.empty() || scene.cellSize < 1)
        throw ProbeError("sphere renderer: needs the filtered levels, a background, at least one material and a cell size");
    const CubeLevels& levels = *scene.prefiltered;
    // S_0 from the first level computed, GGX or Charlie; with none (diffuse materials only), the
    // smallest S_0 that has this many levels.
    int faceSize = 1 << (levels.size() - 1);
    for (const CubeLevels* set : {scene.sheen, &levels})
        if (set)
            for (std::size_t m = set->size(); m-- > 0;)
                if ((*set)[m].size) faceSize = (*set)[m].size << m;
    const int shift = sceneShift(scene);
    CubeLevels scaledLevels = levels;
    shiftLevels(scaledLevels, -shift);
    // The background after the levels, where spheres.comp reads it.
    std::vector<float> cubes = packedLevels(scaledLevels, faceSize);
    const std::vector<float> background = borderedRgbaTexels(shifted(*scene.background, -shift));
    cubes.insert(cubes.end(), background.begin(), background.end());
    // The Charlie levels after the background, where a material with sheen reads them.
    const bool sheen = std::any_of(scene.materials.begin(), scene.materials.end(), [](const SphereMaterial& m) { return m.hasSheen(); });
    if (sheen && (!scene.sheen || !scene.sheenTable || scene.sheen->size() != levels.size()))
        throw ProbeError(
            "sphere renderer: a material with sheen needs the Charlie levels (as many as the filtered ones) and the sheen table");
    const std::size_t sheenFirst = sheen ? cubes.size() / 4 : 0;
    if (sheen) {
        CubeLevels scaledSheen = *scene.sheen;
        shiftLevels(scaledSheen, -shift);
        const std::vector<float> charlie = packedLevels(scaledSheen, faceSize);
        cubes.insert(cubes.end(), charlie.begin(), charlie.end());
    }

    std::vector<float> lookup;
    appendLookup(lookup, scene.dfg, "DFG");
    appendLookup(lookup, sheen ? scene.sheenTable : nullptr, "sheen");
    const int dfgSize = scene.dfg ? scene.dfg->width : 1, sheenSize = sheen ? scene.sheenTable->width : 1;

    for (const SphereMaterial& m : scene.materials)
        if (m.hasSpecular && !scene.dfg) throw ProbeError("sphere renderer: a specular material needs the DFG table");
    std::vector<float> irradiance;
    for (const glm::dvec3& e : scene.irradiance) {
        const glm::dvec3 c = std::ldexp(1.0, -shift) * e;
        irradiance.insert(irradiance.end(), {static_cast<float>(c.r), static_cast<float>(c.g), static_cast<float>(c.b), 0.0f});
    }

    // The spheres in batches whose image stays within the storage buffer range every Vulkan device
    // has (2^27 bytes: 227 spheres of 192^2), so that a scene's every material can be drawn.
    const std::size_t cellPixels = static_cast<std::size_t>(scene.cellSize) * scene.cellSize;
    const std::size_t batch = std::max<std::size_t>(1, kGuaranteedStorageRange / (cellPixels * 4 * sizeof(float)));
    const int width = scene.cellSize * static_cast<int>(scene.materials.size()), height = scene.cellSize;
    Image out{width, height, std::vector<float>(static_cast<std::size_t>(width) * height * 3)};
    Buffer cubeBuffer(device, cubes.size() * sizeof(float), Buffer::Kind::texels);
    Buffer lookupBuffer(device, lookup.size() * sizeof(float), Buffer::Kind::storage);
    Submission submission(device);
    submission.upload(cubeBuffer, cubes.data(), cubeBuffer.bytes());
    submission.upload(lookupBuffer, lookup.data(), lookupBuffer.bytes());
    for (std::size_t first = 0; first < scene.materials.size(); first += batch) {
        const std::size_t count = std::min(batch, scene.materials.size() - first);
        std::vector<float> parameters = irradiance;
        for (std::size_t k = first; k < first + count; ++k) {
            const SphereMaterial& m = scene.materials[k];
            parameters.insert(parameters.end(), {m.baseColor.r, m.baseColor.g, m.baseColor.b, m.metallic, m.specular, m.roughness, m.level,
                                                 m.hasSpecular ? 1.0f : 0.0f, m.sheenColor.r, m.sheenColor.g, m.sheenColor.b,
                                                 m.sheenRoughness, m.sheenLevel, 0.0f, 0.0f, 0.0f});
        }
        const std::size_t pixels = count * cellPixels;
        Buffer image(device, pixels * 4 * sizeof(float), Buffer::Kind::storage);
        Buffer parameterBuffer(device, parameters.size() * sizeof(float), Buffer::Kind::storage);
        PipelineLayout layout(device, {&cubeBuffer, &image, &lookupBuffer, &parameterBuffer});
        ComputePipeline pipeline(device.device(), layout, kSpheresSpv);
        submission.upload(parameterBuffer, parameters.data(), parameterBuffer.bytes());
        const SphereConstants constants{scene.cellSize,
                                        static_cast<int32_t>(count),
                                        faceSize,
                                        static_cast<int32_t>(levels.size()),
                                        scene.background->size,
                                        dfgSize,
                                        static_cast<int32_t>(sheenFirst),
                                        sheenSize,
                                        kTanHalfFov,
                                        kCameraDistance};
        VkCommandBuffer commandBuffer = submission.begin();
        computeBarrier(commandBuffer);
        layout.bind(commandBuffer);
        pipeline.dispatch(commandBuffer, std::as_bytes(std::span(&constants, 1)), groupsFor(pixels));
        computeBarrier(commandBuffer);
        submission.submitAndWait(commandBuffer);
        submission.release(commandBuffer);

        std::vector<float> rgba(pixels * 4);
        submission.download(image, rgba.data(), image.bytes());
        placeBatch(out, rgba, first, count, scene.cellSize, shift);
    }
    return out;
}

} // namespace probe::gpu
