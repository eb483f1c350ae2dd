// The state of a probe::gpu::Filter, shared by the pass recorders.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "buffer.h"
#include "compute_pipeline.h"
#include "filter_descriptors.h"
#include "filter_plan.h"
#include "gpu_timer.h"
#include "image.h"
#include "probe/runtime.h"
#include "submission.h"

namespace probe::gpu {

// What one recording writes, and the views and descriptor sets it binds: the Filter makes up to
// FilterSettings::inFlight of them as recordings need them, so that so many may be pending at once.
// Each recording (each pyramid slice) takes its images from VK_IMAGE_LAYOUT_UNDEFINED, whose
// contents it makes anew.
struct Recording {
    Buffer pyramidBuffer; // exact sampling, and level 0 alone for the reference
    Buffer accumulator;   // the reference's running sums, or the paraboloid map (one vec4 when unused)
    BufferView pyramidView;
    CubeImageResource pyramidImage;          // hardware sampling: mips 0..pyramidDepth
    ImageView pyramidAll;                    // cube, every mip: pass 2 reads
    std::vector<ImageView> pyramidMipCubes;  // cube, mip k alone: pass 1 reads it for level k + 1
    std::vector<ImageView> pyramidMipArrays; // 2D array, mip k: pass 1 writes
    CubeImageResource intermediate, packed;  // conversion: pass 2's RGBA32F output and the R32_UINT words
    std::vector<ImageView> intermediateMips, packedMips;

    // The source and output that the descriptor sets refer to: the caller's (or run()'s).
    VkImageView boundSource = VK_NULL_HANDLE;
    VkImage boundOutput = VK_NULL_HANDLE;
    std::vector<ImageView> outputMips; // views of the bound output (or of `intermediate`), per output level
    std::unique_ptr<DescriptorPool> pool;
    // Pass 1's: per pyramid window (FilterPlan::pyramidWindows) with exact sampling, per pyramid level
    // 0..pyramidDepth with hardware sampling.
    std::vector<VkDescriptorSet> pyramidSets;
    std::vector<VkDescriptorSet> levelSets;   // per output level
    std::vector<VkDescriptorSet> groupSets;   // per output level: the set of the level group it starts (its levels' mips)
    std::vector<VkDescriptorSet> convertSets; // per output level

    std::unique_ptr<GpuTimer> passTimer;  // a segment per pass
    std::unique_ptr<GpuTimer> levelTimer; // pass 2 in a segment per output level
    std::unique_ptr<GpuTimer> sliceTimer; // a slice in one segment
    GpuTimer* timer = nullptr;            // the one the last recording wrote
    bool timed = true;                    // the last recording wrote timestamp queries

    uint64_t completion = 0; // the semaphore value that ends its last recording; 0: none pending

    // The tools' own source and output cubes (run()), a cube-map array for a batch, made at the set's
    // first run().
    CubeImageResource runSource, runOutput;
    ImageView runSourceView;
};

struct Filter::Impl {
    const Device& device;
    FilterSettings settings;
    const FilterPlan plan;

    // Buffers (shaders/buffers.glsl) that every recording reads and none writes.
    Buffer geometry; // per pyramid level, (texel direction, solid angle)
    BufferView geometryView;
    Buffer table; // tap table or FIS samples (one vec4 when unused)
    BufferView tableView;
    std::unique_ptr<Sampler> linear, nearest;
    // A 1x1 cube for the image bindings that a set's dispatches do not read: every binding of a set
    // holds a valid descriptor (Mesa's lavapipe reads them all when a set is bound).
    CubeImageResource placeholder;
    ImageView placeholderCube, placeholderArray;

    std::unique_ptr<FilterDescriptors> descriptors;
    // The sets of what one recording writes (at most FilterSettings::inFlight), used in turn; `current`
    // is the last recording's.
    std::vector<std::unique_ptr<Recording>> recordings;
    Recording* current = nullptr;
    Recording* slicedUpdate = nullptr; // the set of the last pyramid slice, until another recording takes it
    // The Filter's timeline semaphore: recording n (from 1) has completed once it reaches n.
    VkSemaphore completed = VK_NULL_HANDLE;
    uint64_t recorded = 0; // recordings so far

