#include "buffer.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "device.h"
#include "probe/error.h"
#include "vulkan_check.h"

namespace probe::gpu {

Buffer::Buffer(const Device& device, VkDeviceSize bytes, Kind kind) : device_(device.device()), bytes_(bytes) {
    const Device::Impl& d = device.impl();
    if (kind == Kind::storage && bytes > d.limits.maxStorageBufferRange)
        throw ProbeError(
            fmt::format("Vulkan: {} needs a storage buffer of {} MiB, over its maxStorageBufferRange of {} MiB; use a smaller --size",
                        d.info.name, bytes >> 20, d.limits.maxStorageBufferRange >> 20));
    if (kind == Kind::texels && bytes / 16 > d.limits.maxTexelBufferElements)
        throw ProbeError(fmt::format("Vulkan: {} reads texel buffers of at most {} texels, this one needs {}; use a smaller --size",
                                     d.info.name, d.limits.maxTexelBufferElements, bytes / 16));
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                 (kind != Kind::staging ? VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT : 0);
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    vkCheck(vkCreateBuffer(device_, &info, nullptr, &buffer_), "vkCreateBuffer");

    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(device_, buffer_, &requirements);
    VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    allocate.allocationSize = requirements.size;
    allocate.memoryTypeIndex =
        kind != Kind::staging
            ? d.memoryType(requirements.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)
            : d.memoryType(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                           VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    try {
        vkCheck(vkAllocateMemory(device_, &allocate, nullptr, &memory_), "vkAllocateMemory");
        vkCheck(vkBindBufferMemory(device_, buffer_, memory_, 0), "vkBindBufferMemory");
        if (kind == Kind::staging) vkCheck(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
    } catch (...) {
        release();
        throw;
    }
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
    if (this != &other) {
        release();
        device_ = std::exchange(other.device_, VK_NULL_HANDLE);
        buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
        bytes_ = std::exchange(other.bytes_, 0);
        mapped_ = std::exchange(other.mapped_, nullptr);
    }
    return *this;
}

void Buffer::release() {
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
}

BufferView::BufferView(VkDevice device, const Buffer& buffer) : device_(device) {
    VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    info.buffer = buffer.handle();
    info.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    info.range = VK_WHOLE_SIZE;
    vkCheck(vkCreateBufferView(device_, &info, nullptr, &view_), "vkCreateBufferView");
}

BufferView::~BufferView() {
    if (view_) vkDestroyBufferView(device_, view_, nullptr);
}

BufferView::BufferView(BufferView&& other) noexcept { *this = std::move(other); }

BufferView& BufferView::operator=(BufferView&& other) noexcept {
    if (this != &other) {
        if (view_) vkDestroyBufferView(device_, view_, nullptr);
        device_ = std::exchange(other.device_, VK_NULL_HANDLE);
        view_ = std::exchange(other.view_, VK_NULL_HANDLE);
    }
    return *this;
}

std::vector<float> rgbaTexels(const CubeImage& level) {
    std::vector<float> texels;
    texels.reserve(4 * texelCount(level.size));
    for (std::size_t t = 0; t < texelCount(level.size); ++t) {
        const glm::vec3 c = level.texel(t);
        texels.insert(texels.end(), {c.r, c.g, c.b, 1.0f});
    }
    return texels;
}

std::size_t pyramidTexelIndex(int face, int i, int j, int size) {
    const std::size_t row = static_cast<std::size_t>(size) + 2;
    return (face * row + static_cast<std::size_t>(j + 1)) * row + static_cast<std::size_t>(i + 1);
}

std::vector<float> borderedRgbaTexels(const CubeImage& level) {
    const int size = level.size;
    // The texel of the level that (face, i, j) shows, for i or j (not both) one step outside the face.
    const auto neighbour = [&](int face, int i, int j) {
        Texel t;
        texelNeighbour({face, std::clamp(i, 0, size - 1), std::clamp(j, 0, size - 1)},
                       i < 0       ? -1
                       : i >= size ? 1
                                   : 0,
                       j < 0       ? -1
                       : j >= size ? 1
                                   : 0,
                       size, t);
        return level.texel(texelIndex(t, size));
    };
    std::vector<float> texels(4 * pyramidLevelTexels(size));
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = -1; j <= size; ++j)
            for (int i = -1; i <= size; ++i) {
                const bool insideI = i >= 0 && i < size, insideJ = j >= 0 && j < size;
                const int ci = std::clamp(i, 0, size - 1), cj = std::clamp(j, 0, size - 1);
                glm::vec3 c;
                if (insideI && insideJ) c = level.texel(texelIndex({f, i, j}, size));
                else if (insideI || insideJ) c = neighbour(f, i, j);
                else c = (level.texel(texelIndex({f, ci, cj}, size)) + neighbour(f, i, cj) + neighbour(f, ci, j)) * (1.0f / 3.0f);
                std::copy_n(&c.r, 3, &texels[4 * pyramidTexelIndex(f, i, j, size)]);
                texels[4 * pyramidTexelIndex(f, i, j, size) + 3] = 1.0f;
            }
    return texels;
}

} // namespace probe::gpu
