// Filter: buffers, pipelines, the order of the passes, upload and read-back, the engine path.
#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "device.h"
#include "filter_impl.h"
#include "probe/error.h"
#include "vulkan_check.h"

namespace probe::gpu {

namespace {

constexpr VkDeviceSize kTexelBytes = 4 * sizeof(float); // RGBA32F

// First texel of each level of a packed cube with `levels` levels from `baseSize`, and the total.
std::vector<uint32_t> packedOffsets(int baseSize, int levels) {
    std::vector<uint32_t> offsets{0};
    for (int m = 0; m < levels; ++m) offsets.push_back(offsets.back() + static_cast<uint32_t>(texelCount(baseSize >> m)));
    return offsets;
}

// First texel of each level of the bordered pyramid (buffer.h), and the total.
std::vector<uint32_t> pyramidOffsetsFor(int baseSize, int levels) {
    std::vector<uint32_t> offsets{0};
    for (int m = 0; m < levels; ++m) offsets.push_back(offsets.back() + static_cast<uint32_t>(pyramidLevelTexels(baseSize >> m)));
    return offsets;
}

// The timed segments, named by their pass: pass 1 where there is one, then each output level of pass 2.
std::vector<std::string> segmentPasses(Method method, bool pyramid, std::size_t levelCount) {
    std::vector<std::string> passes;
    if (pyramid) passes.push_back("pyramid");
    passes.resize(passes.size() + levelCount, std::string(methodName(method)));
    return passes;
}

// Per pyramid level: the unit texel-centre directions and exact solid angles, from probecore.
std::vector<float> geometryTexels(int baseSize, int levels) {
    std::vector<float> texels;
    for (int m = 0; m < levels; ++m) {
        const CubeGeometry geometry(baseSize >> m);
        for (std::size_t t = 0; t < geometry.directions.size(); ++t)
            for (double value : {geometry.directions[t].x, geometry.directions[t].y, geometry.directions[t].z, geometry.solidAngles[t]})
                texels.push_back(static_cast<float>(value));
    }
    return texels;
}

// The levels of a packed RGBA cube (see packedOffsets), RGB only; the levels not in `wanted` empty.
CubeLevels unpackLevels(const float* texels, const std::vector<uint32_t>& offsets, int baseSize, const std::vector<int>& wanted) {
    CubeLevels result(offsets.size() - 1);
    for (int m : wanted) {
        CubeImage& level = result[m];
        level = CubeImage(baseSize >> m);
        const float* first = texels + 4 * std::size_t(offsets[m]);
        for (std::size_t t = 0; t < texelCount(level.size); ++t) level.set(t, {first[4 * t], first[4 * t + 1], first[4 * t + 2]});
    }
    return result;
}

// The levels 0..depth of the pyramid buffer, inside the faces.
CubeLevels unpackPyramid(const float* texels, const std::vector<uint32_t>& offsets, int baseSize, int depth) {
    CubeLevels result;
    for (int m = 0; m <= depth; ++m) {
        CubeImage level(baseSize >> m);
        const float* first = texels + 4 * std::size_t(offsets[m]);
        for (int f = 0; f < kFaceCount; ++f)
            for (int j = 0; j < level.size; ++j)
                for (int i = 0; i < level.size; ++i) {
                    const float* c = first + 4 * pyramidTexelIndex(f, i, j, level.size);
                    level.set(texelIndex({f, i, j}, level.size), {c[0], c[1], c[2]});
                }
        result.push_back(std::move(level));
    }
    return result;
}

void checkTransferFormat(const Device& device) {
    VkFormatProperties properties;
    vkGetPhysicalDeviceFormatProperties(device.physicalDevice(), VK_FORMAT_R32G32B32A32_SFLOAT, &properties);
    const VkFormatFeatureFlags needed = VK_FORMAT_FEATURE_TRANSFER_SRC_BIT | VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
    if ((properties.optimalTilingFeatures & needed) != needed)
        throw ProbeError(fmt::format("Vulkan: {} cannot copy R32G32B32A32_SFLOAT images to and from buffers (format features {:#x})",
                                     device.info().name, properties.optimalTilingFeatures));
}

} // namespace

Filter::Impl::Impl(const Device& d, const FilterSettings& s) : device(d), settings(s) {
    validateSizeAndLevels(s.faceSize, s.levelCount);
    pyramidLevels = pyramidLevelCount(s.faceSize);
    pyramidDepth = s.pyramidDepth < 0 ? pyramidLevels - 1 : s.pyramidDepth;
    if (pyramidDepth > pyramidLevels - 1)
        throw ProbeError(fmt::format("pyramid depth {}: a {}^2 pyramid has levels 1..{} below the source", s.pyramidDepth, s.faceSize,
                                     pyramidLevels - 1));
    for (int m = 0; m < s.levelCount; ++m) levels.push_back(m);
    if (!s.levels.empty()) {
        for (std::size_t k = 0; k < s.levels.size(); ++k)
            if (s.levels[k] < 0 || s.levels[k] >= s.levelCount || (k > 0 && s.levels[k] <= s.levels[k - 1]))
                throw ProbeError(fmt::format("output levels: {} is not one of 0..{} in ascending order", s.levels[k], s.levelCount - 1));
        levels = s.levels;
    }
    pyramidOffsets = pyramidOffsetsFor(s.faceSize, pyramidLevels);
    outputOffsets = packedOffsets(s.faceSize, s.levelCount);
    for (int m = 0; m < s.levelCount; ++m)
        if (levelAlpha(s.mapping, m, s.levelCount) <= 0.0) copyLevels |= 1u << m;

    std::vector<float> tableData(4, 0.0f);
    switch (s.method) {
    case Method::table:
        if (!s.table) throw ProbeError("method table: no tap table given");
        checkTableFits(*s.table, s);
        tableData = tableBufferData(*s.table);
        tableTaps = s.table->taps;
        tableCoefficientCount = coefficientCount(s.table->form);
        tableUsageFirst = gpu::tableUsageFirst(*s.table);
        break;
    case Method::fis: tableData = importanceSamplingBufferData(s, sampleOffsets); break;
    case Method::reference: break;
    }
    const std::vector<float> geometryData = geometryTexels(s.faceSize, pyramidLevels);

    pyramid = Buffer(d, pyramidOffsets.back() * kTexelBytes, Buffer::Kind::storage);
    output = Buffer(d, outputOffsets.back() * kTexelBytes, Buffer::Kind::storage);
    geometry = Buffer(d, geometryData.size() * sizeof(float), Buffer::Kind::storage);
    table = Buffer(d, tableData.size() * sizeof(float), Buffer::Kind::storage);

    layout = std::make_unique<PipelineLayout>(d, std::array<const Buffer*, kBufferCount>{&pyramid, &output, &geometry, &table});
    switch (s.method) {
    case Method::table: {
        if (!d.impl().computeSubgroupVote)
            throw ProbeError(
                fmt::format("Vulkan: {} has no subgroup vote operations in compute shaders, which the table method needs", d.info().name));
        const std::array<int32_t, 1> form{tableCoefficientCount}; // table_filter.comp's kCoefficientCount
        pass2 = std::make_unique<ComputePipeline>(d.device(), *layout, tableSpirv(), form);
        break;
    }
    case Method::fis: pass2 = std::make_unique<ComputePipeline>(d.device(), *layout, importanceSamplingSpirv()); break;
    case Method::reference: pass2 = std::make_unique<ComputePipeline>(d.device(), *layout, referenceSpirv()); break;
    }
    const bool readsPyramid = std::any_of(levels.begin(), levels.end(), [&](int m) { return (copyLevels & (1u << m)) == 0; });
    if (s.method != Method::reference && readsPyramid) {
        pass1 = std::make_unique<ComputePipeline>(d.device(), *layout, pyramidSpirv(), pyramidSpecialization(s.pyramid));
        pass1Corners = std::make_unique<ComputePipeline>(d.device(), *layout, pyramidCornersSpirv());
    }
    if (std::any_of(levels.begin(), levels.end(), [&](int m) { return (copyLevels & (1u << m)) != 0; }))
        copy = std::make_unique<ComputePipeline>(d.device(), *layout, copyLevelSpirv());
    timer = std::make_unique<GpuTimer>(d, segmentPasses(s.method, pass1 != nullptr, levels.size()));

    submission = std::make_unique<Submission>(d);
    submission->upload(geometry, geometryData.data(), geometry.bytes());
    submission->upload(table, tableData.data(), table.bytes());
}

void Filter::Impl::recordPasses(VkCommandBuffer commandBuffer) {
    dispatches.clear();
    timer->reset(commandBuffer);
    computeBarrier(commandBuffer);
    layout->bind(commandBuffer);
    uint32_t boundary = 0;
    timer->boundary(commandBuffer, boundary++);
    if (pass1) {
        recordPyramidPass(*this, commandBuffer);
        computeBarrier(commandBuffer);
        timer->boundary(commandBuffer, boundary++);
    }
    for (int m : levels) {
        if (copyLevels & (1u << m)) recordCopyLevel(*this, commandBuffer, m);
        else if (settings.method == Method::table) recordTableLevel(*this, commandBuffer, m);
        else if (settings.method == Method::fis) recordImportanceSamplingLevel(*this, commandBuffer, m);
        else recordReferenceLevel(*this, commandBuffer, m);
        timer->boundary(commandBuffer, boundary++);
    }
    computeBarrier(commandBuffer);
}

Filter::Filter(const Device& device, const FilterSettings& settings) : impl_(std::make_unique<Impl>(device, settings)) {}
Filter::~Filter() = default;

CubeLevels Filter::run(const CubeImage& source, int repeat) {
    Impl& f = *impl_;
    if (source.size != f.settings.faceSize)
        throw ProbeError(fmt::format("filter: the probe has face size {}, the filter was built for {}", source.size, f.settings.faceSize));
    if (repeat < 1) throw ProbeError(fmt::format("--repeat {}: must be at least 1", repeat));

    const std::vector<float> texels = borderedRgbaTexels(source); // pass 1 writes the border again, as for record()
    f.submission->upload(f.pyramid, texels.data(), texels.size() * sizeof(float));

    VkCommandBuffer passes = f.submission->begin();
    f.recordPasses(passes);
    vkCheck(vkEndCommandBuffer(passes), "vkEndCommandBuffer");
    f.timer->clear();
    for (int k = 0; k < repeat; ++k) {
        f.submission->submitAndWait(passes, false);
        f.timer->collect();
    }
    f.submission->release(passes);

    std::vector<float> output(f.output.bytes() / sizeof(float));
    f.submission->download(f.output, output.data(), f.output.bytes());
    return unpackLevels(output.data(), f.outputOffsets, f.settings.faceSize, f.levels);
}

void Filter::record(VkCommandBuffer commandBuffer, VkImage sourceCube, VkImage outputCube) {
    Impl& f = *impl_;
    checkTransferFormat(f.device);
    const auto size = static_cast<uint32_t>(f.settings.faceSize);
    VkBufferImageCopy in{}; // into the faces of pyramid level 0, inside their borders
    in.bufferOffset = pyramidTexelIndex(0, 0, 0, f.settings.faceSize) * kTexelBytes;
    in.bufferRowLength = size + 2;
    in.bufferImageHeight = size + 2;
    in.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, kFaceCount};
    in.imageExtent = {size, size, 1};
    vkCmdCopyImageToBuffer(commandBuffer, sourceCube, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, f.pyramid.handle(), 1, &in);
    f.recordPasses(commandBuffer);
    std::vector<VkBufferImageCopy> out;
    for (int m : f.levels) {
        VkBufferImageCopy region{};
        region.bufferOffset = f.outputOffsets[m] * kTexelBytes;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, static_cast<uint32_t>(m), 0, kFaceCount};
        region.imageExtent = {size >> m, size >> m, 1};
        out.push_back(region);
    }
    vkCmdCopyBufferToImage(commandBuffer, f.output.handle(), outputCube, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           static_cast<uint32_t>(out.size()), out.data());
    f.timer->clear();
}

