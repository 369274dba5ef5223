// Buffers and images. Each buffer has a memory role (gpu/memory.h: where it lives on a discrete GPU, an
// integrated one or lavapipe); the choice is a pure function of the device's memory types.
//   createBuffer        mapped roles: Upload (default: per-frame data the CPU writes every frame, one buffer
//                       per frame in flight: frame constants, lights, instances, VSM maps), Readback (GPU
//                       writes, CPU reads: counters, probes, readbacks), Staging (copy sources). Persistently
//                       mapped, zeroed. GpuOnly given here goes to createDeviceBuffer.
//   createDeviceBuffer  GpuOnly: device-local, not mapped, filled with `fill` words: GPU state (cluster
//                       lists, VSM page tables and pools) and data the host writes at load time only through
//                       uploadBuffer (geometry, draws, static bakes: a staging copy, waits). The host reads
//                       them only through readBuffer (a staging copy, waits: setup and tests).
//   createImage         device-local 2D image with mips and layers (ImageDesc), a view of the whole image,
//                       a view per mip and optionally per (mip, layer); uploadImage / readImage move one
//                       mip of one layer through a staging buffer (setup and tests only).
// The module's paths use the Result forms (an out-parameter; out of memory is an error naming the
// resource, and on failure the out-parameter is empty). The value-returning forms abort on failure: for
// tests and tools only. Bytes per memory kind are counted on the device (Device::memoryUsage).
//
// Lifetimes. Every GPU-only resource is one copy shared by the frames in flight: frames on one queue are
// ordered by the frame-start barrier (module.cpp), so a frame never overlaps the previous one's work on
// it. What differs is whether its contents outlive the frame:
//   Lifetime::Persistent  contents carry from frame to frame (a frame reads what earlier frames wrote:
//                         page table, physical pages, owners); never discarded.
//   Lifetime::PerFrame    each frame writes it before reading it (cluster lists, HPB, output images);
//                         its first barrier in a frame discards the old contents (firstUseBarrier).
// Data the host writes or reads every frame instead lives in per-slot host-visible buffers (one per
// frame in flight: Module::Impl::Slot, VirtualShadowMaps::Slot), since the CPU cannot wait for the GPU.
#pragma once
#include "gpu/device.h"
#include "gpu/memory.h"

#include <algorithm>
#include <cstring>
#include <span>
#include <vector>

namespace ml {

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* data = nullptr; // mapped roles only
    VkDeviceSize size = 0;
    MemoryKind kind = MemoryKind::Host; // of `memory` (counted on the device, with the role)
    MemoryRole role = MemoryRole::Upload;
    VkDeviceSize allocated = 0; // bytes of `memory`

    template <class T> T* as() { return static_cast<T*>(data); }
    template <class T> const T* as() const { return static_cast<const T*>(data); }
};

enum class Lifetime : uint8_t { Persistent, PerFrame };

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE; // every mip and layer (2D, or 2D_ARRAY: layers > 1 or arrayViews)
    VkDeviceMemory memory = VK_NULL_HANDLE;
    MemoryKind kind = MemoryKind::DeviceLocal; // images are GPU-only
    VkDeviceSize allocated = 0;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0;
    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
    uint32_t mips = 1, layers = 1;
    Lifetime lifetime = Lifetime::PerFrame;
    std::vector<VkImageView>
        mipViews; // mipViews[m]: mip m, every layer (type as `view`); empty when mips == 1
    std::vector<VkImageView> layerViews; // layerViews[m * layers + l]: mip m of layer l (2D); on request

    uint32_t mipWidth(uint32_t mip) const { return std::max(1u, width >> mip); }
    uint32_t mipHeight(uint32_t mip) const { return std::max(1u, height >> mip); }
    VkImageView mipView(uint32_t mip) const { return mips == 1 ? view : mipViews[mip]; }
};

struct ImageDesc {
    uint32_t width = 1, height = 1;
    VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT;
    uint32_t mips = 1; // 0: the full chain down to 1x1
    uint32_t layers = 1;
    Lifetime lifetime = Lifetime::PerFrame;
    bool layerViews = false; // also create a 2D view per (mip, layer)
    bool arrayViews = false; // `view` and mipViews are 2D_ARRAY even with one layer (shaders indexing layers)
    const char* name = "image";
};

constexpr VkBufferUsageFlags kStorageBufferUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

// size 0 is allowed and becomes a 16-byte buffer, so empty scenes still bind valid descriptors.
Result<void> createBuffer(const Device& device, Buffer& out, VkDeviceSize size, VkBufferUsageFlags usage,
                          const char* name, MemoryRole role = MemoryRole::Upload);
