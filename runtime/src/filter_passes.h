// The passes of a probe::gpu::Filter, each a small object that owns its pipelines and records its
// dispatches (one per file: pyramid_pass.cpp; for pass 2, copy_level_pass.cpp, reference_pass.cpp,
// table_pass.cpp, fis_pass.cpp; then convert_pass.cpp). Each is built from a PassContext (the device,
// the settings and their plan) and records through a PassRecorder into one recording's descriptor
// sets; none reaches into the Filter.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compute_pipeline.h"
#include "filter_descriptors.h"
#include "filter_plan.h"
#include "probe/runtime.h"

namespace probe::gpu {

struct Recording;

// What the passes are built from.
struct PassContext {
    const Device& device;
    const FilterSettings& settings;
    const FilterPlan& plan;
    VkPipelineLayout layout; // the Filter's one layout (filter_descriptors.h)

    // A pipeline of the Filter's layout, through the settings' pipeline cache, for its batch size.
    std::unique_ptr<ComputePipeline> pipeline(std::span<const uint32_t> spirv, std::span<const int32_t> specialization = {}) const;
    // A shader's SPIR-V, or its batch variant (shaders/batch.glsl) for a batch.
    std::span<const uint32_t> batchVariant(std::span<const uint32_t> single, std::span<const uint32_t> batch) const;
    // The SPIR-V of a pass-2 shader for the output format: `variants` holds the RGBA32F, RGBA16F and
    // B10G11R11 builds, in that order (the conversion pass's input is RGBA32F).
    std::span<const uint32_t> outputVariant(std::array<std::span<const uint32_t>, 3> variants) const;
    // The same for a level-group shader (level_group.glsl) and the plan's group width: `narrow` holds
    // the builds of groups of kWrittenMipCount levels, `wide` of kWideWrittenMipCount.
    std::span<const uint32_t> groupVariant(std::array<std::span<const uint32_t>, 3> narrow,
                                           std::array<std::span<const uint32_t>, 3> wide) const;
};

// Where a pass records: the command buffer, the descriptor sets it binds, and the log of the
// recording's dispatches and the barriers between them (Filter::dispatches(), barriers()).
struct PassRecorder {
    VkCommandBuffer commandBuffer;
    const FilterDescriptors& descriptors;
    std::vector<Dispatch>& dispatches;
    int& barriers;

    void bind(VkDescriptorSet set) const { descriptors.bind(commandBuffer, set); }
    // A compute barrier of the passes (computeBarrier), counted.
    void barrier() const {
        computeBarrier(commandBuffer);
        ++barriers;
    }
    // A dispatch of `pipeline` with push constants `constants`, `groups` workgroups in each of `layers`
    // layers, logged as writing `levels` levels from `level`.
    template <typename Constants>
    void dispatch(const ComputePipeline& pipeline, std::string_view pass, int level, const Constants& constants, uint32_t groups,
                  uint32_t layers = 1, int levels = 1) const {
        static_assert(sizeof(Constants) <= kPushConstantBytes);
        pipeline.dispatch(commandBuffer, std::as_bytes(std::span(&constants, 1)), groups, layers);
        dispatches.push_back({std::string(pass), level, groups * layers, levels});
    }
};

// Pass 1: the pyramid from the source (the reference: its level 0 alone, the source it reads texel by
// texel), through the recording's pyramid sets (Recording::pyramidSets).
class PyramidPass {
public:
    explicit PyramidPass(const PassContext& context);
    void record(const PassRecorder& recorder, const Recording& recording) const;
    // What record() dispatches and its texel-taps (Filter::slices), known before it records.
    uint32_t dispatchCount() const;
    double texelTaps() const;

private:
    void recordBorderedLevels(const PassRecorder& recorder, const Recording& recording) const;
    void recordMips(const PassRecorder& recorder, const Recording& recording) const;

    PassContext context_;
    std::unique_ptr<ComputePipeline> levels_;        // a level (exact: a window of one), or hardware's mip
    std::unique_ptr<ComputePipeline> tail_;          // the levels from plan.pyramidTailLevel down, in one workgroup
    std::unique_ptr<ComputePipeline> paraboloidMap_; // fis on a paraboloid map: its levels, after the source's level
};

// Pass 2 at the levels with alpha = 0, for every method: a copy of the source, dispatched under the
// method's pass name.
class CopyLevelPass {
public:
    explicit CopyLevelPass(const PassContext& context);
    void record(const PassRecorder& recorder, int level) const;

private:
    PassContext context_;
    std::unique_ptr<ComputePipeline> pipeline_;
};

// The exact reference: per output level, a dispatch per chunk of source rows (dispatchCount()).
class ReferencePass {
public:
    explicit ReferencePass(const PassContext& context);
    void record(const PassRecorder& recorder, int level) const;
    uint32_t dispatchCount() const; // per level

private:
    PassContext context_;
    std::unique_ptr<ComputePipeline> pipeline_;
};

// The table buffer: every level in the published layout, level 0 first, then per level the tap
// groups of four in use.
std::vector<float> tableBufferData(const TapTable& table);
uint32_t tableUsageFirst(const TapTable& table); // in vec4s, within tableBufferData

// The tap table at a group of consecutive output levels (FilterPlan::levelGroups), bound to a set
// whose written mips are theirs in order, in one dispatch.
class TablePass {
public:
    explicit TablePass(const PassContext& context);
    void record(const PassRecorder& recorder, std::span<const int> levels) const;

private:
    PassContext context_;
    std::unique_ptr<ComputePipeline> pipeline_;
    uint32_t usageFirst_; // where the per-level tap group counts start in the table buffer
};

// FIS's part of the table buffer: every output level's samples (probe::fisSamplesPerLevel, or a
// table's handOffSamples, empty at the other levels) appended to `data` as vec4(direction in the
// tangent frame, pyramid level); returns each level's first sample (in vec4s, within `data`) and
// the end.
std::vector<uint32_t> appendFisSamples(const std::vector<std::vector<Tap>>& perLevel, std::vector<float>& data);

// FIS at a group of consecutive output levels, as TablePass: the FIS method's, or a table's levels
// handed to FIS; `sampleOffsets` from appendFisSamples.
class FisPass {
public:
    FisPass(const PassContext& context, std::vector<uint32_t> sampleOffsets);
    void record(const PassRecorder& recorder, std::span<const int> levels) const;

private:
    PassContext context_;
    std::unique_ptr<ComputePipeline> pipeline_;
    std::vector<uint32_t> sampleOffsets_;
};

// The conversion of a B10G11R11 output on a device that cannot store it: each output level computed
// packed into the recording's `packed` image, then copied into `output` (in
// VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL).
class ConvertPass {
public:
    explicit ConvertPass(const PassContext& context);
    void record(const PassRecorder& recorder, const Recording& recording, VkImage output, const std::vector<int>& levels) const;

private:
    PassContext context_;
    std::unique_ptr<ComputePipeline> pipeline_;
};

// A level group's workgroup ends in its grid (shaders/level_group.glsl): level k's groupsOf(level)
// workgroups after level k - 1's; the unused slots repeat the last end.
template <typename GroupsOf>
std::array<uint32_t, kWideWrittenMipCount> levelGroupEnds(std::span<const int> levels, GroupsOf groupsOf) {
    std::array<uint32_t, kWideWrittenMipCount> ends{};
    uint32_t end = 0;
    for (std::size_t k = 0; k < ends.size(); ++k) {
        if (k < levels.size()) end += groupsOf(levels[k]);
        ends[k] = end;
    }
    return ends;
}

} // namespace probe::gpu
