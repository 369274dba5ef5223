// The host side of the API-sequence fuzzer (tests/api_fuzz/api_fuzz.cpp): what a host engine owns around the
// module. Two frames in flight on the module's device (a command buffer and a fence per slot, waited for by
// the host outside record()), and host G-buffers handed over with setTargets, kept alive until the frames
// that may read them are done (the order docs/integration.md gives: wait, detachTargets, destroy).
#pragma once
#include "engine/module_impl.h"
#include "gpu/resources.h"
#include "manylights/glm.h"
#include "manylights/manylights.h"

#include <glm/gtc/packing.hpp>

#include <cstdint>
#include <vector>

namespace ml::fuzz {

// A host's G-buffer (depth, normal, albedo, optional material) and both outputs, uploaded once: a wall
// facing +Z at a fixed reversed depth, so that every pixel is a surface the lights reach.
struct HostGBuffer {
    uint32_t width = 0, height = 0;
    bool material = false;
    Image depth, normal, albedo, mat, ldr, hdr;

    static HostImage host(const Image& i, VkImageUsageFlags usage) {
        return {i.image, i.view, i.format, {i.width, i.height}, usage};
    }
    HostTargets targets(bool hdrOut) const {
        const VkImageUsageFlags sampled = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        const VkImageUsageFlags storage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        HostTargets t;
        t.width = width;
        t.height = height;
        t.depth = host(depth, sampled);
        t.normal = host(normal, sampled);
        t.albedo = host(albedo, sampled);
        if (material) t.material = host(mat, sampled);
        t.output = host(hdrOut ? hdr : ldr, storage);
        return t;
    }
};

inline HostGBuffer makeGBuffer(const Device& d, uint32_t w, uint32_t h, bool material) {
    HostGBuffer g;
    g.width = w;
    g.height = h;
    g.material = material;
    const VkImageUsageFlags sampled = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    const VkImageUsageFlags storage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    g.depth = createImage(d, w, h, VK_FORMAT_D32_SFLOAT, sampled, "fuzz_host_depth");
    g.normal = createImage(d, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, sampled, "fuzz_host_normal");
    g.albedo = createImage(d, w, h, VK_FORMAT_R8G8B8A8_UNORM, sampled, "fuzz_host_albedo");
    g.ldr = createImage(d, w, h, VK_FORMAT_R8G8B8A8_UNORM, storage, "fuzz_host_ldr");
    g.hdr = createImage(d, w, h, VK_FORMAT_R16G16B16A16_SFLOAT, storage, "fuzz_host_hdr");
    const size_t n = size_t(w) * h;
    const std::vector<float> depth(n, 0.02f); // reversed Z: a wall a few metres in front of the camera
    const std::vector<uint64_t> normal(n, uint64_t(glm::packHalf2x16({0.0f, 0.0f})) |
                                              (uint64_t(glm::packHalf2x16({1.0f, 1.0f})) << 32));
    const std::vector<uint32_t> albedo(n, 0xff808080u);
    const VkImageLayout ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    uploadImage(d, g.depth, 0, 0, depth.data(), n * 4, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    uploadImage(d, g.normal, 0, 0, normal.data(), n * 8, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    uploadImage(d, g.albedo, 0, 0, albedo.data(), n * 4, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    if (material) {
        g.mat = createImage(d, w, h, VK_FORMAT_R8G8_UNORM, sampled, "fuzz_host_material");
        const std::vector<uint16_t> rm(n, 0x0080); // roughness 0.5, metalness 0
        uploadImage(d, g.mat, 0, 0, rm.data(), n * 2, VK_IMAGE_LAYOUT_UNDEFINED, ro);
    }
    const std::vector<uint8_t> zeros(n * 8, 0);
    uploadImage(d, g.ldr, 0, 0, zeros.data(), n * 4, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
    uploadImage(d, g.hdr, 0, 0, zeros.data(), n * 8, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
    return g;
}

inline void destroyGBuffer(const Device& d, HostGBuffer& g) {
    for (Image* i : {&g.depth, &g.normal, &g.albedo, &g.mat, &g.ldr, &g.hdr})
        if (i->image != VK_NULL_HANDLE) destroyImage(d, *i);
}

// Two frames in flight: slot = (frames recorded) % 2. The host waits for the slot's fence before recording
// into it again (the module's slot contract); a refused record() leaves the slot's fence signalled and
// the frame count unchanged (the module's own count must agree: checked by the fuzzer through
// hostShaderBindings().frame).
class FrameLoop {
  public:
    explicit FrameLoop(Module& m) : m_(m), info_(m.deviceInfo()) {
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = info_.queueFamily;
        vkCreateCommandPool(info_.device, &pci, nullptr, &pool_);
        VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        ai.commandPool = pool_;
        ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        ai.commandBufferCount = 2;
        vkAllocateCommandBuffers(info_.device, &ai, cmd_);
        for (VkFence& f : fences_) {
            VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, nullptr, VK_FENCE_CREATE_SIGNALED_BIT};
            vkCreateFence(info_.device, &fci, nullptr, &f);
        }
    }
    ~FrameLoop() {
        waitAll();
        for (VkFence f : fences_) vkDestroyFence(info_.device, f, nullptr);
        vkDestroyCommandPool(info_.device, pool_, nullptr);
    }
    FrameLoop(const FrameLoop&) = delete;
    FrameLoop& operator=(const FrameLoop&) = delete;

    // Waits for the next slot's previous frame (skipWait: not, to check that the harness catches a host
    // that breaks the slot contract), records record() alone into its command buffer and submits it.
    Result<void> frame(bool skipWait = false) {
        const uint32_t slot = uint32_t(recorded_ % 2);
        if (!skipWait) vkWaitForFences(info_.device, 1, &fences_[slot], VK_TRUE, UINT64_MAX);
        m_.collect();
        m_.takeReports();
        VkCommandBuffer cmd = cmd_[slot];
        vkResetCommandBuffer(cmd, 0);
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkBeginCommandBuffer(cmd, &bi);
        auto r = m_.record(cmd);
        vkEndCommandBuffer(cmd);
        if (!r) return r;
        vkResetFences(info_.device, 1, &fences_[slot]);
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        if (VkResult v = vkQueueSubmit(info_.queue, 1, &si, fences_[slot]); v != VK_SUCCESS)
            return fail(std::string("vkQueueSubmit: ") + vkResultName(v));
        ++recorded_;
        return {};
    }
    // Both slots' frames done (before the host destroys images they read, or calls a waiting convenience).
    void waitAll() { vkWaitForFences(info_.device, 2, fences_, VK_TRUE, UINT64_MAX); }
    // Frames recorded by record() or submitFrame(): the module's frame counter.
    uint64_t recorded() const { return recorded_; }
    void countSubmitFrame() { ++recorded_; }

  private:
    Module& m_;
    DeviceInfo info_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_[2]{};
    VkFence fences_[2]{};
    uint64_t recorded_ = 0;
};

} // namespace ml::fuzz
