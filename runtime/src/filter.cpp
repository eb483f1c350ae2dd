// Filter: resources, formats and pipelines of a setting, the sets of what a recording writes, the
// order of the passes, the engine path (filter_run.cpp has the tools' path).
#include <algorithm>
#include <array>
#include <cstring>

#include <fmt/format.h>

#include "device.h"
#include "filter_impl.h"
#include "probe/error.h"
#include "probe/fis.h"
#include "probe/paraboloid.h"
#include "probe/table_filter.h"
#include "separate_cubes.h"
#include "vulkan_check.h"

namespace probe::gpu {

namespace {

constexpr VkDeviceSize kTexelBytes = 4 * sizeof(float); // RGBA32F, the buffers' texels

// Per pyramid level: the unit texel-centre directions and exact solid angles, from probecore.
std::vector<float> geometryTexels(int faceSize, int levels) {
    std::vector<float> texels;
    for (int m = 0; m < levels; ++m) {
        const CubeGeometry geometry(faceSize >> m);
        for (std::size_t t = 0; t < geometry.directions.size(); ++t)
            for (double value : {geometry.directions[t].x, geometry.directions[t].y, geometry.directions[t].z, geometry.solidAngles[t]})
                texels.push_back(static_cast<float>(value));
    }
    return texels;
}

} // namespace

std::string_view samplingName(Sampling sampling) {
    switch (sampling) {
    case Sampling::automatic: return "automatic";
    case Sampling::hardware: return "hardware";
    case Sampling::exact: return "exact";
    }
    return "automatic";
}

Sampling parseSampling(std::string_view name) {
    for (Sampling s : {Sampling::automatic, Sampling::hardware, Sampling::exact})
        if (samplingName(s) == name) return s;
    throw ParameterError("sampling", fmt::format("{}: expected hardware, exact or automatic", name));
}

std::string_view formatName(VkFormat format) {
    switch (format) {
    case VK_FORMAT_R32G32B32A32_SFLOAT: return "rgba32f";
    case VK_FORMAT_R16G16B16A16_SFLOAT: return "rgba16f";
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32: return "b10g11r11";
    case VK_FORMAT_E5B9G9R9_UFLOAT_PACK32: return "rgb9e5";
    default: return "unsupported";
    }
}

VkFormat parsePyramidFormat(std::string_view name) {
    if (name == "auto") return VK_FORMAT_UNDEFINED;
    for (VkFormat f : {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_E5B9G9R9_UFLOAT_PACK32})
        if (formatName(f) == name) return f;
    throw ParameterError("pyramidFormat", fmt::format("{}: expected auto, rgba32f, rgba16f or rgb9e5", name));
}

VkFormat parseFormat(std::string_view name) {
    for (VkFormat f : {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_B10G11R11_UFLOAT_PACK32})
        if (formatName(f) == name) return f;
    throw ParameterError("outputFormat", fmt::format("{}: expected rgba16f, rgba32f or b10g11r11", name));
}

void Filter::checkLimits(const Device& device, const FilterSettings& settings) { planFilter(settings, capabilitiesOf(device)); }

Filter::Impl::Impl(const Device& d, const FilterSettings& s, VkCommandBuffer initialization)
    : device(d), settings(s), plan(planFilter(s, capabilitiesOf(d))) {
    const MethodKind kind = s.method.kind;
    std::vector<float> tableData;
    std::vector<uint32_t> sampleOffsets; // FIS's, or a table's hand-offs': each output level's first sample, and the end
    if (kind == MethodKind::table) {
        tableData = tableBufferData(*s.method.table);
        sampleOffsets = appendFisSamples(handOffSamples(*s.method.table), tableData);
    } else if (kind == MethodKind::fis) {
        sampleOffsets = appendFisSamples(fisSamplesPerLevel(s.faceSize, s.levelCount, s.mapping, s.method.fis, s.method.lobe), tableData);
    }
    if (tableData.empty()) tableData.assign(4, 0.0f); // the reference, or every level a copy: a buffer cannot be empty
    const std::vector<float> geometryData = plan.geometry ? geometryTexels(s.faceSize, plan.pyramidLevels) : std::vector<float>(4, 0.0f);
    geometry = Buffer(d, geometryData.size() * sizeof(float), Buffer::Kind::texels);
    geometryView = BufferView(d.device(), geometry);
    table = Buffer(d, tableData.size() * sizeof(float), Buffer::Kind::storage);
    if (table.bytes() / kTexelBytes > d.impl().limits.maxTexelBufferElements)
        throw ProbeError(fmt::format("Vulkan: {} reads texel buffers of at most {} texels, this one has {}", d.info().name,
                                     d.impl().limits.maxTexelBufferElements, table.bytes() / kTexelBytes));
    tableView = BufferView(d.device(), table);

    const VkDevice vk = d.device();
    placeholder = CubeImageResource(d, 1, 1, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT);
    placeholderCube = ImageView(vk, placeholder.handle(), VK_FORMAT_R32G32B32A32_SFLOAT, cubeViewType(), 0, 1);
    placeholderArray = ImageView(vk, placeholder.handle(), VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_VIEW_TYPE_2D_ARRAY, 0, 1);
    linear = std::make_unique<Sampler>(vk, true);
    nearest = std::make_unique<Sampler>(vk, false);
    descriptors = std::make_unique<FilterDescriptors>(vk, plan.writtenMipCount);

    const PassContext context{d, settings, plan, descriptors->pipelineLayout()};
    if (plan.buildsPyramid || (kind == MethodKind::reference && plan.filters)) pyramid.emplace(context);
    if (kind == MethodKind::table) tablePass.emplace(context);
    if (kind == MethodKind::fis || plan.fisLevels != 0) fisPass.emplace(context, std::move(sampleOffsets));
    if (kind == MethodKind::reference) referencePass.emplace(context);
    if (std::any_of(plan.computedLevels.begin(), plan.computedLevels.end(), [&](int m) { return plan.isCopy(m); }))
        copyPass.emplace(context);
    if (plan.convertOutput) convertPass.emplace(context);

    recordings.push_back(makeRecording());
    current = recordings.front().get();
    VkSemaphoreTypeCreateInfo timeline{VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO};
    timeline.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
    VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO, &timeline};
    vkCheck(vkCreateSemaphore(vk, &semaphoreInfo, nullptr, &completed), "vkCreateSemaphore");

