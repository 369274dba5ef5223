// Buffers and images.
//   createBuffer        host-visible, persistently mapped: per-frame data the CPU writes (frame constants,
//                       lights, instances) and small readbacks (counters). On lavapipe all memory is host
//                       memory; on a discrete GPU this is host-visible device memory or system memory.
//   createDeviceBuffer  device-local, not mapped: persistent GPU state (shadow page tables and pools,
//                       cluster lists). The host reaches it only through fillDeviceBuffer / readBuffer,
//                       which record a copy through a staging buffer and wait (setup and tests only).
#pragma once
#include "engine/device.h"

#include <cstring>
#include <span>
#include <vector>

namespace ml {

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* data = nullptr;
    VkDeviceSize size = 0;

    template <class T> T* as() { return static_cast<T*>(data); }
    template <class T> const T* as() const { return static_cast<const T*>(data); }
};

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0;
    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
};

constexpr VkBufferUsageFlags kStorageBufferUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT;

// size 0 is allowed and becomes a 16-byte buffer, so empty scenes still bind valid descriptors.
Buffer createBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, const char* name);
// Device-local (falls back to any memory type the buffer allows); contents start as `fill` words.
Buffer createDeviceBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, const char* name,
                          uint32_t fill = 0);
// Copies `bytes` from `offset` of any buffer to the host through a staging buffer (waits for the queue).
std::vector<uint8_t> readBuffer(const Device& device, const Buffer& buffer, VkDeviceSize offset, VkDeviceSize bytes);
void destroyBuffer(const Device& device, Buffer& buffer);
// Grows (recreates) when smaller than `size`; contents are not kept. Returns true when recreated.
bool ensureBuffer(const Device& device, Buffer& buffer, VkDeviceSize size, VkBufferUsageFlags usage, const char* name);
inline void upload(Buffer& buffer, const void* src, size_t bytes, size_t offset = 0) {
    std::memcpy(static_cast<char*>(buffer.data) + offset, src, bytes);
}

Image createImage(const Device& device, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                  const char* name);
void destroyImage(const Device& device, Image& image);

// Synchronisation2 helpers. memoryBarrier orders one hazard: writes `srcAccess` of stages `src` before
// accesses `dstAccess` of stages `dst` (say which resource at the call). fullBarrier covers all prior and
// later memory work of the given stages.
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst,
                   VkAccessFlags2 dstAccess);
void fullBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkPipelineStageFlags2 dst);
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                  VkImageLayout to, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst,
                  VkAccessFlags2 dstAccess);

// Copies an image (in TRANSFER_SRC layout) into a host buffer, tightly packed.
void copyImageToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer);

} // namespace ml