Buffer createBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, const char* name,
                    MemoryRole role = MemoryRole::Upload); // aborts on failure (tests, tools)
// Device-local (falls back to any memory type the buffer allows); contents start as `fill` words.
Result<void> createDeviceBuffer(const Device& device, Buffer& out, VkDeviceSize size,
                                VkBufferUsageFlags usage, const char* name, uint32_t fill = 0);
Buffer createDeviceBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, const char* name,
                          uint32_t fill = 0); // aborts on failure (tests, tools)
// Host data into `buffer` at `offset`: a mapped buffer is written in place; a GPU-only one through a
// staging buffer and a copy, submitted and waited for (load time only: the caller has waited for the
// frames in flight that read the buffer).
Result<void> uploadBuffer(const Device& device, const Buffer& buffer, const void* data, VkDeviceSize bytes,
                          VkDeviceSize offset, const char* name);
// Copies `bytes` from `offset` of any buffer to the host through a staging buffer (waits for the queue).
std::vector<uint8_t> readBuffer(const Device& device, const Buffer& buffer, VkDeviceSize offset,
                                VkDeviceSize bytes);
// The whole buffer as an array of T (readBuffer: tests and tools read GPU-only buffers this way).
template <class T> std::vector<T> readBufferAs(const Device& device, const Buffer& buffer) {
    std::vector<uint8_t> bytes = readBuffer(device, buffer, 0, buffer.size);
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
    return out;
}
void destroyBuffer(const Device& device, Buffer& buffer);
// Grows (recreates) when smaller than `size`; contents are not kept. Returns true when recreated. On
// failure the buffer is left empty (destroyed), so a later call retries.
Result<bool> ensureBuffer(const Device& device, Buffer& buffer, VkDeviceSize size, VkBufferUsageFlags usage,
                          const char* name, MemoryRole role = MemoryRole::Upload);

// A buffer-to-buffer copy recorded at a frame's start (FrameSetup::record, or the module's staged
// uploads: engine/frame.h): load-time data or a grown buffer's old contents reach a GPU-only buffer
// without a host wait.
struct StagedCopy {
    VkBuffer source = VK_NULL_HANDLE, destination = VK_NULL_HANDLE;
    std::vector<VkBufferCopy> regions;
};

// The setup commands of the frame being recorded (record() never submits to or waits on the host's
// queue). While Module::record prepares a frame (active), a new GPU-only buffer's fill
// (createDeviceBuffer) and a grown buffer's copy of its old contents (copyBufferInFrame) are queued here
// instead of a one-time submit and wait, and the frame-begin pass records them at the start of the
// frame's own command buffer, before every pass (a copy whose source an earlier queued copy wrote, a
// buffer grown twice in one frame, waits for it). Buffers replaced meanwhile (releaseAfterFrame) are not
// destroyed but handed to the module, which frees them once the frames in flight that used them (and
// this frame's copies from them) are done. Owned by the module; Device::frameSetup points at it.
struct FrameSetup {
    bool active = false;
    struct Fill {
        VkBuffer buffer = VK_NULL_HANDLE;
        uint32_t value = 0;
    };
    std::vector<Fill> fills;
    std::vector<StagedCopy> copies;
    std::vector<Buffer> released;
    bool empty() const { return fills.empty() && copies.empty(); }
    // destroyBuffer: a queued command naming a destroyed buffer is dropped (a record() that failed after
    // queueing it made and then freed the buffer).
    void forget(VkBuffer buffer);
    // Fills, then copies (these and `more`), with the barriers between them; the caller's frame barrier
    // orders them before the passes.
    void record(VkCommandBuffer cmd, std::span<const StagedCopy> more) const;
};
// The frame's setup when one is being prepared (Device::frameSetup active), else null.
inline FrameSetup* activeSetup(const Device& device) {
    return device.frameSetup && device.frameSetup->active ? device.frameSetup : nullptr;
}
// `region` of `from` into `to`: queued into the frame being recorded, or (outside record(): create,
// tools) submitted and waited for. Out of memory is an error naming `name`.
Result<void> copyBufferInFrame(const Device& device, const Buffer& from, const Buffer& to,
                               const VkBufferCopy& region, const char* name);
// A buffer that frames in flight (or a queued copy) may still read: handed to the frame being recorded
// (released once it is done), or, outside record(), destroyed after a device wait. Clears `buffer`.
void releaseAfterFrame(const Device& device, Buffer& buffer);

// Mapped buffers only.
inline void upload(Buffer& buffer, const void* src, size_t bytes, size_t offset = 0) {
    std::memcpy(static_cast<char*>(buffer.data) + offset, src, bytes);
}

