#include "gpu/resources.h"

#include "gpu/memory.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <string>

namespace ml {

namespace {
std::string vkError(const char* call, const char* name, VkResult r) {
    return std::string(call) + " for '" + name + "' failed: " + vkResultName(r);
}

std::string mib(VkDeviceSize bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / (1 << 20));
    return text;
}

// Memory for `req` in `role` (gpu/memory.h); its kind and size are counted on the device until freed.
Result<void> allocate(const Device& device, const VkMemoryRequirements& req, MemoryRole role,
                      const char* name, VkDeviceMemory& memory, MemoryKind& kind) {
    const MemoryChoice c = selectMemoryType(device.memoryProperties, req.memoryTypeBits, role, req.size);
    if (c.type == ~0u)
        return fail(std::string("no memory type for '") + name + "' (" + memoryRoleName(role) +
                    ", allowed types 0x" + std::to_string(req.memoryTypeBits) + ")");
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = c.type;
    if (VkResult r = ML_VK_ALLOC(vkAllocateMemory(device.device, &ai, nullptr, &memory)); r != VK_SUCCESS) {
        memory = VK_NULL_HANDLE;
        return fail(vkError("vkAllocateMemory", name, r) + " (" + mib(req.size) + ", " +
                    memoryKindName(c.kind) + ")");
    }
    kind = c.kind;
    device.countMemory(kind, uint32_t(role), int64_t(req.size));
    return {};
}

void freeMemory(const Device& device, VkDeviceMemory& memory, MemoryKind kind, MemoryRole role,
                VkDeviceSize bytes) {
    if (!memory) return;
    vkFreeMemory(device.device, memory, nullptr);
    device.countMemory(kind, uint32_t(role), -int64_t(bytes));
    memory = VK_NULL_HANDLE;
}

// On failure `b` holds whatever was made (destroyBuffer releases it).
Result<void> makeBuffer(const Device& device, Buffer& b, VkDeviceSize size, VkBufferUsageFlags usage,
                        MemoryRole role, const char* name) {
    b = Buffer{};
    b.size = std::max<VkDeviceSize>((size + 3) / 4 * 4, 16);
    VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    ci.size = b.size;
    ci.usage = usage;
    if (VkResult r = ML_VK_ALLOC(vkCreateBuffer(device.device, &ci, nullptr, &b.buffer)); r != VK_SUCCESS) {
        b.buffer = VK_NULL_HANDLE;
        return fail(vkError("vkCreateBuffer", name, r) + " (" + mib(b.size) + ")");
    }
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device.device, b.buffer, &req);
    ML_TRY(allocate(device, req, role, name, b.memory, b.kind));
    b.role = role;
    b.allocated = req.size;
    ML_VK_CHECK(vkBindBufferMemory(device.device, b.buffer, b.memory, 0)); // fails only on a bug
    device.setName(VK_OBJECT_TYPE_BUFFER, uint64_t(b.buffer), name);
    if (roleIsMapped(role)) {
        if (VkResult r = ML_VK_ALLOC(vkMapMemory(device.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.data));
            r != VK_SUCCESS) {
            b.data = nullptr;
            return fail(vkError("vkMapMemory", name, r));
        }
        std::memset(b.data, 0, b.size);
    }
    return {};
}

template <class T> T orAbort(Result<T> r) {
    if (!r) {
        std::fprintf(stderr, "%s\n", r.error().c_str());
        std::abort();
    }
    return std::move(r.value());
}
void orAbort(Result<void> r) {
    if (!r) {
        std::fprintf(stderr, "%s\n", r.error().c_str());
        std::abort();
    }
}
} // namespace

Result<void> createBuffer(const Device& device, Buffer& out, VkDeviceSize size, VkBufferUsageFlags usage,
                          const char* name, MemoryRole role) {
    if (!roleIsMapped(role)) return createDeviceBuffer(device, out, size, usage, name);
    if (auto r = makeBuffer(device, out, size, usage, role, name); !r) {
        destroyBuffer(device, out);
        return r;
    }
    return {};
}

Buffer createBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, const char* name,
                    MemoryRole role) {
    Buffer b;
    orAbort(createBuffer(device, b, size, usage, name, role));
    return b;
}

