// Timestamp queries at segment boundaries: boundary 0 before the first segment, boundary k after
// segment k. Each segment belongs to a pass (consecutive segments of one pass add up to it), so a
// pass can be timed as a whole and in parts (pass 2, level by level).
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "probe/runtime.h"

namespace probe::gpu {

class GpuTimer {
public:
    // One segment per entry, named by its pass; inactive (records nothing) when the queue has no
    // timestamps.
    GpuTimer(const Device& device, std::vector<std::string> segmentPasses);
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    // Resets the queries; call outside of the passes, before boundary 0.
    void reset(VkCommandBuffer commandBuffer) const;
    void boundary(VkCommandBuffer commandBuffer, uint32_t index) const;
    // Reads the timestamps of the completed run and keeps its segment times.
    void collect();
    void clear() { runs_.clear(); }
    // Per pass (its segments summed in each run) and "total": the median over the collected runs.
    std::vector<PassTime> timings() const;
    // Per segment, named `names[k]`: the median over the collected runs.
    std::vector<PassTime> segmentTimings(const std::vector<std::string>& names) const;

private:
    VkDevice device_;
    VkQueryPool pool_ = VK_NULL_HANDLE;
    double nanosecondsPerTick_ = 1.0;
    uint64_t validMask_ = 0;
    std::vector<std::string> segmentPasses_;
    std::vector<std::vector<double>> runs_; // per run, per segment (ms)
};

} // namespace probe::gpu