// One mip, one layer (the simple images: G-buffer, outputs), a PerFrame image.
Result<void> createImage(const Device& device, Image& out, uint32_t width, uint32_t height, VkFormat format,
                         VkImageUsageFlags usage, const char* name);
// Mips and layers. Refused naming the image when the device cannot hold it (dimension, layer limits).
// Transfer usage is added (uploadImage / readImage). The image starts in UNDEFINED layout.
Result<void> createImage(const Device& device, Image& out, const ImageDesc& desc);
// The same, aborting on failure (tests, tools).
Image createImage(const Device& device, uint32_t width, uint32_t height, VkFormat format,
                  VkImageUsageFlags usage, const char* name);
Image createImage(const Device& device, const ImageDesc& desc);
void destroyImage(const Device& device, Image& image);
// Bytes per texel of the formats the module uses (0 for others).
uint32_t formatBytes(VkFormat format);
// Copies `data` (mipWidth x mipHeight texels, tightly packed) into one mip of one layer through a staging
// buffer, and waits. That subresource goes from `from` (UNDEFINED: its contents are discarded) to `to`.
void uploadImage(const Device& device, const Image& image, uint32_t mip, uint32_t layer, const void* data,
                 size_t bytes, VkImageLayout from, VkImageLayout to);
// One mip of one layer, tightly packed, copied to the host through a staging buffer (waits); the
// subresource is in `layout` before and after.
std::vector<uint8_t> readImage(const Device& device, const Image& image, uint32_t mip, uint32_t layer,
                               VkImageLayout layout);

// Stage of vkCmdFillBuffer. The specification lists it among the clear commands (CLEAR); validation
// layers before 1.3.279 (bookworm has 1.3.239) track it at COPY (KhronosGroup/Vulkan-ValidationLayers
// #7406 on GitHub), so a barrier after a fill names both.
constexpr VkPipelineStageFlags2 kFillStages = VK_PIPELINE_STAGE_2_CLEAR_BIT | VK_PIPELINE_STAGE_2_COPY_BIT;
// Every use the module makes of a buffer: shader storage/uniform access in each stage it dispatches or
// draws with, indirect arguments, index fetch, fills and copies. For hand-offs whose other side is not
// known at the call (a new buffer's first use, a readback of whatever wrote last), not inside a frame.
constexpr VkPipelineStageFlags2 kBufferUseStages =
    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT |
    VK_PIPELINE_STAGE_2_TASK_SHADER_BIT_EXT | VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT |
    VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT |
    VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT;
constexpr VkAccessFlags2 kBufferWrites =
    VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT;
constexpr VkAccessFlags2 kBufferReads = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_UNIFORM_READ_BIT |
                                        VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT |
                                        VK_ACCESS_2_TRANSFER_READ_BIT;
// The frame's output images (tone-mapped, HDR) -> the host's next use after record(): copies and blits,
// sampled or storage reads in a fragment or compute shader. Images are never host-mapped.
constexpr VkPipelineStageFlags2 kOutputReaderStages = VK_PIPELINE_STAGE_2_TRANSFER_BIT |
                                                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                                                      VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkAccessFlags2 kOutputReads =
    VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT;

// Synchronisation2 helpers. memoryBarrier orders one hazard: writes `srcAccess` of stages `src` before
// accesses `dstAccess` of stages `dst` (say which resource at the call). fullBarrier covers all prior and
// later memory work of the given stages.
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess);
void fullBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkPipelineStageFlags2 dst);
// Dynamic rendering without attachments (the fragment shaders write storage with atomics) over a
// size x size area, viewport the same, scissor `scissor`; end it with vkCmdEndRendering.
void beginAttachmentless(VkCommandBuffer cmd, uint32_t size, VkExtent2D scissor);
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                  VkImageLayout to, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess);
// Mips [mip, mip + mipCount) of every layer.
void imageBarrier(VkCommandBuffer cmd, const Image& image, uint32_t mip, uint32_t mipCount,
                  VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess);
// An image's first barrier in a frame, by lifetime: a PerFrame image is discarded (UNDEFINED -> layout,
// the previous frame's accesses in `src` ordered before the transition); a Persistent image keeps its
// contents (layout -> layout: the previous frame's writes `srcAccess` made visible to `dstAccess`).
void firstUseBarrier(VkCommandBuffer cmd, const Image& image, VkImageLayout layout, VkPipelineStageFlags2 src,
                     VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess);

// Copies an image (in TRANSFER_SRC layout) into a host buffer, tightly packed.
void copyImageToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer);

} // namespace ml