    std::unique_ptr<ComputePipeline> pass1;         // the pyramid (the reference: its level 0, the source)
    std::unique_ptr<ComputePipeline> pass1Tail;     // the levels from pyramidTailLevel down, in one workgroup
    std::unique_ptr<ComputePipeline> pass1Source;   // hardware sampling: mips 0 and 1 from the source (plan.pyramidFromSource)
    std::unique_ptr<ComputePipeline> pass1Corners;  // exact sampling: the border corners of each pyramid level
    std::unique_ptr<ComputePipeline> paraboloidMap; // fis on a paraboloid map: its levels, after the source's level
    std::unique_ptr<ComputePipeline> pass2;         // table, fis or reference
    std::unique_ptr<ComputePipeline> handOff;       // table: FIS at the levels handed to it; null when none is computed
    std::unique_ptr<ComputePipeline> copy;          // pass 2 at the levels with alpha = 0; null when none is computed
    std::unique_ptr<ComputePipeline> convert;       // the conversion pass; null unless convertOutput
    std::vector<Buffer> initStaging;                // the initialization's uploads, until recording 1 has completed
    std::vector<Dispatch> dispatches;
    int barriers = 0;                    // the pipeline barriers between the dispatches of the last recording
    uint32_t tableUsageFirst = 0;        // table method: where the per-level tap group counts start in the table buffer
    std::vector<uint32_t> sampleOffsets; // fis, and a table's hand-offs: first sample of each output level in the table buffer, and the end

    std::unique_ptr<Submission> submission;

    // `initialization`: the engine's command buffer to record the one-time initialization into, or
    // VK_NULL_HANDLE to submit it here and wait.
    Impl(const Device& d, const FilterSettings& s, VkCommandBuffer initialization);
    ~Impl();

    // The semaphore's value: every recording up to it has completed.
    uint64_t completedValue() const;
    // A set whose last recording has completed (the least recently used), or a new one while there are
    // fewer than FilterSettings::inFlight, made `current` for recording number `recorded` + 1;
    // ProbeError when all are in flight. Releases the initialization's uploads once recording 1 has
    // completed.
    void acquire();
    // A set of what one recording writes, for the Filter's settings.
    std::unique_ptr<Recording> makeRecording() const;
    // A recording's first barrier: a compute barrier against earlier use of the Filter's resources,
    // and with `discard` the current set's images from UNDEFINED to GENERAL; counted in `barriers`.
    void firstBarrier(VkCommandBuffer commandBuffer, bool discard);

    // Makes the current set's output views and every descriptor set for this source and output.
    void bindImages(VkImageView source, VkImage output);
    // A pipeline of the Filter's layout, through the settings' pipeline cache, for its batch size.
    std::unique_ptr<ComputePipeline> pipeline(std::span<const uint32_t> spirv, std::span<const int32_t> specialization = {}) const;
    // The view type of the cubes the passes sample: a cube-map array for a batch.
    VkImageViewType cubeViewType() const;
    // A shader's SPIR-V, or its batch variant (shaders/batch.glsl) for a batch.
    std::span<const uint32_t> batchVariant(std::span<const uint32_t> single, std::span<const uint32_t> batch) const;
    // Timer reset, a barrier against earlier use of the Filter's resources, boundary 0, pass 1 and a
    // barrier, a boundary; then the output levels with no barrier between them (they write disjoint
    // mips and read only the pyramid), a dispatch per level group and a boundary after the last, or
    // with Timestamps::levels a dispatch per level and a boundary after each; then the conversion, if
    // any, and a boundary.
    void recordPasses(VkCommandBuffer commandBuffer, Timestamps timestamps);
    // Pass 2 at output level m alone: a copy, or the method's dispatch (FIS's at a table's level handed
    // to it).
    void recordLevel(VkCommandBuffer commandBuffer, int m);
    // Pass 2's dispatches over `levels` (computed, ascending): each of plan.levelGroups that they hold
    // whole, and each of their other levels alone.
    std::vector<std::vector<int>> dispatchGroups(const std::vector<int>& levels) const;
    // Pass 2 at the levels of one of dispatchGroups(), in one dispatch where there are several.
    void recordLevelGroup(VkCommandBuffer commandBuffer, const std::vector<int>& group);
    // The pass that computes output level m, as dispatches and timings name it.
    std::string_view levelPass(int m) const;
    // One slice: a barrier against earlier use, pass 1 if asked and a barrier, then its levels; no
    // timestamps.
    void recordSlice(VkCommandBuffer commandBuffer, bool pyramid, const std::vector<int>& levels, bool timestamps);
    // Tools: uploads the batch's probes, runs the passes `repeat` times and returns each one's levels.
    std::vector<CubeLevels> runBatch(std::span<const CubeImage> sources, int repeat, Timestamps timestamps);
    // A compute barrier of the passes (computeBarrier), counted in `barriers`.
    void barrier(VkCommandBuffer commandBuffer);
};

// Pass recorders, one per file (pyramid_pass.cpp; for pass 2, one output level at a time:
// copy_level_pass.cpp, reference_pass.cpp, table_pass.cpp, fis_pass.cpp; then
// convert_pass.cpp): each binds its sets, records its dispatches and appends them to impl.dispatches.
// Pass 1: the pipelines of the settings (the reference's: level 0 of the exact pyramid alone).
void makePyramidPipelines(Filter::Impl& impl);
void recordPyramidPass(Filter::Impl& impl, VkCommandBuffer commandBuffer);
// What recordPyramidPass dispatches and its texel-taps (Filter::slices), known before it records.
uint32_t pyramidDispatchCount(const Filter::Impl& impl);
double pyramidTexelTaps(const Filter::Impl& impl);

// Pass 2: the pipeline of the method, sampling and output format (the conversion writes RGBA32F).
// The table and FIS recorders take a group of consecutive output levels (FilterPlan::levelGroups),
// bound to a set whose written mips are theirs in order, and record one dispatch of them all.
std::unique_ptr<ComputePipeline> makeCopyLevelPipeline(const Filter::Impl& impl);
// Records output level `level` (alpha = 0: a copy of the source) under the method's pass name.
void recordCopyLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int level);