    submission = std::make_unique<Submission>(d);
    // The one-time initialization: the tables' uploads through staging buffers, kept until it has
    // run, and the placeholder into VK_IMAGE_LAYOUT_GENERAL, where it stays.
    VkCommandBuffer commandBuffer = initialization != VK_NULL_HANDLE ? initialization : submission->begin();
    for (const auto& [to, data] : {std::pair<const Buffer*, const float*>{&geometry, geometryData.data()}, {&table, tableData.data()}}) {
        Buffer& staging = initStaging.emplace_back(d, to->bytes(), Buffer::Kind::staging);
        std::memcpy(staging.mapped(), data, to->bytes());
        const VkBufferCopy region{0, 0, to->bytes()};
        vkCmdCopyBuffer(commandBuffer, staging.handle(), to->handle(), 1, &region);
    }
    imageBarrier(commandBuffer, placeholder.handle(), 0, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                 VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    computeBarrier(commandBuffer); // the uploads, before the passes read them
    if (initialization != VK_NULL_HANDLE) return;
    submission->submitAndWait(commandBuffer);
    submission->release(commandBuffer);
    initStaging.clear();
}

Filter::Impl::~Impl() {
    recordings.clear(); // their views, before the images they view
    vkDestroySemaphore(device.device(), completed, nullptr);
}

uint64_t Filter::Impl::completedValue() const {
    uint64_t value = 0;
    vkCheck(vkGetSemaphoreCounterValue(device.device(), completed, &value), "vkGetSemaphoreCounterValue");
    return value;
}

void Filter::Impl::acquire() {
    const uint64_t done = completedValue();
    if (done >= 1) initStaging.clear();
    // The least recently used set first, so that sets are used in turn.
    Recording* free = nullptr;
    for (const std::unique_ptr<Recording>& r : recordings)
        if (r->completion <= done && (!free || r->completion < free->completion)) free = r.get();
    if (!free && recordings.size() < std::size_t(settings.inFlight)) free = recordings.emplace_back(makeRecording()).get();
    if (!free)
        throw ProbeError(fmt::format("Filter::record: {} recordings are in flight (FilterSettings::inFlight), recording {} has not "
                                     "completed: submit each recording signalling the Completion that record() returned, or raise "
                                     "inFlight",
                                     recordings.size(), done + 1));
    current = free;
    if (slicedUpdate == free) slicedUpdate = nullptr;
}

std::unique_ptr<Recording> Filter::Impl::makeRecording() const {
    auto set = std::make_unique<Recording>();
    Recording& r = *set;
    const FilterSettings& s = settings;
    const Device& d = device;
    const VkDevice vk = d.device();
    r.pyramidBuffer = Buffer(d, plan.pyramidTexels * kTexelBytes, Buffer::Kind::texels);
    r.accumulator = Buffer(d, plan.accumulatorTexels * kTexelBytes, Buffer::Kind::storage);
    r.pyramidView = BufferView(vk, r.pyramidBuffer);
    r.pyramidCounters = Buffer(d, sizeof(uint32_t), Buffer::Kind::storage);
    if (plan.buildsPyramid && plan.sampling == Sampling::hardware) {
        const int mips = plan.pyramidDepth + 1;
        // Written through views of another format (E5B9G9R9 as R32_UINT): a mutable image whose views
        // each name the usage their format supports.
        const VkFormat storeFormat = pyramidStoreFormat(plan.pyramidFormat);
        const bool aliased = storeFormat != plan.pyramidFormat;
        const VkImageUsageFlags sampled = aliased ? VK_IMAGE_USAGE_SAMPLED_BIT : 0, stored = aliased ? VK_IMAGE_USAGE_STORAGE_BIT : 0;
        r.pyramidImage =
            CubeImageResource(d, s.faceSize, mips, plan.pyramidFormat,
                              VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, s.batchSize,
                              aliased ? VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT | VK_IMAGE_CREATE_EXTENDED_USAGE_BIT : 0);
        const uint32_t layers = r.pyramidImage.layers();
        const VkImage image = r.pyramidImage.handle();
        r.pyramidAll = ImageView(vk, image, plan.pyramidFormat, cubeViewType(), 0, uint32_t(mips), layers, sampled);
        for (int k = 0; k < mips; ++k) {
            r.pyramidMipCubes.emplace_back(vk, image, plan.pyramidFormat, cubeViewType(), uint32_t(k), 1, layers, sampled);
            r.pyramidMipArrays.emplace_back(vk, image, storeFormat, VK_IMAGE_VIEW_TYPE_2D_ARRAY, uint32_t(k), 1, layers, stored);
        }
    }
    if (plan.convertOutput) {
        r.intermediate = CubeImageResource(d, s.faceSize, s.levelCount, VK_FORMAT_R32G32B32A32_SFLOAT,
                                           VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, s.batchSize);
        r.packed = CubeImageResource(d, s.faceSize, s.levelCount, VK_FORMAT_R32_UINT,
                                     VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, s.batchSize);
        const uint32_t layers = r.packed.layers();
        for (int m = 0; m < s.levelCount; ++m) {
            r.intermediateMips.emplace_back(vk, r.intermediate.handle(), VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_VIEW_TYPE_2D_ARRAY,
                                            uint32_t(m), 1, layers);
            r.packedMips.emplace_back(vk, r.packed.handle(), VK_FORMAT_R32_UINT, VK_IMAGE_VIEW_TYPE_2D_ARRAY, uint32_t(m), 1, layers);
        }
    }
    // The pyramid's and the map's sets, and per output level its own, a group set and a conversion set.
    r.pool =
        descriptors->makePool(uint32_t(plan.pyramidLevels + plan.pyramidWindows.size() + plan.paraboloidWindows.size() + 3 * s.levelCount));

    const auto segments = [&](const std::vector<std::string>& levelPasses) {
        std::vector<std::string> passes;
        if (pyramid) passes.emplace_back("pyramid");
        passes.insert(passes.end(), levelPasses.begin(), levelPasses.end());
        if (plan.convertOutput) passes.emplace_back("convert");
        return passes;
    };
    std::vector<std::string> perLevel;
    for (int m : plan.computedLevels) perLevel.emplace_back(levelPass(m));
    r.passTimer = std::make_unique<GpuTimer>(d, segments({std::string(methodKindName(s.method.kind))}));
    r.levelTimer = std::make_unique<GpuTimer>(d, segments(perLevel));
    r.sliceTimer = std::make_unique<GpuTimer>(d, std::vector<std::string>{"slice"});
    r.timer = r.passTimer.get();
    return set;
}

void Filter::Impl::firstBarrier(VkCommandBuffer commandBuffer, bool discard) {
    // Exact sampling's counter starts at 0, once per set: each dispatch that counts in it sets it back.
    if (plan.sampling == Sampling::exact && !current->pyramidCountersZeroed) {
        vkCmdFillBuffer(commandBuffer, current->pyramidCounters.handle(), 0, VK_WHOLE_SIZE, 0);
        current->pyramidCountersZeroed = true;
    }
    VkMemoryBarrier memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    memory.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    memory.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    std::vector<VkImageMemoryBarrier> images;
    for (const CubeImageResource* image : {&current->pyramidImage, &current->intermediate, &current->packed}) {
        if (!discard || !image->handle()) continue;
        VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        b.srcAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT;
        b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
        b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        b.image = image->handle();
        b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, uint32_t(image->mips()), 0, image->layers()};
        images.push_back(b);
    }
    const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    vkCmdPipelineBarrier(commandBuffer, stages, stages, 0, 1, &memory, 0, nullptr, uint32_t(images.size()), images.data());
    ++barriers;
}

