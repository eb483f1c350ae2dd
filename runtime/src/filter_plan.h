// What a Filter of given settings computes on a device, and the sizes of what it allocates: a pure
// function of the settings and of what the device offers (DeviceCapabilities), which the Filter's
// resources and passes follow and which a test checks without a device.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "filter_descriptors.h"
#include "probe/runtime.h"

namespace probe::gpu {

// What the plan needs of a device: its name (for messages), whether it is a CPU device (automatic
// sampling reads exactly there), subgroup votes in compute shaders, cube-map arrays (batches), the
// buffer and layer limits and the optimal-tiling features of the formats the runtime uses.
struct DeviceCapabilities {
    std::string name;
    bool cpu = false;
    bool computeSubgroupVote = true;
    bool imageCubeArray = true;
    uint32_t maxImageArrayLayers = 256;
    uint32_t maxPerStageDescriptorStorageImages = 4;
    VkDeviceSize maxStorageBufferRange = 0;
    VkDeviceSize minStorageBufferOffsetAlignment = 1;
    uint32_t maxTexelBufferElements = 0;
    std::map<VkFormat, VkFormatFeatureFlags> formatFeatures;

    bool has(VkFormat format, VkFormatFeatureFlags needed) const;
};
DeviceCapabilities capabilitiesOf(const Device& device);

// Part of the bordered pyramid buffer that pass 1 writes through one storage-buffer binding: the
// faces [firstFace, firstFace + faceCount) of one level (layers of a batch's cubes, which the buffer
// holds level by level: shaders/buffers.glsl), bound from texel `first` (aligned as the
// device asks) for `texels` texels, within the device's storage-buffer range. The whole buffer is
// read as a texel buffer, whose limit is in elements: at 2048^2 it is 513.5 MiB where every device
// guarantees a storage-buffer range of 128 MiB.
struct PyramidWindow {
    int level = 0;
    int firstFace = 0;
    int faceCount = 0;
    std::size_t first = 0;
    std::size_t texels = 0;
};

// The windows of levels 0..depth of a bordered pyramid of `faceSize` with `cubes` cubes, in level
// order: one per level where the level fits the range, else runs of whole faces; from `tailLevel` (a
// level from 1 with faces of PROBE_PYRAMID_TAIL_SIZE or smaller; 0: none) the levels down to `depth`
// in one window, which pass 1's last dispatch writes. Throws ProbeError where one face does not fit.
std::vector<PyramidWindow> pyramidWindows(int faceSize, int depth, int tailLevel, int cubes, const DeviceCapabilities& device);

// Part of a level of FIS's dual-paraboloid map that one dispatch of pass 1 writes through one
// storage-buffer binding: the level's texels [start, start + count) (its front image, then its back
// image, row-major: shaders/paraboloid.glsl), bound from pyramid-buffer texel `first` (aligned as the
// device asks) for `texels` texels. The map follows the bordered source in the pyramid buffer, whose
// reads go through a texel buffer: at 2048^2 its level 0 alone takes 512 MiB.
struct ParaboloidWindow {
    int level = 0;
    std::size_t start = 0;
    std::size_t count = 0;
    std::size_t first = 0;
    std::size_t texels = 0;
};

// The windows of every level of the map of a source of `faceSize`, the map starting at pyramid-buffer
// texel `mapFirst`, in level order, each as large as the device's storage-buffer range allows.
std::vector<ParaboloidWindow> paraboloidWindows(int faceSize, std::size_t mapFirst, const DeviceCapabilities& device);

// The most probes a batch holds (FilterSettings::batchSize).
inline constexpr int kMaxBatchSize = 256;

struct FilterPlan {
    Sampling sampling = Sampling::exact;                    // resolved: the reference and the paraboloid map read exactly
    VkFormat pyramidFormat = VK_FORMAT_R32G32B32A32_SFLOAT; // hardware sampling's pyramid image
    bool convertOutput = false;                             // B10G11R11 through the conversion pass
    int pyramidLevels = 0;                                  // log2(S_0) + 1: down to 1x1
    int pyramidDepth = 0;                                   // pass 1 builds levels 1..pyramidDepth
    int pyramidTailLevel = 0;                               // pass 1's tail: levels pyramidTailLevel..pyramidDepth (0: none)
    std::vector<int> computedLevels;                        // the output levels computed, ascending
    // The storage images a dispatch writes (filter_descriptors.h): kWideWrittenMipCount where the
    // device offers as many per stage, else the kWrittenMipCount every device offers.
    uint32_t writtenMipCount = kWrittenMipCount;
    // Pass 2's dispatches over computedLevels: consecutive levels of one pass (the table's, or FIS's)
    // share one, at most writtenMipCount of them; a copy and a reference level each have their own.
    std::vector<std::vector<int>> levelGroups;
    uint32_t copyLevels = 0;             // bit m: output level m has alpha = 0, a copy of the source
    uint32_t fisLevels = 0;              // table: bit m, computed level m is handed to FIS (TableLevel::fisSamples)
    bool filters = false;                // a computed level is filtered, not copied
    bool buildsPyramid = false;          // pass 1 builds a pyramid (table or fis with a filtered level computed)
    bool paraboloid = false;             // fis on a dual-paraboloid map: pass 1 builds it in the pyramid buffer
    std::vector<uint32_t> outputOffsets; // first texel of each output level (packed), and the total
    // First texel of each bordered pyramid level of a cube (buffer.h), and the total; a batch's level k
    // starts at batchSize times its offset.
    std::vector<uint32_t> pyramidOffsets;
    std::vector<PyramidWindow> pyramidWindows;       // where pass 1 writes the bordered pyramid (exact sampling, the reference)
    std::vector<ParaboloidWindow> paraboloidWindows; // and then the paraboloid map, after the bordered source
    // The geometry buffer holds every pyramid level's directions and solid angles where exact sampling
    // or the box pyramid reads them (hardware sampling computes its directions), else one texel.
    bool geometry = false;
    // Each recording's buffers and the geometry buffer, in RGBA32F texels (1: unused).
    std::size_t pyramidTexels = 1, accumulatorTexels = 1, geometryTexels = 1;

    bool isCopy(int level) const { return (copyLevels & (1u << level)) != 0; }
    bool isHandedOff(int level) const { return (fisLevels & (1u << level)) != 0; }
};

// The format a pyramid image's mips are written through: E5B9G9R9, which no device stores, as its
// R32_UINT bits (shaders/images.glsl packs them); any other as itself.
VkFormat pyramidStoreFormat(VkFormat pyramid);

// Throws ParameterError naming the setting the method or the runtime refuses, and ProbeError naming
// the device and what it lacks (a format feature, subgroup votes, a buffer range) for the rest.
FilterPlan planFilter(const FilterSettings& settings, const DeviceCapabilities& device);

} // namespace probe::gpu