std::unique_ptr<ComputePipeline> makeReferencePipeline(const Filter::Impl& impl);
void recordReferenceLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int level);
uint32_t referenceDispatchCount(const Filter::Impl& impl); // per level

std::unique_ptr<ComputePipeline> makeTablePipeline(const Filter::Impl& impl);
// The table buffer: every level in the published layout, level 0 first, then per level the tap
// groups of four in use.
std::vector<float> tableBufferData(const TapTable& table);
uint32_t tableUsageFirst(const TapTable& table); // in vec4s, within tableBufferData
void recordTableLevels(Filter::Impl& impl, VkCommandBuffer commandBuffer, std::span<const int> levels);

std::unique_ptr<ComputePipeline> makeFisPipeline(const Filter::Impl& impl);
// FIS's part of the table buffer: every output level's samples (probe::fisSamplesPerLevel, or a
// table's handOffSamples, empty at the other levels) appended to `data` as vec4(direction in the
// tangent frame, pyramid level); sampleOffsets gets each level's first sample (in vec4s, within
// `data`) and the end.
void appendFisSamples(const std::vector<std::vector<Tap>>& perLevel, std::vector<float>& data, std::vector<uint32_t>& sampleOffsets);
// A FIS level, or a table's level handed to FIS (through `handOff`).
void recordFisLevels(Filter::Impl& impl, VkCommandBuffer commandBuffer, std::span<const int> levels);

// The conversion pass: packs each output level computed into `packed`, then copies it into `output`
// (in VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL).
std::unique_ptr<ComputePipeline> makeConvertPipeline(const Filter::Impl& impl);
void recordConversion(Filter::Impl& impl, VkCommandBuffer commandBuffer, VkImage output, const std::vector<int>& levels);

// The SPIR-V of a pass-2 shader for the output format: `variants` holds the RGBA32F, RGBA16F and
// B10G11R11 builds, in that order (the conversion pass's input is RGBA32F).
std::span<const uint32_t> outputVariant(const Filter::Impl& impl, std::array<std::span<const uint32_t>, 3> variants);

// Appends a dispatch of `pipeline` with push constants `constants` to the command buffer and to
// impl.dispatches (`levels` output levels from `level`).
template <typename Constants>
void dispatchPass(Filter::Impl& impl, VkCommandBuffer commandBuffer, const ComputePipeline& pipeline, std::string_view pass, int level,
                  const Constants& constants, uint32_t groups, uint32_t layers = 1, int levels = 1) {
    static_assert(sizeof(Constants) <= kPushConstantBytes);
    pipeline.dispatch(commandBuffer, std::as_bytes(std::span(&constants, 1)), groups, layers);
    impl.dispatches.push_back({std::string(pass), level, groups * layers, levels});
}

// A level group's workgroup ends in its grid (shaders/level_group.glsl): level k's groupsOf(level)
// workgroups after level k - 1's; the unused slots repeat the last end.
template <typename GroupsOf>
std::array<uint32_t, kWrittenMipCount> levelGroupEnds(std::span<const int> levels, GroupsOf groupsOf) {
    std::array<uint32_t, kWrittenMipCount> ends{};
    uint32_t end = 0;
    for (std::size_t k = 0; k < ends.size(); ++k) {
        if (k < levels.size()) end += groupsOf(levels[k]);
        ends[k] = end;
    }
    return ends;
}

} // namespace probe::gpu