void destroyBuffer(const Device& device, Buffer& b) {
    if (device.frameSetup && b.buffer) device.frameSetup->forget(b.buffer);
    if (b.memory && b.data) vkUnmapMemory(device.device, b.memory);
    if (b.buffer) vkDestroyBuffer(device.device, b.buffer, nullptr);
    freeMemory(device, b.memory, b.kind, b.role, b.allocated);
    b = Buffer{};
}

Result<void> createDeviceBuffer(const Device& device, Buffer& b, VkDeviceSize size, VkBufferUsageFlags usage,
                                const char* name, uint32_t fill) {
    auto made = makeBuffer(device, b, size,
                           usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           MemoryRole::GpuOnly, name);
    // Inside record() the fill goes into the frame's own command buffer (FrameSetup), ahead of every
    // pass: a one-time submit here would submit to and wait on the host's queue behind its back.
    if (FrameSetup* setup = activeSetup(device); setup && made) {
        setup->fills.push_back({b.buffer, fill});
        return {};
    }
    auto cmd = made ? device.tryBeginOneTime(name) : Result<VkCommandBuffer>(fail(made.error()));
    if (!cmd) {
        destroyBuffer(device, b);
        return fail(cmd.error());
    }
    vkCmdFillBuffer(cmd.value(), b.buffer, 0, VK_WHOLE_SIZE, fill);
    // The fill -> the buffer's first use, whatever it is (read or write in any stage the module uses).
    memoryBarrier(cmd.value(), kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, kBufferUseStages,
                  kBufferReads | kBufferWrites);
    if (auto r = device.tryEndOneTime(cmd.value(), name); !r) {
        destroyBuffer(device, b);
        return r;
    }
    return {};
}

Buffer createDeviceBuffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, const char* name,
                          uint32_t fill) {
    Buffer b;
    orAbort(createDeviceBuffer(device, b, size, usage, name, fill));
    return b;
}

