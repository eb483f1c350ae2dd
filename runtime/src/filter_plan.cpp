#include "filter_plan.h"

#include <algorithm>

#include <fmt/format.h>

#include "buffer.h"
#include "device.h"
#include "filter_descriptors.h"
#include "probe/error.h"
#include "probe/paraboloid.h"

namespace probe::gpu {

namespace {

constexpr VkDeviceSize kTexelBytes = 4 * sizeof(float); // RGBA32F, the buffers' texels

// First texel of each level of a packed cube with `levels` levels from `faceSize`, and the total.
std::vector<uint32_t> packedOffsets(int faceSize, int levels) {
    std::vector<uint32_t> offsets{0};
    for (int m = 0; m < levels; ++m) offsets.push_back(offsets.back() + static_cast<uint32_t>(texelCount(faceSize >> m)));
    return offsets;
}

// First texel of each level of the bordered pyramid (buffer.h), and the total.
std::vector<uint32_t> pyramidOffsetsFor(int faceSize, int levels) {
    std::vector<uint32_t> offsets{0};
    for (int m = 0; m < levels; ++m) offsets.push_back(offsets.back() + static_cast<uint32_t>(pyramidLevelTexels(faceSize >> m)));
    return offsets;
}

// The dual-paraboloid map (shaders/paraboloid.glsl): both images of every level, down to 1x1.
std::size_t paraboloidMapTexels(int faceSize) {
    std::size_t texels = 0;
    for (int size = paraboloidSize(faceSize); size >= 1; size /= 2) texels += 2 * static_cast<std::size_t>(size) * size;
    return texels;
}

bool readsParaboloid(const FilterMethod& method) { return method.kind == MethodKind::fis && method.fis.map == FisMap::paraboloid; }

Sampling resolveSampling(const DeviceCapabilities& device, const FilterSettings& s) {
    if (s.method.kind == MethodKind::reference) return Sampling::exact; // it reads every texel as it is
    if (readsParaboloid(s.method)) {
        // The map lives in a buffer and is read with the shader's own arithmetic.
        if (s.sampling == Sampling::hardware)
            throw ParameterError("sampling", "hardware: FIS on a paraboloid map reads it exactly (use exact or automatic)");
        return Sampling::exact;
    }
    if (s.sampling != Sampling::automatic) return s.sampling;
    return device.cpu ? Sampling::exact : Sampling::hardware;
}

// The requested format, where the device filters and stores it. By default RGBA16F, the format
// engines filter in: the sampler reads half the bytes per tap (docs/benchmarks.md times both), and
// run() scales a source brighter than 65504 into its range; RGBA32F where a device lacks it.
VkFormat choosePyramidFormat(const DeviceCapabilities& device, VkFormat requested) {
    // Filtered as itself, stored through pyramidStoreFormat.
    const auto usable = [&](VkFormat format) {
        return device.has(format, VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT) &&
               device.has(pyramidStoreFormat(format), VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT);
    };
    if (requested != VK_FORMAT_UNDEFINED) {
        if (!usable(requested))
            throw ProbeError(fmt::format("Vulkan: {} cannot filter and store {} images{}, which the pyramid needs (use another format)",
                                         device.name, formatName(requested),
                                         pyramidStoreFormat(requested) != requested ? " (stored as R32_UINT bits)" : ""));
        return requested;
    }
    for (VkFormat format : {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT})
        if (usable(format)) return format;
    throw ProbeError(fmt::format("Vulkan: {} can neither filter and store R16G16B16A16_SFLOAT nor R32G32B32A32_SFLOAT images, which "
                                 "the pyramid of hardware sampling needs (use exact sampling)",
                                 device.name));
}

// Whether a B10G11R11 output goes through the conversion pass; throws for a format the runtime
// cannot write.
bool checkOutputFormat(const DeviceCapabilities& device, VkFormat format) {
    if (format != VK_FORMAT_R32G32B32A32_SFLOAT && format != VK_FORMAT_R16G16B16A16_SFLOAT && format != VK_FORMAT_B10G11R11_UFLOAT_PACK32)
        throw ParameterError("outputFormat", fmt::format("{}: the output cube is R32G32B32A32_SFLOAT, R16G16B16A16_SFLOAT or "
                                                         "B10G11R11_UFLOAT_PACK32",
                                                         int(format)));
    if (device.has(format, VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT)) return false;
    if (format == VK_FORMAT_B10G11R11_UFLOAT_PACK32 && device.has(format, VK_FORMAT_FEATURE_TRANSFER_DST_BIT) &&
        device.has(VK_FORMAT_R32_UINT, VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT | VK_FORMAT_FEATURE_TRANSFER_SRC_BIT))
        return true;
    throw ProbeError(fmt::format("Vulkan: {} cannot store {} images (storage image usage), which the output cube needs", device.name,
                                 formatName(format)));
}

} // namespace

VkFormat pyramidStoreFormat(VkFormat pyramid) { return pyramid == VK_FORMAT_E5B9G9R9_UFLOAT_PACK32 ? VK_FORMAT_R32_UINT : pyramid; }

bool DeviceCapabilities::has(VkFormat format, VkFormatFeatureFlags needed) const {
    const auto f = formatFeatures.find(format);
    return f != formatFeatures.end() && (f->second & needed) == needed;
}

std::vector<PyramidWindow> pyramidWindows(int faceSize, int depth, int tailLevel, int cubes, const DeviceCapabilities& d) {
    const std::vector<uint32_t> offsets = pyramidOffsetsFor(faceSize, depth + 1);
    const int layers = kFaceCount * cubes;
    const std::size_t range = d.maxStorageBufferRange / kTexelBytes;
    // A binding's offset is a multiple of the alignment (a power of two), in bytes.
    const std::size_t alignment = std::max<std::size_t>(1, d.minStorageBufferOffsetAlignment / kTexelBytes);
    std::vector<PyramidWindow> windows;
    if (tailLevel > 0 && tailLevel <= depth) { // a few thousand texels a cube: within every range
        const std::size_t start = std::size_t(cubes) * offsets[tailLevel], first = start / alignment * alignment;
        windows.push_back({tailLevel, 0, layers, first, std::size_t(cubes) * offsets[depth + 1] - first});
        depth = tailLevel - 1;
    }
    const std::size_t tail = windows.size();
    for (int level = 0; level <= depth; ++level) {
        const std::size_t perFace = pyramidLevelTexels(faceSize >> level) / kFaceCount;
        for (int face = 0; face < layers;) {
            const std::size_t start = std::size_t(cubes) * offsets[level] + face * perFace, first = start / alignment * alignment;
            int count = 0;
            while (face + count < layers && start + (count + 1) * perFace - first <= range) ++count;
            if (count == 0)
                throw ProbeError(fmt::format("Vulkan: {} writes storage buffers of at most {:.1f} MiB, and a face of the {}^2 pyramid "
                                             "takes {:.1f} MiB; use a smaller --size",
                                             d.name, static_cast<double>(d.maxStorageBufferRange) / (1 << 20), faceSize,
                                             static_cast<double>((start + perFace - first) * kTexelBytes) / (1 << 20)));
            windows.push_back({level, face, count, first, start + count * perFace - first});
            face += count;
        }
    }
    std::rotate(windows.begin(), windows.begin() + std::ptrdiff_t(tail), windows.end()); // the tail's last
    return windows;
}

std::vector<ParaboloidWindow> paraboloidWindows(int faceSize, std::size_t mapFirst, const DeviceCapabilities& d) {
    const std::size_t range = d.maxStorageBufferRange / kTexelBytes;
    const std::size_t alignment = std::max<std::size_t>(1, d.minStorageBufferOffsetAlignment / kTexelBytes);
    if (range < alignment) // a window starts up to alignment - 1 texels before its first texel
        throw ProbeError(fmt::format("Vulkan: {} writes storage buffers of at most {} bytes, below its offset alignment", d.name,
                                     d.maxStorageBufferRange));
    std::vector<ParaboloidWindow> windows;
    std::size_t levelFirst = mapFirst;
    for (int level = 0, size = paraboloidSize(faceSize); size >= 1; ++level, size /= 2) {
        const std::size_t levelTexels = 2 * std::size_t(size) * std::size_t(size);
        for (std::size_t start = 0; start < levelTexels;) {
            const std::size_t first = (levelFirst + start) / alignment * alignment;
            const std::size_t count = std::min(levelTexels - start, range - (levelFirst + start - first));
            windows.push_back({level, start, count, first, levelFirst + start + count - first});
            start += count;
        }
        levelFirst += levelTexels;
    }
    return windows;
}

DeviceCapabilities capabilitiesOf(const Device& device) {
    const Device::Impl& d = device.impl();
    DeviceCapabilities c;
    c.name = d.info.name;
    c.cpu = d.info.type == "cpu";
    c.computeSubgroupVote = d.computeSubgroupVote;
    c.imageCubeArray = d.imageCubeArray;
    c.maxImageArrayLayers = d.limits.maxImageArrayLayers;
    c.maxPerStageDescriptorStorageImages = d.limits.maxPerStageDescriptorStorageImages;
    c.maxStorageBufferRange = d.limits.maxStorageBufferRange;
    c.minStorageBufferOffsetAlignment = d.limits.minStorageBufferOffsetAlignment;
    c.maxTexelBufferElements = d.limits.maxTexelBufferElements;
    for (VkFormat f : {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_B10G11R11_UFLOAT_PACK32, VK_FORMAT_R32_UINT,
                       VK_FORMAT_E5B9G9R9_UFLOAT_PACK32})
        c.formatFeatures[f] = d.features(f);
    return c;
}

FilterPlan planFilter(const FilterSettings& s, const DeviceCapabilities& d) {
    validateSizeAndLevels(s.faceSize, s.levelCount);
    validateMappingLevels(s.mapping, s.levelCount);
    validateMethod(s.method, s.faceSize, s.levelCount, s.mapping);
    if (s.inFlight < 1 || s.inFlight > 64)
        throw ParameterError("inFlight", fmt::format("{}: recordings in flight are 1 to 64", s.inFlight));
    if (s.batchSize < 1 || s.batchSize > kMaxBatchSize)
        throw ParameterError("batchSize", fmt::format("{}: a batch is 1 to {} probes", s.batchSize, kMaxBatchSize));
    if (s.batchSize > 1 && (s.method.kind == MethodKind::reference || readsParaboloid(s.method)))
        throw ParameterError("batchSize",
                             fmt::format("{}: {} filters one probe at a time", s.batchSize,
                                         s.method.kind == MethodKind::reference ? "the reference" : "FIS on a paraboloid map"));
    if (s.batchSize > 1 && !d.imageCubeArray)
        throw ProbeError(fmt::format("Vulkan: {} has no imageCubeArray feature, which a batch's cube-map arrays need", d.name));
    if (uint32_t(kFaceCount * s.batchSize) > d.maxImageArrayLayers)
        throw ProbeError(fmt::format("Vulkan: {} makes images of at most {} layers, and a batch of {} takes {}", d.name,
                                     d.maxImageArrayLayers, s.batchSize, kFaceCount * s.batchSize));
    FilterPlan plan;
    plan.pyramidLevels = pyramidLevelCount(s.faceSize);
    plan.pyramidDepth = s.pyramidDepth < 0 ? plan.pyramidLevels - 1 : s.pyramidDepth;
    if (plan.pyramidDepth > plan.pyramidLevels - 1)
        throw ParameterError("pyramidDepth", fmt::format("{}: a {}^2 pyramid has levels 1..{} below the source", s.pyramidDepth, s.faceSize,
                                                         plan.pyramidLevels - 1));
    for (int m = 0; m < s.levelCount; ++m) plan.computedLevels.push_back(m);
    if (!s.computedLevels.empty()) {
        for (std::size_t k = 0; k < s.computedLevels.size(); ++k)
            if (s.computedLevels[k] < 0 || s.computedLevels[k] >= s.levelCount || (k > 0 && s.computedLevels[k] <= s.computedLevels[k - 1]))
                throw ParameterError("computedLevels",
                                     fmt::format("{}: not one of 0..{} in ascending order", s.computedLevels[k], s.levelCount - 1));
        plan.computedLevels = s.computedLevels;
    }
    plan.outputOffsets = packedOffsets(s.faceSize, s.levelCount);
    for (int m = 0; m < s.levelCount; ++m)
        if (lobeAlpha(s.method.lobe, levelAlpha(s.mapping, m, s.levelCount)) <= 0.0) plan.copyLevels |= 1u << m;
    const bool filters = std::any_of(plan.computedLevels.begin(), plan.computedLevels.end(), [&](int m) { return !plan.isCopy(m); });
    plan.filters = filters;
    const MethodKind kind = s.method.kind;
    if (kind == MethodKind::table)
        for (int m : plan.computedLevels)
            if (!plan.isCopy(m) && s.method.table->levels[m].fisSamples > 0) plan.fisLevels |= 1u << m;
    const auto joins = [&](int m) { return kind != MethodKind::reference && !plan.isCopy(m); };
    if (d.maxPerStageDescriptorStorageImages >= kWideWrittenMipCount) plan.writtenMipCount = kWideWrittenMipCount;
    for (int m : plan.computedLevels) {
        std::vector<int>* last = plan.levelGroups.empty() ? nullptr : &plan.levelGroups.back();
        if (last && joins(m) && joins(last->back()) && last->back() == m - 1 && last->size() < plan.writtenMipCount &&
            plan.isHandedOff(m) == plan.isHandedOff(last->back()))
            last->push_back(m);
        else plan.levelGroups.push_back({m});
    }
    plan.buildsPyramid = kind != MethodKind::reference && filters;
    plan.paraboloid = readsParaboloid(s.method) && filters;
    if (plan.paraboloid) plan.pyramidDepth = 0; // the map reads the source alone
    plan.sampling = resolveSampling(d, s);
    if (s.pyramidFormat != VK_FORMAT_UNDEFINED) {
        if (s.pyramidFormat != VK_FORMAT_R32G32B32A32_SFLOAT && s.pyramidFormat != VK_FORMAT_R16G16B16A16_SFLOAT &&
            s.pyramidFormat != VK_FORMAT_E5B9G9R9_UFLOAT_PACK32)
            throw ParameterError("pyramidFormat", fmt::format("{}: the pyramid is R32G32B32A32_SFLOAT, R16G16B16A16_SFLOAT or "
                                                              "E5B9G9R9_UFLOAT_PACK32",
                                                              int(s.pyramidFormat)));
        if (plan.sampling == Sampling::exact)
            throw ParameterError("pyramidFormat",
                                 fmt::format("{}: only hardware sampling's pyramid is an image; exact sampling's is a float32 "
                                             "buffer (choose hardware sampling)",
                                             formatName(s.pyramidFormat)));
    }
    if (kind == MethodKind::table && plan.sampling == Sampling::exact && !d.computeSubgroupVote)
        throw ProbeError(fmt::format("Vulkan: {} has no subgroup vote operations in compute shaders, which the table method's exact "
                                     "sampling needs (use hardware sampling)",
                                     d.name));
    plan.convertOutput = checkOutputFormat(d, s.outputFormat);
    if (plan.buildsPyramid && !plan.paraboloid) {
        // The level of face size PROBE_PYRAMID_TAIL_SIZE, or level 1 where the source is no larger.
        plan.pyramidTailLevel = std::max(1, plan.pyramidLevels - kPyramidTailMipCount);
        if (plan.pyramidTailLevel > plan.pyramidDepth) plan.pyramidTailLevel = 0;
    }
    if (plan.buildsPyramid && plan.sampling == Sampling::hardware) plan.pyramidFormat = choosePyramidFormat(d, s.pyramidFormat);

    // The bordered pyramid: every level for exact sampling, level 0 alone for the reference.
    plan.pyramidOffsets = pyramidOffsetsFor(s.faceSize, plan.pyramidLevels);
    // The paraboloid map follows the bordered source.
    if (plan.paraboloid) plan.pyramidTexels = plan.pyramidOffsets[1] + paraboloidMapTexels(s.faceSize);
    else if (plan.buildsPyramid && plan.sampling == Sampling::exact)
        plan.pyramidTexels = std::size_t(s.batchSize) * plan.pyramidOffsets.back();
    else if (kind == MethodKind::reference && filters) plan.pyramidTexels = plan.pyramidOffsets[1];
    if (kind == MethodKind::reference) plan.accumulatorTexels = plan.outputOffsets.back();
    plan.geometry = plan.sampling == Sampling::exact || s.method.pyramid().kind == PyramidKind::box;
    if (plan.geometry) {
        plan.geometryTexels = 0;
        for (int m = 0; m < plan.pyramidLevels; ++m) plan.geometryTexels += texelCount(s.faceSize >> m);
    }

    // The accumulator within the device's storage-buffer range, the pyramid written in windows within
    // it, and the buffers read as texel buffers within its element count.
    if (plan.accumulatorTexels * kTexelBytes > d.maxStorageBufferRange)
        throw ProbeError(fmt::format("Vulkan: {} needs a storage buffer of {:.1f} MiB at {}^2, over its maxStorageBufferRange of "
                                     "{:.1f} MiB; use a smaller --size",
                                     d.name, static_cast<double>(plan.accumulatorTexels * kTexelBytes) / (1 << 20), s.faceSize,
                                     static_cast<double>(d.maxStorageBufferRange) / (1 << 20)));
    if (plan.pyramidTexels > 1)
        plan.pyramidWindows = plan.buildsPyramid && plan.sampling == Sampling::exact
                                  ? pyramidWindows(s.faceSize, plan.pyramidDepth, plan.pyramidTailLevel, s.batchSize, d)
                                  : pyramidWindows(s.faceSize, 0, 0, s.batchSize, d);
    if (plan.paraboloid) plan.paraboloidWindows = paraboloidWindows(s.faceSize, plan.pyramidOffsets[1], d);
    for (const std::size_t texels : {plan.pyramidTexels, plan.geometryTexels})
        if (texels > d.maxTexelBufferElements)
            throw ProbeError(fmt::format("Vulkan: {} reads texel buffers of at most {} texels, this one has {}; use a smaller size", d.name,
                                         d.maxTexelBufferElements, texels));
    return plan;
}

} // namespace probe::gpu
