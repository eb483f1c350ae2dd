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
#include "gpu_timer.h"
#include "probe/runtime.h"
#include "submission.h"

namespace probe::gpu {

struct Filter::Impl {
    const Device& device;
    FilterSettings settings;
    int pyramidLevels = 0;                // log2(S_0) + 1: down to 1x1
    int pyramidDepth = 0;                 // pass 1 builds levels 1..pyramidDepth
    std::vector<int> levels;              // the output levels computed, ascending
    std::vector<uint32_t> pyramidOffsets; // first texel of each pyramid level (with its borders), and the total
    std::vector<uint32_t> outputOffsets;  // first texel of each output level, and the total

    Buffer pyramid;  // binding 0
    Buffer output;   // binding 1
    Buffer geometry; // binding 2: per pyramid level, (texel direction, solid angle)
    Buffer table;    // binding 3: tap table or FIS samples (one vec4 when unused)
    std::unique_ptr<PipelineLayout> layout;
    std::unique_ptr<ComputePipeline> pass1;        // the pyramid; null for the reference method
    std::unique_ptr<ComputePipeline> pass1Corners; // the border corners of each pyramid level, with pass1
    std::unique_ptr<ComputePipeline> pass2;        // table, fis or reference
    std::unique_ptr<ComputePipeline> copy;         // pass 2 at the levels with alpha = 0; null when none is computed
    std::unique_ptr<GpuTimer> timer;
    std::vector<Dispatch> dispatches;
    uint32_t copyLevels = 0;             // bit m: output level m has alpha = 0, a copy of the source
    int tableTaps = 0;                   // table method: N per frame
    int tableCoefficientCount = 0;       // table method: 3 (quadratic) or 1 (constant)
    uint32_t tableUsageFirst = 0;        // table method: where the per-level tap group counts start in the table buffer
    std::vector<uint32_t> sampleOffsets; // fis: first sample of each output level in the table buffer, and the total

    std::unique_ptr<Submission> submission;

    Impl(const Device& d, const FilterSettings& s);

    // Timer reset, boundary 0, pass 1 and a barrier, a boundary; then each output level and a boundary
    // after it (no barrier between levels: they write disjoint texels and read only the pyramid).
    void recordPasses(VkCommandBuffer commandBuffer);
};

// Pass recorders, one per file (pyramid_pass.cpp; for pass 2, one output level at a time:
// copy_level_pass.cpp, reference_pass.cpp, table_pass.cpp, importance_sampling_pass.cpp): each records
// its dispatches and appends them to impl.dispatches.
std::span<const uint32_t> pyramidSpirv();
std::span<const uint32_t> pyramidCornersSpirv();
// pyramid.comp's specialization constants: kBoxKind, kInverseSolidAngle.
std::array<int32_t, 2> pyramidSpecialization(const PyramidSettings& pyramid);
void recordPyramidPass(Filter::Impl& impl, VkCommandBuffer commandBuffer);

std::span<const uint32_t> copyLevelSpirv();
// Records output level `level` (alpha = 0: a copy of the source) under the method's pass name.
void recordCopyLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int level);

std::span<const uint32_t> referenceSpirv();
void recordReferenceLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int level);

std::span<const uint32_t> tableSpirv();
// Throws ProbeError with every reason why `table` cannot serve `settings`.
void checkTableFits(const TapTable& table, const FilterSettings& settings);
// The table buffer: every level in the published layout, level 0 first.
std::vector<float> tableBufferData(const TapTable& table);
uint32_t tableUsageFirst(const TapTable& table); // in vec4s, within tableBufferData
void recordTableLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int level);

std::span<const uint32_t> importanceSamplingSpirv();
// The table buffer for FIS: every output level's samples (probe::importanceSamplesPerLevel) as
// vec4(direction in the tangent frame, pyramid level); sampleOffsets gets each level's first sample
// and the total.
std::vector<float> importanceSamplingBufferData(const FilterSettings& settings, std::vector<uint32_t>& sampleOffsets);
void recordImportanceSamplingLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int level);

// Appends a dispatch of `pipeline` with push constants `constants` to the command buffer and to
// impl.dispatches.
template <typename Constants>
void dispatchPass(Filter::Impl& impl, VkCommandBuffer commandBuffer, const ComputePipeline& pipeline, std::string_view pass, int level,
                  const Constants& constants, uint32_t groups) {
    static_assert(sizeof(Constants) <= kPushConstantBytes);
    pipeline.dispatch(commandBuffer, std::as_bytes(std::span(&constants, 1)), groups);
    impl.dispatches.push_back({std::string(pass), level, groups});
}

} // namespace probe::gpu
