// A batch of the engine's separately allocated cubes (Filter::record with one cube a probe): the
// sources copied into the set's cube-map array of their format, the outputs copied from the set's
// own output array, around the passes of one probe.
#pragma once

#include <vector>

#include "filter_impl.h"

namespace probe::gpu {

// Refuses, naming the field, what record() cannot copy: counts other than the batch's, cubes of other
// sizes, layers, formats or usage.
void checkSeparateCubes(const Filter::Impl& f, VkCommandBuffer commandBuffer, const std::vector<SourceCube>& sources,
                        const std::vector<OutputCube>& outputs);

// Makes the current set's source array for `format` (again where its format differs) and its own output.
void makeSeparateCubeImages(Filter::Impl& f, VkFormat format);

// Before the passes: each source into its cube of the set's array (two barriers, one copy a cube),
// the set's output made writable. After them: each cube of the set's output into its output (a
// barrier, one copy a cube).
void copySourcesIn(Filter::Impl& f, VkCommandBuffer commandBuffer, const std::vector<SourceCube>& sources);
void copyOutputsOut(Filter::Impl& f, VkCommandBuffer commandBuffer, const std::vector<OutputCube>& outputs);

} // namespace probe::gpu
