#include "gpu_timer.h"

#include <algorithm>

#include "device.h"
#include "vulkan_check.h"

namespace probe::gpu {

GpuTimer::GpuTimer(const Device& device, std::vector<std::string> passNames)
    : device_(device.device()), passNames_(std::move(passNames)) {
    const Device::Impl& d = device.impl();
    if (d.timestampValidBits == 0 || d.limits.timestampPeriod <= 0.0f) return;
    nanosecondsPerTick_ = d.limits.timestampPeriod;
    validMask_ = d.timestampValidBits >= 64 ? ~uint64_t(0) : (uint64_t(1) << d.timestampValidBits) - 1;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = static_cast<uint32_t>(passNames_.size() + 1);
    vkCheck(vkCreateQueryPool(device_, &info, nullptr, &pool_), "vkCreateQueryPool");
}

GpuTimer::~GpuTimer() {
    if (pool_) vkDestroyQueryPool(device_, pool_, nullptr);
}

void GpuTimer::reset(VkCommandBuffer commandBuffer) const {
    if (pool_) vkCmdResetQueryPool(commandBuffer, pool_, 0, static_cast<uint32_t>(passNames_.size() + 1));
}

void GpuTimer::boundary(VkCommandBuffer commandBuffer, uint32_t index) const {
    if (pool_) vkCmdWriteTimestamp(commandBuffer, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, index);
}

void GpuTimer::collect() {
    if (!pool_) return;
    std::vector<uint64_t> ticks(passNames_.size() + 1);
    vkCheck(vkGetQueryPoolResults(device_, pool_, 0, static_cast<uint32_t>(ticks.size()), ticks.size() * sizeof(uint64_t),
                                  ticks.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
            "vkGetQueryPoolResults");
    const auto ms = [&](std::size_t from, std::size_t to) {
        return static_cast<double>((ticks[to] - ticks[from]) & validMask_) * nanosecondsPerTick_ * 1e-6;
    };
    std::vector<double> run;
    for (std::size_t p = 0; p < passNames_.size(); ++p) run.push_back(ms(p, p + 1));
    run.push_back(ms(0, passNames_.size()));
    runs_.push_back(std::move(run));
}

std::vector<PassTime> GpuTimer::timings() const {
    std::vector<PassTime> result;
    if (runs_.empty()) return result;
    for (std::size_t p = 0; p <= passNames_.size(); ++p) {
        PassTime time;
        time.name = p < passNames_.size() ? passNames_[p] : "total";
        for (const auto& run : runs_) time.runsMs.push_back(run[p]);
        std::vector<double> sorted = time.runsMs;
        std::sort(sorted.begin(), sorted.end());
        const std::size_t n = sorted.size();
        time.medianMs = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
        result.push_back(std::move(time));
    }
    return result;
}

} // namespace probe::gpu
