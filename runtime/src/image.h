// Cube images with their own memory, their views, and samplers: the pyramid of hardware sampling
// and the tools' source and output cubes.
#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>

#include "probe/runtime.h"

namespace probe::gpu {

// A 2D image of 6 array layers per cube (cube compatible: `cubes` of them, a cube-map array for a
// batch) and `mips` mips from `faceSize`, device local.
class CubeImageResource {
public:
    CubeImageResource() = default;
    // `flags` beside CUBE_COMPATIBLE: MUTABLE_FORMAT and EXTENDED_USAGE for an image stored through
    // views of another format.
    CubeImageResource(const Device& device, int faceSize, int mips, VkFormat format, VkImageUsageFlags usage, int cubes = 1,
                      VkImageCreateFlags flags = 0);
    ~CubeImageResource();
    CubeImageResource(CubeImageResource&& other) noexcept;
    CubeImageResource& operator=(CubeImageResource&& other) noexcept;

    VkImage handle() const { return image_; }
    VkFormat format() const { return format_; }
    int faceSize() const { return faceSize_; }
    int mips() const { return mips_; }
    uint32_t layers() const { return layers_; }

private:
    void release();

    VkDevice device_ = VK_NULL_HANDLE;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    int faceSize_ = 0;
    int mips_ = 0;
    uint32_t layers_ = 0;
};

// A view of mips [firstMip, firstMip + mipCount) and layers [0, layers) of an image: a cube (or a
// cube-map array) to sample, or a 2D array (the faces as layers) to store to or fetch from.
class ImageView {
public:
    ImageView() = default;
    // `usage`: 0 for the image's, or the part of it this view serves (an image of EXTENDED_USAGE has
    // usages that its own format does not support).
    ImageView(VkDevice device, VkImage image, VkFormat format, VkImageViewType type, uint32_t firstMip, uint32_t mipCount,
              uint32_t layers = kFaceCount, VkImageUsageFlags usage = 0);
    ~ImageView();
    ImageView(ImageView&& other) noexcept;
    ImageView& operator=(ImageView&& other) noexcept;

    VkImageView handle() const { return view_; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkImageView view_ = VK_NULL_HANDLE;
};

// Clamp-to-edge sampling with unnormalized LOD, no anisotropy: `linear` filters bilinearly within a
// mip and linearly between mips (trilinear; cube images filter seamlessly in Vulkan), else nearest.
class Sampler {
public:
    Sampler() = default;
    Sampler(VkDevice device, bool linear);
    ~Sampler();
    Sampler(const Sampler&) = delete;
    Sampler& operator=(const Sampler&) = delete;

    VkSampler handle() const { return sampler_; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkSampler sampler_ = VK_NULL_HANDLE;
};

// Bytes per texel of the formats the runtime reads back (RGBA32F 16, RGBA16F 8, B10G11R11 4).
uint32_t texelBytes(VkFormat format);

// RGB floats of `texels` texels of `format` (RGBA32F, RGBA16F or B10G11R11, packed as Vulkan
// stores them) appended to `rgb`.
void unpackTexels(const void* data, std::size_t texels, VkFormat format, std::vector<float>& rgb);

// Each channel of `levels` clamped to the largest finite value of `format` (probe/shared_constants.h,
// as the shaders' PROBE_OUTPUT_MAX), where scaling up texels read back from it may have passed that.
void saturateTexels(CubeLevels& levels, VkFormat format);

// The barrier of mips [firstMip, firstMip + mipCount) of layers [0, layers) of `image`, with a
// layout change; imageBarrier records one on every layer.
VkImageMemoryBarrier imageMemoryBarrier(VkImage image, uint32_t firstMip, uint32_t mipCount, uint32_t layers, VkImageLayout from,
                                        VkImageLayout to, VkAccessFlags srcAccess, VkAccessFlags dstAccess);

// A barrier on mips [firstMip, firstMip + mipCount) of every layer of `image`, with a layout change.
void imageBarrier(VkCommandBuffer commandBuffer, VkImage image, uint32_t firstMip, uint32_t mipCount, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags srcStage, VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

} // namespace probe::gpu
