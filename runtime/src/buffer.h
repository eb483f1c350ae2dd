// A VkBuffer with its own memory: device-local storage, or host-visible staging (mapped).
#pragma once

#include <vector>

#include <vulkan/vulkan.h>

#include "probe/runtime.h"

namespace probe::gpu {

class Buffer {
public:
    enum class Kind {
        storage, // device local (preferred), storage and uniform texel buffer, transfer source and destination
        texels,  // the same, bound whole as an RGBA32F texel buffer or in storage-buffer windows (never whole as
                 // a storage buffer): its size is bounded by the texel-buffer element count, not the storage-buffer range
        staging, // host visible and coherent, mapped, transfer source and destination
    };

    Buffer() = default;
    Buffer(const Device& device, VkDeviceSize bytes, Kind kind);
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize bytes() const { return bytes_; }
    // The mapped memory of a staging buffer (nullptr for storage).
    void* mapped() const { return mapped_; }

private:
    void release();

    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize bytes_ = 0;
    void* mapped_ = nullptr;
};

// An RGBA32F view of a whole buffer, to bind as a uniform texel buffer.
class BufferView {
public:
    BufferView() = default;
    BufferView(VkDevice device, const Buffer& buffer);
    ~BufferView();
    BufferView(BufferView&& other) noexcept;
    BufferView& operator=(BufferView&& other) noexcept;

    VkBufferView handle() const { return view_; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkBufferView view_ = VK_NULL_HANDLE;
};

// The texels of a cube level in the storage buffers' layout: RGBA32F, alpha 1, in texelIndex order.
std::vector<float> rgbaTexels(const CubeImage& level);

// The pyramid buffer's layout (shaders/buffers.glsl): each face of a level of face size S with a
// one-texel border, (S + 2)^2 texels, texel (i, j) for i, j in [-1, S]. The index of (face, i, j) in
// a level, and the texels of a level.
std::size_t pyramidTexelIndex(int face, int i, int j, int size);
inline std::size_t pyramidLevelTexels(int size) { return pyramidTexelIndex(kFaceCount, -1, -1, size); }

// A cube level in that layout, RGBA32F, alpha 1, with its border filled as pyramid.comp fills it:
// the adjacent face's texel (probe::texelNeighbour), and at the corners, the average of the three
// texels that meet there.
std::vector<float> borderedRgbaTexels(const CubeImage& level);

} // namespace probe::gpu
