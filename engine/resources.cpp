#include "engine/resources.h"

#include <algorithm>

namespace ml {

namespace {
// Memory for `req`: of a type with all `flags`; with `fallback`, any type the resource allows when none
// has them (device-local is a preference: lavapipe's one memory type is host memory).
VkDeviceMemory allocate(const Device& device, const VkMemoryRequirements& req, VkMemoryPropertyFlags flags,
                        bool fallback, const char* name) {
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = device.memoryType(req.memoryTypeBits, flags);
    if (ai.memoryTypeIndex == ~0u && fallback) ai.memoryTypeIndex = device.memoryType(req.memoryTypeBits, 0);
    if (ai.memoryTypeIndex == ~0u) {
        std::fprintf(stderr, "%s:%d: no memory type 0x%x for %s\n", __FILE__, __LINE__, flags, name);
        std::abort();
    }
    VkDeviceMemory memory = VK_NULL_HANDLE;
    ML_VK_CHECK(vkAllocateMemory(device.device, &ai, nullptr, &memory));
    return memory;
}

Buffer makeBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags flags,
                  bool fallback, const char* name) {
    Buffer b;
    b.size = std::max<VkDeviceSize>((size + 3) / 4 * 4, 16);
    VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    ci.size = b.size;
    ci.usage = usage;
    ML_VK_CHECK(vkCreateBuffer(device.device, &ci, nullptr, &b.buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device.device, b.buffer, &req);
    b.memory = allocate(device, req, flags, fallback, name);
    ML_VK_CHECK(vkBindBufferMemory(device.device, b.buffer, b.memory, 0));
    device.setName(VK_OBJECT_TYPE_BUFFER, uint64_t(b.buffer), name);
    return b;
}
} // namespace

Buffer createBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, const char* name) {
    Buffer b = makeBuffer(device, size, usage, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                          false, name);
    ML_VK_CHECK(vkMapMemory(device.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.data));
    std::memset(b.data, 0, b.size);
    return b;
}

void destroyBuffer(const Device& device, Buffer& b) {
    if (b.memory && b.data) vkUnmapMemory(device.device, b.memory);
    if (b.buffer) vkDestroyBuffer(device.device, b.buffer, nullptr);
    if (b.memory) vkFreeMemory(device.device, b.memory, nullptr);
    b = Buffer{};
}

Buffer createDeviceBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, const char* name,
                          uint32_t fill) {
    Buffer b = makeBuffer(device, size, usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, true, name);
    VkCommandBuffer cmd = device.beginOneTime();
    vkCmdFillBuffer(cmd, b.buffer, 0, VK_WHOLE_SIZE, fill);
    // The fill -> the buffer's first use, whatever it is (read or write in any stage the module uses).
    memoryBarrier(cmd, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, kBufferUseStages, kBufferReads | kBufferWrites);
    device.endOneTime(cmd);
    return b;
}

std::vector<uint8_t> readBuffer(const Device& device, const Buffer& buffer, VkDeviceSize offset, VkDeviceSize bytes) {
    std::vector<uint8_t> out(bytes);
    if (!bytes) return out;
    Buffer staging = createBuffer(device, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "readback_staging");
    VkCommandBuffer cmd = device.beginOneTime();
    // The last writes to the buffer (any shader stage, fill or copy, earlier submissions) -> the copy.
    memoryBarrier(cmd, kBufferUseStages, kBufferWrites, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer.buffer, staging.buffer, 1, &region);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                  VK_ACCESS_2_HOST_READ_BIT);
    device.endOneTime(cmd);
    std::memcpy(out.data(), staging.data, bytes);
    destroyBuffer(device, staging);
    return out;
}

bool ensureBuffer(const Device& device, Buffer& b, VkDeviceSize size, VkBufferUsageFlags usage, const char* name) {
    if (b.buffer && b.size >= size) return false;
    destroyBuffer(device, b);
    // Grow by 1.5x so per-frame growth (more lights, more clusters) settles quickly.
    b = createBuffer(device, size + size / 2, usage, name);
    return true;
}

Image createImage(const Device& device, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                  const char* name) {
    Image img;
    img.format = format;
    img.width = width;
    img.height = height;
    bool depth = format == VK_FORMAT_D32_SFLOAT || format == VK_FORMAT_D16_UNORM;
    img.aspect = depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = format;
    ci.extent = {width, height, 1};
    ci.mipLevels = 1;
    ci.arrayLayers = 1;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = usage;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    ML_VK_CHECK(vkCreateImage(device.device, &ci, nullptr, &img.image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device.device, img.image, &req);
    img.memory = allocate(device, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, true, name);
    ML_VK_CHECK(vkBindImageMemory(device.device, img.image, img.memory, 0));
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = img.image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format;
    vi.subresourceRange = {img.aspect, 0, 1, 0, 1};
    ML_VK_CHECK(vkCreateImageView(device.device, &vi, nullptr, &img.view));
    device.setName(VK_OBJECT_TYPE_IMAGE, uint64_t(img.image), name);
    return img;
}

void destroyImage(const Device& device, Image& img) {
    if (img.view) vkDestroyImageView(device.device, img.view, nullptr);
    if (img.image) vkDestroyImage(device.device, img.image, nullptr);
    if (img.memory) vkFreeMemory(device.device, img.memory, nullptr);
    img = Image{};
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst,
                   VkAccessFlags2 dstAccess) {
    VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    mb.srcStageMask = src;
    mb.srcAccessMask = srcAccess;
    mb.dstStageMask = dst;
    mb.dstAccessMask = dstAccess;
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.memoryBarrierCount = 1;
    di.pMemoryBarriers = &mb;
    vkCmdPipelineBarrier2(cmd, &di);
}

void fullBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkPipelineStageFlags2 dst) {
    VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    mb.srcStageMask = src;
    mb.srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT;
    mb.dstStageMask = dst;
    mb.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.memoryBarrierCount = 1;
    di.pMemoryBarriers = &mb;
    vkCmdPipelineBarrier2(cmd, &di);
}

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst,
                  VkAccessFlags2 dstAccess) {
    VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    ib.srcStageMask = src;
    ib.srcAccessMask = srcAccess;
    ib.dstStageMask = dst;
    ib.dstAccessMask = dstAccess;
    ib.oldLayout = from;
    ib.newLayout = to;
    ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    ib.image = image;
    ib.subresourceRange = {aspect, 0, 1, 0, 1};
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.imageMemoryBarrierCount = 1;
    di.pImageMemoryBarriers = &ib;
    vkCmdPipelineBarrier2(cmd, &di);
}

void copyImageToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer) {
    VkBufferImageCopy region{};
    region.imageSubresource = {image.aspect, 0, 0, 1};
    region.imageExtent = {image.width, image.height, 1};
    vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.buffer, 1, &region);
}

} // namespace ml
