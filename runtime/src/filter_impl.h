// The state of a probe::gpu::Filter: its resources, the passes it computes (filter_passes.h) and the
// recordings in flight, shared by filter.cpp (the engine path) and filter_run.cpp (the tools').
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "buffer.h"
#include "compute_pipeline.h"
#include "filter_descriptors.h"
#include "filter_passes.h"
#include "filter_plan.h"
#include "gpu_timer.h"
#include "image.h"
#include "probe/runtime.h"
#include "recording.h"
#include "submission.h"

namespace probe::gpu {

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

    // The passes (filter_passes.h), those the settings compute.
    std::optional<PyramidPass> pyramid;         // pass 1 (the reference: its level 0, the source)
    std::optional<TablePass> tablePass;         // the table's levels
    std::optional<FisPass> fisPass;             // FIS's levels, or a table's levels handed to FIS
    std::optional<ReferencePass> referencePass; // the reference's levels
    std::optional<CopyLevelPass> copyPass;      // the levels with alpha = 0
    std::optional<ConvertPass> convertPass;     // B10G11R11 through the conversion pass
    std::vector<Buffer> initStaging;            // the initialization's uploads, until recording 1 has completed
    std::vector<Dispatch> dispatches;
    int barriers = 0; // the pipeline barriers between the dispatches of the last recording

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
    // The set's own output cube (a cube-map array for a batch), which run() reads back and a batch of
    // separate cubes copies out, made at its first use; the layout the passes write it in.
    void makeOwnOutput(Recording& r) const;
    VkImageLayout ownOutputLayout() const;
    // The view type of the cubes the passes sample: a cube-map array for a batch.
    VkImageViewType cubeViewType() const;
    // What a pass records into, for this recording's command buffer.
    PassRecorder recorder(VkCommandBuffer commandBuffer);
    // Timer reset, a barrier against earlier use of the Filter's resources, boundary 0, pass 1 and a
    // barrier, a boundary; then the output levels with no barrier between them (they write disjoint
    // mips and read only the pyramid), a dispatch per level group and a boundary after the last, or
    // with Timestamps::levels a dispatch per level and a boundary after each; then the conversion, if
    // any, and a boundary.
    void recordPasses(VkCommandBuffer commandBuffer, Timestamps timestamps);
    // Pass 2 at output level m alone: a copy, or the method's dispatch (FIS's at a table's level handed
    // to it).
    void recordLevel(VkCommandBuffer commandBuffer, int m);
    // Pass 2's dispatches over `levels` (computed, ascending): per group of plan.levelGroups, each run
    // of consecutive levels of it that they hold (a slice's levels cut from a group share a dispatch).
    std::vector<std::vector<int>> dispatchGroups(const std::vector<int>& levels) const;
    // Pass 2 at the levels of one of dispatchGroups(), in one dispatch where there are several.
    void recordLevelGroup(VkCommandBuffer commandBuffer, const std::vector<int>& group);
    // The pass that computes output level m, as dispatches and timings name it.
    std::string_view levelPass(int m) const;
    // One slice: a barrier against earlier use, pass 1 if asked and a barrier, then its levels; no
    // timestamps.
    void recordSlice(VkCommandBuffer commandBuffer, bool withPyramid, const std::vector<int>& levels, bool timestamps);
    // Tools: uploads the batch's probes, runs the passes `repeat` times and returns each one's levels.
    std::vector<CubeLevels> runBatch(std::span<const CubeImage> sources, int repeat, Timestamps timestamps);
};

} // namespace probe::gpu
