// The engine path: Filter::record into the caller's command buffer, on the caller's device (the test
// device wrapped), from the caller's RGBA16F source cube (sampled through its cube view) straight
// into the caller's RGBA16F output mips, gives the same levels as the tool path (Filter::run) on the
// same half-float texels, in both sampling modes, and the validation layer stays silent.
#include <cstring>

#include <glm/gtc/packing.hpp>

#include "gpu_test_support.h"
#include "probe/synthetic.h"

using namespace probe;
using probetest::GpuTest;

namespace {

// Minimal caller-side Vulkan: what an engine already has.
struct Caller {
    VkDevice device;
    VkPhysicalDevice physical;
    uint32_t queueFamily;
    VkQueue queue;

    uint32_t memoryType(uint32_t bits, VkMemoryPropertyFlags flags) const {
        VkPhysicalDeviceMemoryProperties memory;
        vkGetPhysicalDeviceMemoryProperties(physical, &memory);
        for (uint32_t t = 0; t < memory.memoryTypeCount; ++t)
            if ((bits & (1u << t)) && (memory.memoryTypes[t].propertyFlags & flags) == flags) return t;
        ADD_FAILURE() << "no memory type";
        return 0;
    }
    VkDeviceMemory allocate(VkMemoryRequirements r, VkMemoryPropertyFlags flags) const {
        VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, nullptr, r.size, memoryType(r.memoryTypeBits, flags)};
        VkDeviceMemory memory = VK_NULL_HANDLE;
        EXPECT_EQ(vkAllocateMemory(device, &info, nullptr, &memory), VK_SUCCESS);
        return memory;
    }
};

struct HostBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    float* data = nullptr;
};

HostBuffer hostBuffer(const Caller& c, VkDeviceSize bytes) {
    HostBuffer b;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    EXPECT_EQ(vkCreateBuffer(c.device, &info, nullptr, &b.buffer), VK_SUCCESS);
    VkMemoryRequirements r;
    vkGetBufferMemoryRequirements(c.device, b.buffer, &r);
    b.memory = c.allocate(r, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    vkBindBufferMemory(c.device, b.buffer, b.memory, 0);
    void* mapped = nullptr;
    vkMapMemory(c.device, b.memory, 0, VK_WHOLE_SIZE, 0, &mapped);
    b.data = static_cast<float*>(mapped);
    return b;
}

struct CubeTexture {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
};

CubeTexture cubeTexture(const Caller& c, int size, int mips, VkImageUsageFlags usage) {
    CubeTexture t;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.flags = VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    info.extent = {uint32_t(size), uint32_t(size), 1};
    info.mipLevels = uint32_t(mips);
    info.arrayLayers = 6;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    EXPECT_EQ(vkCreateImage(c.device, &info, nullptr, &t.image), VK_SUCCESS);
    VkMemoryRequirements r;
    vkGetImageMemoryRequirements(c.device, t.image, &r);
    t.memory = c.allocate(r, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    vkBindImageMemory(c.device, t.image, t.memory, 0);
    return t;
}

void transition(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to, VkAccessFlags srcAccess,
                VkAccessFlags dstAccess) {
    VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    barrier.srcAccessMask = srcAccess;
    barrier.dstAccessMask = dstAccess;
    barrier.oldLayout = from;
    barrier.newLayout = to;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, 6};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0, nullptr, 1,
                         &barrier);
}

// The probe as the caller's RGBA16F texels hold it.
CubeImage halfRounded(const CubeImage& probe) {
    CubeImage rounded = probe;
    for (float& v : rounded.rgb) v = glm::unpackHalf1x16(glm::packHalf1x16(v));
    return rounded;
}