std::unique_ptr<ComputePipeline> PassContext::pipeline(std::span<const uint32_t> spirv, std::span<const int32_t> specialization) const {
    return std::make_unique<ComputePipeline>(device.device(), layout, spirv, specialization, 0, settings.pipelineCache, settings.batchSize);
}

std::span<const uint32_t> PassContext::batchVariant(std::span<const uint32_t> single, std::span<const uint32_t> batch) const {
    return settings.batchSize > 1 ? batch : single;
}

std::span<const uint32_t> PassContext::groupVariant(std::array<std::span<const uint32_t>, 3> narrow,
                                                    std::array<std::span<const uint32_t>, 3> wide) const {
    return outputVariant(plan.writtenMipCount == kWideWrittenMipCount ? wide : narrow);
}

std::span<const uint32_t> PassContext::outputVariant(std::array<std::span<const uint32_t>, 3> variants) const {
    if (plan.convertOutput) return variants[0];
    switch (settings.outputFormat) {
    case VK_FORMAT_R16G16B16A16_SFLOAT: return variants[1];
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32: return variants[2];
    default: return variants[0];
    }
}

VkImageViewType Filter::Impl::cubeViewType() const {
    return settings.batchSize > 1 ? VK_IMAGE_VIEW_TYPE_CUBE_ARRAY : VK_IMAGE_VIEW_TYPE_CUBE;
}

