#include "image.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <utility>

#include <glm/gtc/packing.hpp>

#include "device.h"
#include "probe/shared_constants.h"
#include "vulkan_check.h"

namespace probe::gpu {

CubeImageResource::CubeImageResource(const Device& device, int faceSize, int mips, VkFormat format, VkImageUsageFlags usage, int cubes,
                                     VkImageCreateFlags flags)
    : device_(device.device()), format_(format), faceSize_(faceSize), mips_(mips), layers_(uint32_t(kFaceCount * cubes)) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.flags = VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT | flags;
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {uint32_t(faceSize), uint32_t(faceSize), 1};
    info.mipLevels = uint32_t(mips);
    info.arrayLayers = layers_;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    vkCheck(vkCreateImage(device_, &info, nullptr, &image_), "vkCreateImage");
    VkMemoryRequirements requirements;
    vkGetImageMemoryRequirements(device_, image_, &requirements);
    VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    allocate.allocationSize = requirements.size;
    allocate.memoryTypeIndex = device.impl().memoryType(requirements.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    try {
        vkCheck(vkAllocateMemory(device_, &allocate, nullptr, &memory_), "vkAllocateMemory");
        vkCheck(vkBindImageMemory(device_, image_, memory_, 0), "vkBindImageMemory");
    } catch (...) {
        release();
        throw;
    }
}

CubeImageResource::~CubeImageResource() { release(); }

CubeImageResource::CubeImageResource(CubeImageResource&& other) noexcept { *this = std::move(other); }

CubeImageResource& CubeImageResource::operator=(CubeImageResource&& other) noexcept {
    if (this != &other) {
        release();
        device_ = std::exchange(other.device_, VK_NULL_HANDLE);
        image_ = std::exchange(other.image_, VK_NULL_HANDLE);
        memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
        format_ = other.format_;
        faceSize_ = other.faceSize_;
        mips_ = other.mips_;
        layers_ = other.layers_;
    }
    return *this;
}

void CubeImageResource::release() {
    if (image_) vkDestroyImage(device_, image_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
    image_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
}

ImageView::ImageView(VkDevice device, VkImage image, VkFormat format, VkImageViewType type, uint32_t firstMip, uint32_t mipCount,
                     uint32_t layers, VkImageUsageFlags usage)
    : device_(device) {
    const VkImageViewUsageCreateInfo viewUsage{VK_STRUCTURE_TYPE_IMAGE_VIEW_USAGE_CREATE_INFO, nullptr, usage};
    VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO, usage ? &viewUsage : nullptr};
    info.image = image;
    info.viewType = type;
    info.format = format;
    info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, firstMip, mipCount, 0, layers};
    vkCheck(vkCreateImageView(device_, &info, nullptr, &view_), "vkCreateImageView");
}

ImageView::~ImageView() {
    if (view_) vkDestroyImageView(device_, view_, nullptr);
}

ImageView::ImageView(ImageView&& other) noexcept { *this = std::move(other); }

ImageView& ImageView::operator=(ImageView&& other) noexcept {
    if (this != &other) {
        if (view_) vkDestroyImageView(device_, view_, nullptr);
        device_ = std::exchange(other.device_, VK_NULL_HANDLE);
        view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    }
    return *this;
}

Sampler::Sampler(VkDevice device, bool linear) : device_(device) {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = linear ? VK_FILTER_LINEAR : VK_FILTER_NEAREST;
    info.mipmapMode = linear ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
    info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.minLod = 0.0f;
    info.maxLod = VK_LOD_CLAMP_NONE; // the view's mips bound the level
    vkCheck(vkCreateSampler(device_, &info, nullptr, &sampler_), "vkCreateSampler");
}

Sampler::~Sampler() {
    if (sampler_) vkDestroySampler(device_, sampler_, nullptr);
}

uint32_t texelBytes(VkFormat format) {
    switch (format) {
    case VK_FORMAT_R16G16B16A16_SFLOAT: return 8;
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32:
    case VK_FORMAT_E5B9G9R9_UFLOAT_PACK32: return 4;
    default: return 16;
    }
}

void unpackTexels(const void* data, std::size_t texels, VkFormat format, std::vector<float>& rgb) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t t = 0; t < texels; ++t) {
        glm::vec3 c;
        if (format == VK_FORMAT_R16G16B16A16_SFLOAT) {
            uint16_t half[4];
            std::memcpy(half, bytes + 8 * t, sizeof(half));
            c = {glm::unpackHalf1x16(half[0]), glm::unpackHalf1x16(half[1]), glm::unpackHalf1x16(half[2])};
        } else if (format == VK_FORMAT_B10G11R11_UFLOAT_PACK32) {
            uint32_t packed;
            std::memcpy(&packed, bytes + 4 * t, sizeof(packed));
            c = glm::unpackF2x11_1x10(packed); // R in bits 0-10, G in 11-21, B in 22-31, as Vulkan's format
        } else if (format == VK_FORMAT_E5B9G9R9_UFLOAT_PACK32) {
            uint32_t packed;
            std::memcpy(&packed, bytes + 4 * t, sizeof(packed));
            c = glm::unpackF3x9_E1x5(packed); // R in bits 0-8, G in 9-17, B in 18-26, the exponent in 27-31
        } else {
            std::memcpy(&c, bytes + 16 * t, sizeof(c));
        }
        rgb.insert(rgb.end(), {c.r, c.g, c.b});
    }
}

void saturateTexels(CubeLevels& levels, VkFormat format) {
    const glm::vec3 largest = format == VK_FORMAT_B10G11R11_UFLOAT_PACK32
                                  ? glm::vec3(PROBE_FLOAT11_MAX, PROBE_FLOAT11_MAX, PROBE_FLOAT10_MAX)
                              : format == VK_FORMAT_R16G16B16A16_SFLOAT ? glm::vec3(PROBE_HALF_MAX)
                                                                        : glm::vec3(std::numeric_limits<float>::max());
    for (CubeImage& level : levels)
        for (std::size_t i = 0; i < level.rgb.size(); ++i)
            level.rgb[i] = std::clamp(level.rgb[i], -largest[int(i % 3)], largest[int(i % 3)]);
}

VkImageMemoryBarrier imageMemoryBarrier(VkImage image, uint32_t firstMip, uint32_t mipCount, uint32_t layers, VkImageLayout from,
                                        VkImageLayout to, VkAccessFlags srcAccess, VkAccessFlags dstAccess) {
    VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    barrier.srcAccessMask = srcAccess;
    barrier.dstAccessMask = dstAccess;
    barrier.oldLayout = from;
    barrier.newLayout = to;
    barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, firstMip, mipCount, 0, layers};
    return barrier;
}

void imageBarrier(VkCommandBuffer commandBuffer, VkImage image, uint32_t firstMip, uint32_t mipCount, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags srcStage, VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
    const VkImageMemoryBarrier barrier =
        imageMemoryBarrier(image, firstMip, mipCount, VK_REMAINING_ARRAY_LAYERS, from, to, srcAccess, dstAccess);
    vkCmdPipelineBarrier(commandBuffer, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

} // namespace probe::gpu