void recordAndCompare(const Caller& c, const gpu::Device& owner, const gpu::Device& wrapped, gpu::Sampling sampling) {
    const int size = 32, levels = 5;
    gpu::FilterSettings settings;
    settings.method.kind = MethodKind::fis;
    settings.faceSize = size;
    settings.levelCount = levels;
    settings.sampling = sampling;
    settings.outputFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
    const CubeImage source = halfRounded(probetest::randomProbe(size, 7));
    gpu::Filter tool(owner, settings);
    const CubeLevels expected = tool.run(source);

    gpu::Filter engine(wrapped, settings);
    const CubeTexture in = cubeTexture(c, size, 1, VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
    const CubeTexture out = cubeTexture(c, size, levels, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = in.image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_CUBE;
    viewInfo.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 6};
    VkImageView inView = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateImageView(c.device, &viewInfo, nullptr, &inView), VK_SUCCESS);
    std::size_t outputTexels = 0;
    for (int m = 0; m < levels; ++m) outputTexels += texelCount(size >> m);
    HostBuffer staging = hostBuffer(c, outputTexels * 4 * sizeof(uint16_t));
    auto* halves = reinterpret_cast<uint16_t*>(staging.data);
    for (std::size_t t = 0; t < texelCount(size); ++t) {
        const glm::vec3 v = source.texel(t);
        const uint16_t rgba[4] = {glm::packHalf1x16(v.r), glm::packHalf1x16(v.g), glm::packHalf1x16(v.b), glm::packHalf1x16(1.0f)};
        std::memcpy(halves + 4 * t, rgba, sizeof(rgba));
    }

    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = c.queueFamily;
    VkCommandPool pool = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateCommandPool(c.device, &poolInfo, nullptr, &pool), VK_SUCCESS);
    VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, nullptr, pool, VK_COMMAND_BUFFER_LEVEL_PRIMARY, 1};
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    ASSERT_EQ(vkAllocateCommandBuffers(c.device, &allocate, &cmd), VK_SUCCESS);
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    vkBeginCommandBuffer(cmd, &begin);

    // The engine's own work: its cube uploaded and made readable by compute shaders, its output
    // mips in GENERAL for the filter's writes.
    transition(cmd, in.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkBufferImageCopy whole{};
    whole.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 6};
    whole.imageExtent = {uint32_t(size), uint32_t(size), 1};
    vkCmdCopyBufferToImage(cmd, staging.buffer, in.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &whole);
    transition(cmd, in.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
               VK_ACCESS_SHADER_READ_BIT);
    transition(cmd, out.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, 0, VK_ACCESS_SHADER_WRITE_BIT);

    engine.record(cmd, {inView, VK_FORMAT_R16G16B16A16_SFLOAT}, {out.image, VK_FORMAT_R16G16B16A16_SFLOAT});

    transition(cmd, out.image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_ACCESS_SHADER_WRITE_BIT,
               VK_ACCESS_TRANSFER_READ_BIT);
    std::vector<VkBufferImageCopy> back;
    VkDeviceSize offset = 0;
    for (int m = 0; m < levels; ++m) {
        VkBufferImageCopy region{};
        region.bufferOffset = offset;
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(m), 0, 6};
        region.imageExtent = {uint32_t(size >> m), uint32_t(size >> m), 1};
        back.push_back(region);
        offset += texelCount(size >> m) * 4 * sizeof(uint16_t);
    }
    vkCmdCopyImageToBuffer(cmd, out.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer, uint32_t(back.size()), back.data());
    VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0, nullptr);
    vkEndCommandBuffer(cmd);
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    ASSERT_EQ(vkQueueSubmit(c.queue, 1, &submit, VK_NULL_HANDLE), VK_SUCCESS);
    ASSERT_EQ(vkQueueWaitIdle(c.queue), VK_SUCCESS);

    const std::vector<gpu::PassTime> timings = engine.timings();
    ASSERT_EQ(timings.size(), 3u);
    EXPECT_EQ(timings[0].name, "pyramid");
    EXPECT_GT(timings[2].medianMs, 0.0);
    const uint16_t* texels = halves;
    for (int m = 0; m < levels; ++m) {
        CubeImage level(size >> m);
        for (std::size_t t = 0; t < texelCount(level.size); ++t)
            level.set(t,
                      {glm::unpackHalf1x16(texels[4 * t]), glm::unpackHalf1x16(texels[4 * t + 1]), glm::unpackHalf1x16(texels[4 * t + 2])});
        texels += 4 * texelCount(level.size);
        EXPECT_EQ(level.rgb, expected[m].rgb) << gpu::samplingName(sampling) << " sampling, level " << m;
    }

    vkDestroyCommandPool(c.device, pool, nullptr);
    vkDestroyImageView(c.device, inView, nullptr);
    vkDestroyBuffer(c.device, staging.buffer, nullptr);
    vkFreeMemory(c.device, staging.memory, nullptr);
    for (const CubeTexture& t : {in, out}) {
        vkDestroyImage(c.device, t.image, nullptr);
        vkFreeMemory(c.device, t.memory, nullptr);
    }
}

} // namespace

TEST_F(GpuTest, RecordIntoCallersCommandBufferEqualsRun) {
    const gpu::Device& owner = probetest::testDevice();
    const Caller c{owner.device(), owner.physicalDevice(), owner.queueFamily(), owner.queue()};
    const gpu::Device wrapped(owner.instance(), c.physical, c.device, c.queueFamily, c.queue);
    for (gpu::Sampling sampling : {gpu::Sampling::exact, gpu::Sampling::hardware}) recordAndCompare(c, owner, wrapped, sampling);
}
