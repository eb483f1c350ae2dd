// One recording's resources of a probe::gpu::Filter: what it writes and the views and descriptor sets
// it binds, which the Filter keeps per recording in flight and its passes (filter_passes.h) record
// with.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "buffer.h"
#include "filter_descriptors.h"
#include "gpu_timer.h"
#include "image.h"

namespace probe::gpu {

// What one recording writes, and the views and descriptor sets it binds: the Filter makes up to
// FilterSettings::inFlight of them as recordings need them, so that so many may be pending at once.
// Each recording (each pyramid slice) takes its images from VK_IMAGE_LAYOUT_UNDEFINED, whose
// contents it makes anew.
struct Recording {
    Buffer pyramidBuffer; // exact sampling, and level 0 alone for the reference
    Buffer accumulator;   // the reference's running sums (one vec4 when unused)
    // Pass 1's workgroups counted per dispatch (exact sampling's levels): zeroed by the set's first
    // recording, set back to 0 by each dispatch that counts in it.
    Buffer pyramidCounters;
    bool pyramidCountersZeroed = false;
    BufferView pyramidView;
    CubeImageResource pyramidImage;          // hardware sampling: mips 0..pyramidDepth
    ImageView pyramidAll;                    // cube (a cube-map array for a batch), every mip: pass 2 reads
    std::vector<ImageView> pyramidMipCubes;  // the same, mip k alone: pass 1 reads it for level k + 1
    std::vector<ImageView> pyramidMipArrays; // 2D array, mip k: pass 1 writes
    CubeImageResource intermediate, packed;  // conversion: pass 2's RGBA32F output and the R32_UINT words
    std::vector<ImageView> intermediateMips, packedMips;

    // The source and output that the descriptor sets refer to: the caller's (or run()'s).
    VkImageView boundSource = VK_NULL_HANDLE;
    VkImage boundOutput = VK_NULL_HANDLE;
    std::vector<ImageView> outputMips; // views of the bound output (or of `intermediate`), per output level
    std::unique_ptr<DescriptorPool> pool;
    // Pass 1's: per pyramid window (FilterPlan::pyramidWindows) with exact sampling, then per paraboloid
    // window (FilterPlan::paraboloidWindows); per pyramid level 0..pyramidDepth with hardware sampling.
    std::vector<VkDescriptorSet> pyramidSets;
    std::vector<VkDescriptorSet> levelSets;   // per output level
    std::vector<VkDescriptorSet> groupSets;   // per output level: the mips of its level group's levels from it on
    std::vector<VkDescriptorSet> convertSets; // per output level

    std::unique_ptr<GpuTimer> passTimer;  // a segment per pass
    std::unique_ptr<GpuTimer> levelTimer; // pass 2 in a segment per output level
    std::unique_ptr<GpuTimer> sliceTimer; // a slice in one segment
    GpuTimer* timer = nullptr;            // the one the last recording wrote
    bool timed = true;                    // the last recording wrote timestamp queries

    uint64_t completion = 0; // the semaphore value that ends its last recording; 0: none pending

    // A batch of separate cubes (record() with one cube a probe): the sources copied into a cube-map
    // array of their format, made at the set's first such recording (again if the format changes); the
    // outputs copied from runOutput.
    CubeImageResource copySource;
    ImageView copySourceView;

    // The tools' own source and output cubes (run()), a cube-map array for a batch, made at the set's
    // first run().
    CubeImageResource runSource, runOutput;
    ImageView runSourceView;
};

} // namespace probe::gpu