Result<void> uploadBuffer(const Device& device, const Buffer& buffer, const void* data, VkDeviceSize bytes,
                          VkDeviceSize offset, const char* name) {
    if (!bytes) return {};
    if (buffer.data) { // mapped (an upload-role buffer): written in place
        std::memcpy(static_cast<char*>(buffer.data) + offset, data, bytes);
        return {};
    }
    Buffer staging;
    ML_TRY(createBuffer(device, staging, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, name, MemoryRole::Staging));
    std::memcpy(staging.data, data, bytes);
    auto cmd = device.tryBeginOneTime(name);
    if (!cmd) {
        destroyBuffer(device, staging);
        return fail(cmd.error());
    }
    // Earlier uses of the range (frames in flight were waited for by the caller; setup reads) -> the copy.
    memoryBarrier(cmd.value(), kBufferUseStages, kBufferReads | kBufferWrites, VK_PIPELINE_STAGE_2_COPY_BIT,
                  VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(cmd.value(), staging.buffer, buffer.buffer, 1, &region);
    // The staging copy -> every later use of the buffer.
    memoryBarrier(cmd.value(), VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, kBufferUseStages,
                  kBufferReads | kBufferWrites);
    auto r = device.tryEndOneTime(cmd.value(), name);
    destroyBuffer(device, staging);
    return r;
}

void FrameSetup::forget(VkBuffer buffer) {
    std::erase_if(fills, [&](const Fill& f) { return f.buffer == buffer; });
    std::erase_if(copies, [&](const StagedCopy& c) { return c.source == buffer || c.destination == buffer; });
}

void FrameSetup::record(VkCommandBuffer cmd, std::span<const StagedCopy> more) const {
    // Earlier frames' accesses to a grown buffer's old contents (any stage, e.g. the VSM passes' page
    // table writes) -> the copy reading them. Fills and staged copies write new buffers or unread ranges:
    // nothing earlier to order.
    if (!copies.empty())
        memoryBarrier(cmd, kBufferUseStages, kBufferWrites, kFillStages,
                      VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
    for (const Fill& f : fills) vkCmdFillBuffer(cmd, f.buffer, 0, VK_WHOLE_SIZE, f.value);
    // A new buffer's fill -> a copy into it (write-after-write: the grown page table is filled, then its
    // old entries are copied over).
    if (!fills.empty() && (!copies.empty() || !more.empty()))
        memoryBarrier(cmd, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, kFillStages,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT);
    // A copy reading what an earlier copy of the list wrote (read-after-write: a buffer grown twice while
    // one frame was prepared, A -> B then B -> C) waits for it. Growth is rare, so one list scan is cheap.
    for (size_t i = 0; i < copies.size(); ++i) {
        const StagedCopy& c = copies[i];
        bool after = false;
        for (size_t j = 0; j < i && !after; ++j) after = copies[j].destination == c.source;
        if (after)
            memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                          VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
        vkCmdCopyBuffer(cmd, c.source, c.destination, uint32_t(c.regions.size()), c.regions.data());
    }
    for (const StagedCopy& c : more)
        vkCmdCopyBuffer(cmd, c.source, c.destination, uint32_t(c.regions.size()), c.regions.data());
}

Result<void> copyBufferInFrame(const Device& device, const Buffer& from, const Buffer& to,
                               const VkBufferCopy& region, const char* name) {
    if (FrameSetup* setup = activeSetup(device)) {
        setup->copies.push_back({from.buffer, to.buffer, {region}});
        return {};
    }
    auto cmd = device.tryBeginOneTime(name);
    if (!cmd) return fail(cmd.error());
    // Earlier uses of both buffers (the caller waited for the frames in flight) -> the copy; the copy ->
    // every later use of the destination.
    memoryBarrier(cmd.value(), kBufferUseStages, kBufferWrites, VK_PIPELINE_STAGE_2_COPY_BIT,
                  VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdCopyBuffer(cmd.value(), from.buffer, to.buffer, 1, &region);
    memoryBarrier(cmd.value(), VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, kBufferUseStages,
                  kBufferReads | kBufferWrites);
    return device.tryEndOneTime(cmd.value(), name);
}

void releaseAfterFrame(const Device& device, Buffer& buffer) {
    if (!buffer.buffer) return;
    if (FrameSetup* setup = activeSetup(device)) {
        setup->released.push_back(buffer);
        buffer = Buffer{};
        return;
    }
    device.waitDevice(); // outside record(): a host call at load time may wait
    destroyBuffer(device, buffer);
}

std::vector<uint8_t> readBuffer(const Device& device, const Buffer& buffer, VkDeviceSize offset,
                                VkDeviceSize bytes) {
    std::vector<uint8_t> out(bytes);
    if (!bytes) return out;
    Buffer staging = createBuffer(device, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "readback_staging",
                                  MemoryRole::Readback);
    VkCommandBuffer cmd = device.beginOneTime();
    // The last writes to the buffer (any shader stage, fill or copy, earlier submissions) -> the copy.
    memoryBarrier(cmd, kBufferUseStages, kBufferWrites, VK_PIPELINE_STAGE_2_COPY_BIT,
                  VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer.buffer, staging.buffer, 1, &region);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    device.endOneTime(cmd);
    std::memcpy(out.data(), staging.data, bytes);
    destroyBuffer(device, staging);
    return out;
}

Result<bool> ensureBuffer(const Device& device, Buffer& b, VkDeviceSize size, VkBufferUsageFlags usage,
                          const char* name, MemoryRole role) {
    if (b.buffer && b.size >= size) return false;
    destroyBuffer(device, b);
    // Grow by 1.5x so per-frame growth (more lights, more clusters) settles quickly, but a storage buffer
    // that fits the device's storage buffer range stays within it: shaders bind it whole (VK_WHOLE_SIZE).
    VkDeviceSize grown = size + size / 2;
    const VkDeviceSize range = device.properties.limits.maxStorageBufferRange;
    if ((usage & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) && size <= range) grown = std::min(grown, range);
    ML_TRY(
        createBuffer(device, b, grown, usage, name, role)); // on failure `b` is empty: the next call retries
    return true;
}

namespace {
Result<VkImageView> makeView(const Device& device, const Image& img, VkImageViewType type, uint32_t mip,
                             uint32_t mipCount, uint32_t layer, uint32_t layerCount, const char* name) {
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = img.image;
    vi.viewType = type;
    vi.format = img.format;
    vi.subresourceRange = {img.aspect, mip, mipCount, layer, layerCount};
    VkImageView view = VK_NULL_HANDLE;
    if (VkResult r = ML_VK_ALLOC(vkCreateImageView(device.device, &vi, nullptr, &view)); r != VK_SUCCESS)
        return fail(vkError("vkCreateImageView", name, r));
    return view;
}

Error imageError(const char* name, const std::string& why) {
    return fail(std::string("createImage ") + name + ": " + why);
}
} // namespace

uint32_t formatBytes(VkFormat format) {
    switch (format) {
    case VK_FORMAT_R8_UINT:
    case VK_FORMAT_R8_UNORM:
        return 1;
    case VK_FORMAT_R16_UINT:
    case VK_FORMAT_R16_SFLOAT:
    case VK_FORMAT_R8G8_UNORM:
        return 2;
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_UINT:
        return 4;
    case VK_FORMAT_R32G32_UINT:
    case VK_FORMAT_R16G16B16A16_SFLOAT:
        return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT:
        return 16;
    default:
        return 0;
    }
}

namespace {
Result<void> makeImage(const Device& device, Image& img, const ImageDesc& desc) {
    img = Image{};
    img.format = desc.format;
    img.width = desc.width;
    img.height = desc.height;
    img.layers = desc.layers;
    img.lifetime = desc.lifetime;
    const uint32_t fullChain = uint32_t(std::bit_width(std::max(desc.width, desc.height)));
    img.mips = desc.mips ? desc.mips : fullChain;
    const bool depth = desc.format == VK_FORMAT_D32_SFLOAT || desc.format == VK_FORMAT_D16_UNORM;
    img.aspect = depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
    const VkPhysicalDeviceLimits& lim = device.properties.limits;
    if (!desc.width || !desc.height || desc.width > lim.maxImageDimension2D ||
        desc.height > lim.maxImageDimension2D)
        return imageError(desc.name, std::to_string(desc.width) + "x" + std::to_string(desc.height) +
                                         " outside 1.." + std::to_string(lim.maxImageDimension2D));
    if (!desc.layers || desc.layers > lim.maxImageArrayLayers)
        return imageError(desc.name, std::to_string(desc.layers) + " layers outside 1.." +
                                         std::to_string(lim.maxImageArrayLayers));
    if (img.mips > fullChain)
        return imageError(desc.name, std::to_string(img.mips) + " mips, the chain of " +
                                         std::to_string(desc.width) + "x" + std::to_string(desc.height) +
                                         " has " + std::to_string(fullChain));
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = desc.format;
    ci.extent = {desc.width, desc.height, 1};
    ci.mipLevels = img.mips;
    ci.arrayLayers = desc.layers;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    ci.usage = desc.usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImageFormatProperties fp{};
    if (vkGetPhysicalDeviceImageFormatProperties(device.physicalDevice, ci.format, ci.imageType, ci.tiling,
                                                 ci.usage, 0, &fp) != VK_SUCCESS)
        return imageError(desc.name,
                          "format " + std::to_string(int(desc.format)) + " does not support the usage");
    if (VkResult r = ML_VK_ALLOC(vkCreateImage(device.device, &ci, nullptr, &img.image)); r != VK_SUCCESS) {
        img.image = VK_NULL_HANDLE;
        return fail(vkError("vkCreateImage", desc.name, r) + " (" + std::to_string(desc.width) + "x" +
                    std::to_string(desc.height) + ", " + std::to_string(img.mips) + " mips, " +
                    std::to_string(desc.layers) + " layers)");
    }
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device.device, img.image, &req);
    ML_TRY(allocate(device, req, MemoryRole::GpuOnly, desc.name, img.memory, img.kind));
    img.allocated = req.size;
    ML_VK_CHECK(vkBindImageMemory(device.device, img.image, img.memory, 0)); // fails only on a bug
    const VkImageViewType type =
        desc.layers > 1 || desc.arrayViews ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    auto view = makeView(device, img, type, 0, img.mips, 0, desc.layers, desc.name);
    ML_TRY(view);
    img.view = view.value();
    if (img.mips > 1)
        for (uint32_t m = 0; m < img.mips; ++m) {
            auto v = makeView(device, img, type, m, 1, 0, desc.layers, desc.name);
            ML_TRY(v);
            img.mipViews.push_back(v.value());
        }
    if (desc.layerViews)
        for (uint32_t m = 0; m < img.mips; ++m)
            for (uint32_t l = 0; l < desc.layers; ++l) {
                auto v = makeView(device, img, VK_IMAGE_VIEW_TYPE_2D, m, 1, l, 1, desc.name);
                ML_TRY(v);
                img.layerViews.push_back(v.value());
            }
    device.setName(VK_OBJECT_TYPE_IMAGE, uint64_t(img.image), desc.name);
    return {};
}
} // namespace

Result<void> createImage(const Device& device, Image& out, const ImageDesc& desc) {
    if (auto r = makeImage(device, out, desc); !r) {
        destroyImage(device, out);
        return r;
    }
    return {};
}

Image createImage(const Device& device, const ImageDesc& desc) {
    Image img;
    orAbort(createImage(device, img, desc));
    return img;
}

Result<void> createImage(const Device& device, Image& out, uint32_t width, uint32_t height, VkFormat format,
                         VkImageUsageFlags usage, const char* name) {
    ImageDesc desc;
    desc.width = width;
    desc.height = height;
    desc.format = format;
    desc.usage = usage;
    desc.name = name;
    return createImage(device, out, desc);
}

Image createImage(const Device& device, uint32_t width, uint32_t height, VkFormat format,
                  VkImageUsageFlags usage, const char* name) {
    Image img;
    orAbort(createImage(device, img, width, height, format, usage, name));
    return img;
}

void destroyImage(const Device& device, Image& img) {
    for (VkImageView v : img.mipViews) vkDestroyImageView(device.device, v, nullptr);
    for (VkImageView v : img.layerViews) vkDestroyImageView(device.device, v, nullptr);
    if (img.view) vkDestroyImageView(device.device, img.view, nullptr);
    if (img.image) vkDestroyImage(device.device, img.image, nullptr);
    freeMemory(device, img.memory, img.kind, MemoryRole::GpuOnly, img.allocated);
    img = Image{};
}

namespace {
void rangeBarrier(VkCommandBuffer cmd, VkImage image, VkImageSubresourceRange range, VkImageLayout from,
                  VkImageLayout to, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess) {
    VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    ib.srcStageMask = src;
    ib.srcAccessMask = srcAccess;
    ib.dstStageMask = dst;
    ib.dstAccessMask = dstAccess;
    ib.oldLayout = from;
    ib.newLayout = to;
    ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    ib.image = image;
    ib.subresourceRange = range;
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.imageMemoryBarrierCount = 1;
    di.pImageMemoryBarriers = &ib;
    vkCmdPipelineBarrier2(cmd, &di);
}

// Any earlier use of an image (shaders, attachments, copies) -> the staging copy, and back.
constexpr VkPipelineStageFlags2 kImageUseStages =
    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TASK_SHADER_BIT_EXT |
    VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
    VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT |
    VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT;
constexpr VkAccessFlags2 kImageWrites =
    VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT;
constexpr VkAccessFlags2 kImageReads =
    VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT |
    VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
    VK_ACCESS_2_TRANSFER_READ_BIT;

void subresourceBarrier(VkCommandBuffer cmd, const Image& image, uint32_t mip, uint32_t layer,
                        VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 src,
                        VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess) {
    rangeBarrier(cmd, image.image, {image.aspect, mip, 1, layer, 1}, from, to, src, srcAccess, dst,
                 dstAccess);
}

VkBufferImageCopy subresourceCopy(const Image& image, uint32_t mip, uint32_t layer) {
    VkBufferImageCopy region{};
    region.imageSubresource = {image.aspect, mip, layer, 1};
    region.imageExtent = {image.mipWidth(mip), image.mipHeight(mip), 1};
    return region;
}

size_t subresourceBytes(const Image& image, uint32_t mip) {
    return size_t(image.mipWidth(mip)) * image.mipHeight(mip) * formatBytes(image.format);
}

void checkSubresource(const Image& image, uint32_t mip, uint32_t layer, const char* what) {
    if (mip >= image.mips || layer >= image.layers || !formatBytes(image.format)) {
        std::fprintf(stderr, "%s: mip %u layer %u of an image of %u mips, %u layers (format %d)\n", what, mip,
                     layer, image.mips, image.layers, int(image.format));
        std::abort();
    }
}
} // namespace

void uploadImage(const Device& device, const Image& image, uint32_t mip, uint32_t layer, const void* data,
                 size_t bytes, VkImageLayout from, VkImageLayout to) {
    checkSubresource(image, mip, layer, "uploadImage");
    if (bytes != subresourceBytes(image, mip)) {
        std::fprintf(stderr, "uploadImage: %zu bytes for mip %u (%ux%u texels of %u bytes)\n", bytes, mip,
                     image.mipWidth(mip), image.mipHeight(mip), formatBytes(image.format));
        std::abort();
    }
    Buffer staging =
        createBuffer(device, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, "upload_staging", MemoryRole::Staging);
    std::memcpy(staging.data, data, bytes);
    VkCommandBuffer cmd = device.beginOneTime();
    // Earlier uses of the subresource (write-after-read/write; none when discarded) -> the copy's writes.
    subresourceBarrier(cmd, image, mip, layer, from, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, kImageUseStages,
                       kImageWrites, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy region = subresourceCopy(image, mip, layer);
    vkCmdCopyBufferToImage(cmd, staging.buffer, image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &region);
    // The copy's writes -> every later use.
    subresourceBarrier(cmd, image, mip, layer, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, to,
                       VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, kImageUseStages,
                       kImageReads | kImageWrites);
    device.endOneTime(cmd);
    destroyBuffer(device, staging);
}

std::vector<uint8_t> readImage(const Device& device, const Image& image, uint32_t mip, uint32_t layer,
                               VkImageLayout layout) {
    checkSubresource(image, mip, layer, "readImage");
    std::vector<uint8_t> out(subresourceBytes(image, mip));
    Buffer staging = createBuffer(device, out.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, "readback_staging",
                                  MemoryRole::Readback);
    VkCommandBuffer cmd = device.beginOneTime();
    // The last writes of the subresource -> the copy's reads.
    subresourceBarrier(cmd, image, mip, layer, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kImageUseStages,
                       kImageWrites, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy region = subresourceCopy(image, mip, layer);
    vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer, 1,
                           &region);
    // The copy's reads -> later writes (write-after-read); the staging writes -> the host.
    subresourceBarrier(cmd, image, mip, layer, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout,
                       VK_PIPELINE_STAGE_2_COPY_BIT, 0, kImageUseStages, 0);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    device.endOneTime(cmd);
    std::memcpy(out.data(), staging.data, out.size());
    destroyBuffer(device, staging);
    return out;
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess) {
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

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                  VkImageLayout to, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess) {
    rangeBarrier(cmd, image, {aspect, 0, 1, 0, 1}, from, to, src, srcAccess, dst, dstAccess);
}

void copyImageToBuffer(VkCommandBuffer cmd, const Image& image, const Buffer& buffer) {
    VkBufferImageCopy region{};
    region.imageSubresource = {image.aspect, 0, 0, 1};
    region.imageExtent = {image.width, image.height, 1};
    vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.buffer, 1, &region);
}

void imageBarrier(VkCommandBuffer cmd, const Image& image, uint32_t mip, uint32_t mipCount,
                  VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess,
                  VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess) {
    rangeBarrier(cmd, image.image, {image.aspect, mip, mipCount, 0, image.layers}, from, to, src, srcAccess,
                 dst, dstAccess);
}

void firstUseBarrier(VkCommandBuffer cmd, const Image& image, VkImageLayout layout, VkPipelineStageFlags2 src,
                     VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst, VkAccessFlags2 dstAccess) {
    if (image.lifetime == Lifetime::PerFrame) // discarded: only the execution order against earlier accesses
        imageBarrier(cmd, image, 0, image.mips, VK_IMAGE_LAYOUT_UNDEFINED, layout, src, 0, dst, dstAccess);
    else
        imageBarrier(cmd, image, 0, image.mips, layout, layout, src, srcAccess, dst, dstAccess);
}

void beginAttachmentless(VkCommandBuffer cmd, uint32_t size, VkExtent2D scissor) {
    VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
    ri.renderArea = {{0, 0}, {size, size}};
    ri.layerCount = 1;
    vkCmdBeginRendering(cmd, &ri);
    VkViewport vp{0, 0, float(size), float(size), 0, 1};
    VkRect2D sc{{0, 0}, scissor};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
}

} // namespace ml