std::vector<PassTime> Filter::timings() const {
    // After record(), the caller's submission has completed when this is called.
    if (impl_->timer->timings().empty()) impl_->timer->collect();
    return impl_->timer->timings();
}

std::vector<PassTime> Filter::levelTimings() const {
    if (impl_->timer->timings().empty()) impl_->timer->collect();
    std::vector<std::string> names;
    if (impl_->pass1) names.push_back("pyramid");
    for (int m : impl_->levels) names.push_back(fmt::format("level {}", m));
    std::vector<PassTime> segments = impl_->timer->segmentTimings(names);
    if (impl_->pass1 && !segments.empty()) segments.erase(segments.begin());
    return segments;
}

const std::vector<Dispatch>& Filter::dispatches() const { return impl_->dispatches; }

CubeLevels Filter::downloadPyramid() const {
    Impl& f = *impl_;
    if (!f.pass1) return {};
    std::vector<float> texels(f.pyramid.bytes() / sizeof(float));
    f.submission->download(f.pyramid, texels.data(), f.pyramid.bytes());
    return unpackPyramid(texels.data(), f.pyramidOffsets, f.settings.faceSize, f.pyramidDepth);
}

std::string_view methodName(Method method) {
    switch (method) {
    case Method::table: return "table";
    case Method::fis: return "fis";
    default: return "reference";
    }
}

Method parseMethod(std::string_view name) {
    for (Method m : {Method::table, Method::fis, Method::reference})
        if (methodName(m) == name) return m;
    throw ProbeError(fmt::format("--method {}: expected table, fis or reference", name));
}

} // namespace probe::gpu