PassRecorder Filter::Impl::recorder(VkCommandBuffer commandBuffer) { return {commandBuffer, *descriptors, dispatches, barriers}; }

// Every time, not only when the handles change: an image destroyed and another created may reuse a
// handle, and the views of the first would remain.
void Filter::Impl::bindImages(VkImageView source, VkImage output) {
    Recording& r = *current;
    r.pool->reset();
    r.outputMips.clear();
    r.outputMips.resize(settings.levelCount);
    const VkDevice vk = device.device();
    const auto common = [&](VkDescriptorSet set) {
        // A window of the pyramid buffer, which can exceed the storage-buffer range: pass 1's sets bind
        // their own below, and no other pass writes it.
        descriptors->writeBuffer(set, kPyramidBuffer, r.pyramidBuffer.handle(), 0,
                                 std::min<VkDeviceSize>(r.pyramidBuffer.bytes(), device.impl().limits.maxStorageBufferRange));
        descriptors->writeBuffer(set, kAccumulator, r.accumulator.handle());
        descriptors->writeTexelBuffer(set, kGeometry, geometryView.handle());
        descriptors->writeTexelBuffer(set, kTableTexels, tableView.handle());
        descriptors->writeBuffer(set, kTableBuffer, table.handle());
        descriptors->writeBuffer(set, kPyramidCounters, r.pyramidCounters.handle());
        descriptors->writeTexelBuffer(set, kPyramidTexels, r.pyramidView.handle());
        descriptors->writeSampled(set, kSourceCube, source, nearest->handle(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        // Nearest: a device need not filter the placeholder's RGBA32F linearly.
        descriptors->writeSampled(set, kPyramidCube, placeholderCube.handle(), nearest->handle(), VK_IMAGE_LAYOUT_GENERAL);
        descriptors->writeMips(set, std::array{placeholderArray.handle()});
    };
    const bool hardware = plan.buildsPyramid && plan.sampling == Sampling::hardware;
    r.pyramidSets.clear();
    // A set per window of the pyramid buffer: the pyramid's, then the paraboloid map's.
    const auto windowSet = [&](std::size_t first, std::size_t texels) {
        const VkDescriptorSet set = r.pool->allocate();
        common(set);
        descriptors->writeBuffer(set, kPyramidBuffer, r.pyramidBuffer.handle(), first * kTexelBytes, texels * kTexelBytes);
        r.pyramidSets.push_back(set);
    };
    if (pyramid)
        for (const PyramidWindow& w : plan.pyramidWindows) windowSet(w.first, w.texels);
    for (const ParaboloidWindow& w : plan.paraboloidWindows) windowSet(w.first, w.texels);
    if (pyramid && hardware)
        for (int k = 0; k <= plan.pyramidDepth; ++k) {
            const VkDescriptorSet set = r.pool->allocate();
            common(set);
            if (k > 0)
                descriptors->writeSampled(set, kPyramidCube, r.pyramidMipCubes[k - 1].handle(), linear->handle(), VK_IMAGE_LAYOUT_GENERAL);
            // The tail writes its mips (down to the depth); any other dispatch its one mip.
            std::vector<VkImageView> mips{r.pyramidMipArrays[k].handle()};
            if (plan.pyramidTailLevel > 0 && k == plan.pyramidTailLevel)
                for (int e = k + 1; e <= plan.pyramidDepth && e < k + kPyramidTailMipCount; ++e)
                    mips.push_back(r.pyramidMipArrays[e].handle());
            descriptors->writeMips(set, mips);
            r.pyramidSets.push_back(set);
        }
    r.levelSets.assign(settings.levelCount, VK_NULL_HANDLE);
    r.convertSets.assign(settings.levelCount, VK_NULL_HANDLE);
    std::vector<VkImageView> targets(settings.levelCount, VK_NULL_HANDLE); // what pass 2 writes, per level
    const auto levelSet = [&](std::span<const VkImageView> mips) {
        const VkDescriptorSet set = r.pool->allocate();
        common(set);
        if (hardware) descriptors->writeSampled(set, kPyramidCube, r.pyramidAll.handle(), linear->handle(), VK_IMAGE_LAYOUT_GENERAL);
        descriptors->writeMips(set, mips);
        return set;
    };
    for (int m : plan.computedLevels) {
        if (plan.convertOutput) {
            targets[m] = r.intermediateMips[m].handle();
        } else {
            r.outputMips[m] = ImageView(vk, output, settings.outputFormat, VK_IMAGE_VIEW_TYPE_2D_ARRAY, uint32_t(m), 1,
                                        uint32_t(kFaceCount * settings.batchSize));
            targets[m] = r.outputMips[m].handle();
        }
        r.levelSets[m] = levelSet(std::span(&targets[m], 1));
        if (plan.convertOutput) {
            const VkDescriptorSet c = r.pool->allocate();
            common(c);
            descriptors->writeSampled(c, kPyramidCube, r.intermediateMips[m].handle(), nearest->handle(), VK_IMAGE_LAYOUT_GENERAL);
            descriptors->writeMips(c, std::array{r.packedMips[m].handle()});
            r.convertSets[m] = c;
        }
    }
    // From each level of a group, the mips of the group's levels from it on: a run of them (a whole
    // group, or a slice's part of it) binds its first level's set.
    r.groupSets.assign(settings.levelCount, VK_NULL_HANDLE);
    for (const std::vector<int>& group : plan.levelGroups)
        for (std::size_t k = 0; k < group.size(); ++k) {
            std::vector<VkImageView> mips;
            for (std::size_t e = k; e < group.size(); ++e) mips.push_back(targets[group[e]]);
            r.groupSets[group[k]] = mips.size() > 1 ? levelSet(mips) : r.levelSets[group[k]];
        }
    r.boundSource = source;
    r.boundOutput = output;
}

void Filter::Impl::recordLevel(VkCommandBuffer commandBuffer, int m) {
    descriptors->bind(commandBuffer, current->levelSets[m]);
    const std::span<const int> level(&m, 1);
    if (plan.isCopy(m)) copyPass->record(recorder(commandBuffer), m);
    else if (tablePass && !plan.isHandedOff(m)) tablePass->record(recorder(commandBuffer), level);
    else if (fisPass) fisPass->record(recorder(commandBuffer), level);
    else referencePass->record(recorder(commandBuffer), m);
}

std::vector<std::vector<int>> Filter::Impl::dispatchGroups(const std::vector<int>& levels) const {
    const auto holds = [&](int m) { return std::find(levels.begin(), levels.end(), m) != levels.end(); };
    std::vector<std::vector<int>> out;
    for (const std::vector<int>& group : plan.levelGroups)
        for (std::size_t k = 0; k < group.size(); ++k) {
            if (!holds(group[k])) continue;
            if (k == 0 || !holds(group[k - 1])) out.emplace_back();
            out.back().push_back(group[k]);
        }
    return out;
}

void Filter::Impl::recordLevelGroup(VkCommandBuffer commandBuffer, const std::vector<int>& group) {
    if (group.size() == 1) return recordLevel(commandBuffer, group.front());
    descriptors->bind(commandBuffer, current->groupSets[group.front()]);
    if (tablePass && !plan.isHandedOff(group.front())) tablePass->record(recorder(commandBuffer), group);
    else fisPass->record(recorder(commandBuffer), group);
}

std::string_view Filter::Impl::levelPass(int m) const {
    return plan.isHandedOff(m) ? methodKindName(MethodKind::fis) : methodKindName(settings.method.kind);
}

void Filter::Impl::recordPasses(VkCommandBuffer commandBuffer, Timestamps timestamps) {
    dispatches.clear();
    barriers = 0;
    Recording& r = *current;
    const bool perLevel = timestamps == Timestamps::levels;
    r.timed = timestamps != Timestamps::none;
    r.timer = perLevel ? r.levelTimer.get() : r.passTimer.get();
    uint32_t boundary = 0;
    const auto mark = [&] {
        if (r.timed) r.timer->boundary(commandBuffer, boundary++);
    };
    if (r.timed) r.timer->reset(commandBuffer);
    firstBarrier(commandBuffer, true);
    mark();
    if (pyramid) {
        pyramid->record(recorder(commandBuffer), r);
        recorder(commandBuffer).barrier();
        mark();
    }
    // Timed level by level, each level has its own dispatch; otherwise each level group one.
    if (perLevel)
        for (int m : plan.computedLevels) {
            recordLevel(commandBuffer, m);
            mark();
        }
    else {
        for (const std::vector<int>& group : dispatchGroups(plan.computedLevels)) recordLevelGroup(commandBuffer, group);
        mark();
    }
    if (plan.convertOutput) {
        convertPass->record(recorder(commandBuffer), r, r.boundOutput, plan.computedLevels);
        mark();
    }
}

void Filter::Impl::recordSlice(VkCommandBuffer commandBuffer, bool withPyramid, const std::vector<int>& levels, bool timestamps) {
    dispatches.clear();
    barriers = 0;
    Recording& r = *current;
    r.timed = timestamps;
    r.timer = r.sliceTimer.get();
    if (r.timed) r.timer->reset(commandBuffer);
    firstBarrier(commandBuffer, withPyramid); // a level slice reads the pyramid its update's pyramid slice built
    if (r.timed) r.timer->boundary(commandBuffer, 0);
    if (withPyramid && pyramid) {
        pyramid->record(recorder(commandBuffer), r);
        recorder(commandBuffer).barrier();
    }
    for (const std::vector<int>& group : dispatchGroups(levels)) recordLevelGroup(commandBuffer, group);
    if (convertPass && !levels.empty()) convertPass->record(recorder(commandBuffer), r, r.boundOutput, levels);
    if (r.timed) r.timer->boundary(commandBuffer, 1);
}

Filter::Filter(const Device& device, const FilterSettings& settings) {
    device.impl().releaseRetired();
    impl_ = std::make_unique<Impl>(device, settings, VK_NULL_HANDLE);
}
Filter::Filter(const Device& device, const FilterSettings& settings, VkCommandBuffer initialization) {
    if (initialization == VK_NULL_HANDLE) throw ProbeError("Filter: the initialization command buffer is VK_NULL_HANDLE");
    device.impl().releaseRetired();
    impl_ = std::make_unique<Impl>(device, settings, initialization);
}

// A recording still in flight keeps every resource it reads: the Device releases them once it has
// completed, rather than this waiting on the queue.
Filter::~Filter() {
    if (!impl_ || impl_->completedValue() >= impl_->recorded) return;
    const VkSemaphore semaphore = impl_->completed;
    const uint64_t value = impl_->recorded;
    Device::Impl& device = impl_->device.impl();
    device.retire(std::shared_ptr<void>(std::move(impl_)), semaphore, value);
}

namespace {

// record()'s checks of what the engine gives it, each naming the field.
void checkRecordArguments(const Filter::Impl& f, VkCommandBuffer commandBuffer, const SourceCube& source, const OutputCube& output) {
    const auto refuse = [](const std::string& field, const std::string& problem) {
        return ProbeError(fmt::format("Filter::record: {} {}", field, problem));
    };
    const uint32_t faceSize = static_cast<uint32_t>(f.settings.faceSize), levelCount = static_cast<uint32_t>(f.settings.levelCount);
    const uint32_t layers = uint32_t(kFaceCount * f.settings.batchSize);
    const bool batch = f.settings.batchSize > 1;
    if (commandBuffer == VK_NULL_HANDLE) throw refuse("commandBuffer", "is VK_NULL_HANDLE");
    if (source.view == VK_NULL_HANDLE) throw refuse("source.view", "is VK_NULL_HANDLE");
    if (source.viewType != f.cubeViewType())
        throw refuse("source.viewType",
                     fmt::format("is {}, not {} ({}): the passes read a {}", int(source.viewType),
                                 batch ? "VK_IMAGE_VIEW_TYPE_CUBE_ARRAY" : "VK_IMAGE_VIEW_TYPE_CUBE", int(f.cubeViewType()),
                                 batch ? fmt::format("cube-map array view of the batch's {} probes", f.settings.batchSize) : "cube view"));
    if (source.arrayLayers != layers)
        throw refuse("source.arrayLayers", fmt::format("is {}, but the filter reads {} (6 per probe of a batch of {})", source.arrayLayers,
                                                       layers, f.settings.batchSize));
    if (source.faceSize != faceSize)
        throw refuse("source.faceSize", fmt::format("is {}, but the filter was built for S_0 = {}", source.faceSize, faceSize));
    if (!(f.device.impl().features(source.format) & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
        throw refuse("source.format",
                     fmt::format("{} cannot be sampled on {} (sampled image usage)", int(source.format), f.device.info().name));
    if (output.image == VK_NULL_HANDLE) throw refuse("output.image", "is VK_NULL_HANDLE");
    if (output.format != f.settings.outputFormat)
        throw refuse("output.format",
                     fmt::format("is {}, but the filter was built for {}", formatName(output.format), formatName(f.settings.outputFormat)));
    if (output.faceSize != faceSize)
        throw refuse("output.faceSize", fmt::format("is {}, but the filter was built for S_0 = {}", output.faceSize, faceSize));
    if (output.mipLevels < levelCount)
        throw refuse("output.mipLevels", fmt::format("is {}, but the filter writes {} levels", output.mipLevels, levelCount));
    if (output.arrayLayers != layers)
        throw refuse("output.arrayLayers", fmt::format("is {}, but the filter writes {} (6 per probe of a batch of {})", output.arrayLayers,
                                                       layers, f.settings.batchSize));
    const VkImageUsageFlags written = f.plan.convertOutput ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : VK_IMAGE_USAGE_STORAGE_BIT;
    if ((output.usage & written) == 0)
        throw refuse("output.usage", f.plan.convertOutput ? "lacks TRANSFER_DST, which a B10G11R11 output on this device is written by"
                                                          : "lacks STORAGE, which the passes write the output with");
}

// The texel-taps of output level m (Filter::slices).
double levelTexelTaps(const Filter::Impl& f, int m) {
    const FilterSettings& s = f.settings;
    const double texels = double(texelCount(s.faceSize >> m)) * s.batchSize;
    if (f.plan.isCopy(m)) return texels;
    switch (s.method.kind) {
    case MethodKind::table:
        if (f.plan.isHandedOff(m)) return texels * s.method.table->levels[m].fisSamples;
        return texels * tapsInUse(*s.method.table, m) * (2.0 + 7.0 / 16.0);
    case MethodKind::fis: return texels * s.method.fis.samplesAt(m);
    case MethodKind::reference: break;
    }
    return texels * double(texelCount(s.faceSize));
}

// The dispatches of pass 2 (and the conversion) over `levels`, as recordSlice records them.
uint32_t levelsDispatchCount(const Filter::Impl& f, const std::vector<int>& levels) {
    uint32_t count = f.plan.convertOutput ? uint32_t(levels.size()) : 0u;
    for (const std::vector<int>& group : f.dispatchGroups(levels)) {
        const int m = group.front();
        count += group.size() == 1 && !f.plan.isCopy(m) && f.referencePass ? f.referencePass->dispatchCount() : 1u;
    }
    return count;
}

// A set for a recording from `source` to `output`, bound; its descriptor sets and views are the
// recording's until it completes.
void startRecording(Filter::Impl& f, const SourceCube& source, const OutputCube& output) {
    f.device.impl().releaseRetired();
    f.acquire();
    f.bindImages(source.view, output.image);
}

// The recording's number, which its completion signals.
Completion finishRecording(Filter::Impl& f) {
    f.current->timer->clear();
    f.current->completion = ++f.recorded;
    return {f.completed, f.recorded};
}

} // namespace

Completion Filter::record(VkCommandBuffer commandBuffer, const SourceCube& source, const OutputCube& output, Timestamps timestamps) {
    Impl& f = *impl_;
    checkRecordArguments(f, commandBuffer, source, output);
    startRecording(f, source, output);
    f.recordPasses(commandBuffer, timestamps);
    return finishRecording(f);
}

Completion Filter::record(VkCommandBuffer commandBuffer, const std::vector<SourceCube>& sources, const std::vector<OutputCube>& outputs,
                          Timestamps timestamps) {
    Impl& f = *impl_;
    checkSeparateCubes(f, commandBuffer, sources, outputs);
    f.device.impl().releaseRetired();
    f.acquire();
    makeSeparateCubeImages(f, sources.front().format);
    f.bindImages(f.current->copySourceView.handle(), f.current->runOutput.handle());
    copySourcesIn(f, commandBuffer, sources);
    f.recordPasses(commandBuffer, timestamps);
    copyOutputsOut(f, commandBuffer, outputs);
    f.barriers += 3; // the copies': two before the passes, one after
    return finishRecording(f);
}

std::vector<Slice> Filter::slices(int count) const {
    const Impl& f = *impl_;
    if (count < 1) throw ProbeError(fmt::format("Filter::slices: count {} is below 1", count));
    std::vector<Slice> out;
    if (f.pyramid) out.push_back({true, {}, f.pyramid->dispatchCount(), f.pyramid->texelTaps()});
    if (count == 1) { // the whole update, pass 1 and every level
        if (out.empty()) out.push_back({});
        for (int m : f.plan.computedLevels) {
            out.back().levels.push_back(m);
            out.back().texelTaps += levelTexelTaps(f, m);
        }
        out.back().dispatches += levelsDispatchCount(f, out.back().levels);
        return out;
    }
    double total = 0.0;
    for (int m : f.plan.computedLevels) total += levelTexelTaps(f, m);
    const int levelSlices = std::max(1, count - int(out.size()));
    // Cut the levels, in order, where their running texel-taps pass each k / levelSlices of the total.
    double done = 0.0;
    for (int m : f.plan.computedLevels) {
        const int k = std::min(levelSlices - 1, int(done * levelSlices / std::max(total, 1e-300)));
        if (out.empty() || out.back().pyramid || int(out.size()) - (f.pyramid ? 1 : 0) <= k) out.push_back({});
        out.back().levels.push_back(m);
        out.back().texelTaps += levelTexelTaps(f, m);
        done += levelTexelTaps(f, m);
    }
    for (Slice& slice : out) slice.dispatches += levelsDispatchCount(f, slice.levels);
    return out;
}

Completion Filter::record(VkCommandBuffer commandBuffer, const SourceCube& source, const OutputCube& output, const Slice& slice,
                          Timestamps timestamps) {
    Impl& f = *impl_;
    checkRecordArguments(f, commandBuffer, source, output);
    for (std::size_t k = 0; k < slice.levels.size(); ++k)
        if (std::find(f.plan.computedLevels.begin(), f.plan.computedLevels.end(), slice.levels[k]) == f.plan.computedLevels.end() ||
            (k > 0 && slice.levels[k] <= slice.levels[k - 1]))
            throw ProbeError(fmt::format(
                "Filter::record: slice.levels: {} is not one of the levels the filter computes, in ascending order", slice.levels[k]));
    if (slice.pyramid || !f.pyramid) {
        startRecording(f, source, output);
        f.slicedUpdate = f.pyramid ? f.current : nullptr;
    } else {
        // The levels read the pyramid that the update's first slice built, in that slice's set: its
        // descriptor sets are read again, not rewritten, so the earlier slices may still be pending.
        Recording* update = f.slicedUpdate;
        if (!update)
            throw ProbeError("Filter::record: slice: a slice of levels with no pyramid slice before it whose set is still its "
                             "update's (record the slices of Filter::slices in order; a later whole recording may take that set)");
        if (update->boundSource != source.view || update->boundOutput != output.image)
            throw ProbeError("Filter::record: slice: the source or output cube differs from the one its update's pyramid slice "
                             "recorded");
        f.device.impl().releaseRetired();
        f.current = update;
    }
    f.recordSlice(commandBuffer, slice.pyramid, slice.levels, timestamps != Timestamps::none);
    return finishRecording(f);
}

Sampling Filter::sampling() const { return impl_->plan.sampling; }
VkFormat Filter::pyramidFormat() const {
    return impl_->plan.sampling == Sampling::hardware ? impl_->plan.pyramidFormat : VK_FORMAT_R32G32B32A32_SFLOAT;
}
bool Filter::outputNeedsTransfer() const { return impl_->plan.convertOutput; }

VkImageCreateInfo Filter::outputImageInfo() const {
    const FilterSettings& s = impl_->settings;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.flags = VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = s.outputFormat;
    info.extent = {uint32_t(s.faceSize), uint32_t(s.faceSize), 1};
    info.mipLevels = uint32_t(s.levelCount);
    info.arrayLayers = uint32_t(kFaceCount * s.batchSize);
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | (impl_->plan.convertOutput ? VK_IMAGE_USAGE_TRANSFER_DST_BIT : VK_IMAGE_USAGE_STORAGE_BIT);
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    return info;
}

std::vector<PassTime> Filter::timings() const {
    // After record(), the caller's submission has completed when this is called.
    const Recording& r = *impl_->current;
    if (!r.timed) return {};
    if (r.timer->timings().empty()) r.timer->collect();
    return r.timer->timings();
}

std::vector<PassTime> Filter::levelTimings() const {
    const Recording& r = *impl_->current;
    if (!r.timed || r.timer != r.levelTimer.get()) return {};
    std::vector<std::string> names;
    if (impl_->pyramid) names.push_back("pass 1");
    for (int m : impl_->plan.computedLevels) names.push_back(fmt::format("level {}", m));
    if (impl_->plan.convertOutput) names.push_back("convert");
    std::vector<PassTime> segments = r.timer->segmentTimings(names);
    std::erase_if(segments, [](const PassTime& p) { return p.name == "pass 1" || p.name == "convert"; });
    return segments;
}

const std::vector<Dispatch>& Filter::dispatches() const { return impl_->dispatches; }
int Filter::barriers() const { return impl_->barriers; }

CubeLevels filterProbe(const Device& device, const FilterSettings& settings, const CubeImage& source) {
    Filter filter(device, settings);
    return filter.run(source);
}

} // namespace probe::gpu
