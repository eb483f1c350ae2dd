// Timestamp queries at pass boundaries: boundary 0 before the first pass, boundary k after pass k.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "probe/runtime.h"

namespace probe::gpu {

class GpuTimer {
public:
    // Room for `passCount` passes; inactive (records nothing) when the queue has no timestamps.
    GpuTimer(const Device& device, std::vector<std::string> passNames);
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;

    // Resets the queries; call outside of the passes, before boundary 0.
    void reset(VkCommandBuffer commandBuffer) const;
    void boundary(VkCommandBuffer commandBuffer, uint32_t index) const;
    // Reads the timestamps of the completed run and keeps its pass times.
    void collect();
    void clear() { runs_.clear(); }
    // Per pass and "total": the median over the collected runs.
    std::vector<PassTime> timings() const;

private:
    VkDevice device_;
    VkQueryPool pool_ = VK_NULL_HANDLE;
    double nanosecondsPerTick_ = 1.0;
    uint64_t validMask_ = 0;
    std::vector<std::string> passNames_;
    std::vector<std::vector<double>> runs_; // per run, per pass, then the total (ms)
};

} // namespace probe::gpu
