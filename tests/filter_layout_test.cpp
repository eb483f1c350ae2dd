// The Filter's pipeline layout asks of a device, per shader stage, no more descriptors of each type
// than Vulkan guarantees on every device (the specification's required limits). Each of its
// pipelines binds the whole layout, so an excess would fail on devices at those limits (many mobile
// GPUs) while passing on lavapipe and desktop GPUs, whose limits are far higher.
#include <gtest/gtest.h>

#include "filter_descriptors.h"
#include "probe/limits.h"

namespace {

using namespace probe::gpu;

TEST(FilterLayout, StaysWithinTheLimitsEveryDeviceOffers) {
    const uint32_t storageImages = filterDescriptorCount(VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
    const uint32_t storageBuffers = filterDescriptorCount(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    const uint32_t samplers = filterDescriptorCount(VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
    const uint32_t texelBuffers = filterDescriptorCount(VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER);
    EXPECT_LE(storageImages, 4u);                                              // maxPerStageDescriptorStorageImages
    EXPECT_LE(storageBuffers, 4u);                                             // maxPerStageDescriptorStorageBuffers
    EXPECT_LE(samplers, 16u);                                                  // maxPerStageDescriptorSamplers
    EXPECT_LE(samplers + texelBuffers, 16u);                                   // maxPerStageDescriptorSampledImages
    EXPECT_LE(storageImages + storageBuffers + samplers + texelBuffers, 128u); // maxPerStageResources
    // Every binding is counted: the four types are all the layout has.
    uint32_t all = 0;
    for (const FilterBindingLayout& b : kFilterBindings) all += b.count;
    EXPECT_EQ(all, storageImages + storageBuffers + samplers + texelBuffers);
    // Pass 1's last dispatch writes the tail's mips through the one storage-image binding.
    EXPECT_EQ(kFilterBindings[kWrittenMips].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
    EXPECT_EQ(kFilterBindings[kWrittenMips].count, uint32_t(kPyramidTailMipCount));
    // The wide layout (FilterPlan::writtenMipCount, for a device that offers its storage images) has
    // them for every level of the largest face size, and nothing else more.
    EXPECT_EQ(filterDescriptorCount(VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kWideWrittenMipCount), uint32_t(probe::kMaxLevels));
    EXPECT_EQ(filterDescriptorCount(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kWideWrittenMipCount), storageBuffers);
}

} // namespace
