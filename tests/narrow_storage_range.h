// Narrows the test device's storage-buffer range while it lives: what a device that offers less
// does with buffers larger than its range (the runtime binds windows of them). For the tests that
// see the runtime's sources (Device::Impl).
#pragma once

#include "device.h"
#include "gpu_test_support.h"

namespace probetest {

class NarrowStorageRange {
public:
    explicit NarrowStorageRange(uint32_t bytes) : range_(limits_.maxStorageBufferRange) { limits_.maxStorageBufferRange = bytes; }
    ~NarrowStorageRange() { limits_.maxStorageBufferRange = range_; }
    NarrowStorageRange(const NarrowStorageRange&) = delete;
    NarrowStorageRange& operator=(const NarrowStorageRange&) = delete;

private:
    VkPhysicalDeviceLimits& limits_ = testDevice().impl().limits;
    uint32_t range_;
};

} // namespace probetest
