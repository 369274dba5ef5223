// Helpers for the GPU tests: a module on lavapipe with validation on, a scene bound to it, image
// readback. Every test ends by checking that the validation layer reported no error or warning.
#pragma once
#include "manylights/glm.h"
#include "manylights/manylights.h"
#include "engine/module_impl.h"
#include "shadows/static/static_method.h"
#include "host/scene_host.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <glm/gtc/packing.hpp>

#include <cstring>

namespace ml::test {

// Virtual shadow maps are off unless asked for: the shading references here model static shadows only
// (the VSM tests compare with their own references).
inline std::unique_ptr<Module> makeModule(CullingMode mode = CullingMode::Clustered, bool vsm = false) {
    resetValidationCounters(); // process-wide; ctest runs each test in its own process anyway
    ModuleOptions o;
    o.device.validation = true;
    o.culling = mode;
    o.statistics = true; // the tests compare the per-pixel counts
    o.vsm.enabled = vsm;
    auto m = Module::create(o);
    EXPECT_TRUE(m.ok()) << m.error();
    return m ? std::move(m.value()) : nullptr;
}

// Copies an image that is in `layout` into host memory (tightly packed) and returns it to `layout`.
inline std::vector<uint8_t> readImage(Module& module, const Image& image, uint32_t texelBytes,
                                      VkImageLayout layout) {
    Device& d = deviceOf(module);
    vkQueueWaitIdle(d.queue);
    Buffer b = createBuffer(d, VkDeviceSize(image.width) * image.height * texelBytes,
                            VK_BUFFER_USAGE_TRANSFER_DST_BIT, "test_readback");
    VkCommandBuffer cmd = d.beginOneTime();
    imageBarrier(cmd, image.image, image.aspect, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    copyImageToBuffer(cmd, image, b);
    imageBarrier(cmd, image.image, image.aspect, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout,
                 VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                 VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
    d.endOneTime(cmd);
    std::vector<uint8_t> out(size_t(image.width) * image.height * texelBytes);
    std::memcpy(out.data(), b.data, out.size());
    destroyBuffer(d, b);
    return out;
}

inline void renderFrame(Module& m) {
    Device& d = deviceOf(m);
    VkCommandBuffer cmd = d.beginOneTime();
    auto r = m.record(cmd);
    ASSERT_TRUE(r.ok()) << r.error();
    d.endOneTime(cmd);
    vkQueueWaitIdle(d.queue);
    m.collect();
}

// Texel i of an RGBA16F image read back with readImage.
inline glm::vec4 half4(const std::vector<uint8_t>& img, size_t i) {
    uint64_t bits;
    std::memcpy(&bits, img.data() + i * 8, 8);
    return glm::vec4(glm::unpackHalf2x16(uint32_t(bits)), glm::unpackHalf2x16(uint32_t(bits >> 32)));
}

inline std::vector<float> toFloats(const std::vector<uint8_t>& bytes) {
    std::vector<float> f(bytes.size() / 4);
    std::memcpy(f.data(), bytes.data(), f.size() * 4);
    return f;
}

} // namespace ml::test
