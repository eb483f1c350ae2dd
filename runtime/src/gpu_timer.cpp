#include "gpu_timer.h"

#include <algorithm>

#include "device.h"
#include "vulkan_check.h"

namespace probe::gpu {

namespace {

PassTime medianOf(std::string name, std::vector<double> runsMs) {
    PassTime time{std::move(name), 0.0, std::move(runsMs)};
    std::vector<double> sorted = time.runsMs;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    if (n) time.medianMs = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    return time;
}

} // namespace

GpuTimer::GpuTimer(const Device& device, std::vector<std::string> segmentPasses)
    : device_(device.device()), segmentPasses_(std::move(segmentPasses)) {
    const Device::Impl& d = device.impl();
    if (d.timestampValidBits == 0 || d.limits.timestampPeriod <= 0.0f) return;
    nanosecondsPerTick_ = d.limits.timestampPeriod;
    validMask_ = d.timestampValidBits >= 64 ? ~uint64_t(0) : (uint64_t(1) << d.timestampValidBits) - 1;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = static_cast<uint32_t>(segmentPasses_.size() + 1);
    vkCheck(vkCreateQueryPool(device_, &info, nullptr, &pool_), "vkCreateQueryPool");
}

GpuTimer::~GpuTimer() {
    if (pool_) vkDestroyQueryPool(device_, pool_, nullptr);
}

void GpuTimer::reset(VkCommandBuffer commandBuffer) const {
    if (pool_) vkCmdResetQueryPool(commandBuffer, pool_, 0, static_cast<uint32_t>(segmentPasses_.size() + 1));
}

void GpuTimer::boundary(VkCommandBuffer commandBuffer, uint32_t index) const {
    if (pool_) vkCmdWriteTimestamp(commandBuffer, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, index);
}

void GpuTimer::collect() {
    if (!pool_) return;
    std::vector<uint64_t> ticks(segmentPasses_.size() + 1);
    vkCheck(vkGetQueryPoolResults(device_, pool_, 0, static_cast<uint32_t>(ticks.size()), ticks.size() * sizeof(uint64_t), ticks.data(),
                                  sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
            "vkGetQueryPoolResults");
    std::vector<double> run;
    for (std::size_t k = 0; k < segmentPasses_.size(); ++k)
        run.push_back(static_cast<double>((ticks[k + 1] - ticks[k]) & validMask_) * nanosecondsPerTick_ * 1e-6);
    runs_.push_back(std::move(run));
}

std::vector<PassTime> GpuTimer::timings() const {
    std::vector<PassTime> result;
    if (runs_.empty()) return result;
    std::vector<std::string> passes;
    for (const std::string& pass : segmentPasses_)
        if (passes.empty() || passes.back() != pass) passes.push_back(pass);
    for (const std::string& pass : passes) {
        std::vector<double> runsMs;
        for (const auto& run : runs_) {
            double ms = 0.0;
            for (std::size_t k = 0; k < run.size(); ++k)
                if (segmentPasses_[k] == pass) ms += run[k];
            runsMs.push_back(ms);
        }
        result.push_back(medianOf(pass, std::move(runsMs)));
    }
    std::vector<double> totals;
    for (const auto& run : runs_) {
        double ms = 0.0;
        for (double segment : run) ms += segment;
        totals.push_back(ms);
    }
    result.push_back(medianOf("total", std::move(totals)));
    return result;
}

std::vector<PassTime> GpuTimer::segmentTimings(const std::vector<std::string>& names) const {
    std::vector<PassTime> result;
    if (runs_.empty()) return result;
    for (std::size_t k = 0; k < segmentPasses_.size() && k < names.size(); ++k) {
        std::vector<double> runsMs;
        for (const auto& run : runs_) runsMs.push_back(run[k]);
        result.push_back(medianOf(names[k], std::move(runsMs)));
    }
    return result;
}

} // namespace probe::gpu
