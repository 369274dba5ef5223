// The Module members that hand out device handles and submit a frame for headless hosts, and the
// diagnostics read-backs (engine/manylights_diagnostics.h). Kept out of module.cpp: these read the
// module's state after the fact and take no part in recording a frame.
#include "engine/manylights_diagnostics.h"

#include "engine/module_impl.h"
#include "shadows/virtual/vsm_math.h"

#include <glm/gtc/packing.hpp>

namespace ml {

DeviceInfo Module::deviceInfo() const {
    const Device& d = *impl_->device;
    return {d.instance, d.physicalDevice, d.device, d.queue, d.queueFamily, d.name, d.validationEnabled()};
}

Result<void> Module::submitFrame() {
    const Device& d = *impl_->device;
    VkCommandBuffer cmd = d.beginOneTime();
    auto r = record(cmd);
    d.endOneTime(cmd); // submitted even after a refusal: the one-off buffer is then empty
    return r;
}

namespace diag {

static_assert(uint32_t(VsmProbeStatus::Page) == ML_VSM_PROBE_PAGE);
static_assert(uint32_t(VsmProbeStatus::Fallback) == ML_VSM_PROBE_FALLBACK);
static_assert(uint32_t(VsmProbeStatus::NoCaster) == ML_VSM_PROBE_NO_CASTER);
static_assert(uint32_t(VsmProbeStatus::Missing) == ML_VSM_PROBE_MISSING);

static const Module::Impl& state(const Module& module) {
    return internals(module);
}

LastFrame lastFrame(const Module& module) {
    const gpu::FrameConstants& fc = state(module).lastConstants;
    LastFrame f;
    f.viewProj = fc.viewProj;
    f.invViewProj = fc.invViewProj;
    f.cameraPosition = glm::vec3(fc.cameraPosition);
    f.size = glm::uvec4(fc.size.x, fc.size.y, 0, 0);
    f.nearPlane = fc.depth.x;
    f.farPlane = fc.depth.y;
    return f;
}

Result<void> readGBuffer(Module& module, std::vector<float>& depth, std::vector<glm::vec3>& normal) {
    Module::Impl& m = internals(module);
    if (!m.ownTargets) return fail("readGBuffer: the G-buffer belongs to the host (setTargets)");
    if (m.frameIndex == 0) return fail("readGBuffer: no frame recorded yet");
    const Device& d = *m.device;
    ML_VK_CHECK(vkQueueWaitIdle(d.queue));
    const size_t pixels = size_t(m.width) * m.height;
    Buffer rb = createBuffer(d, pixels * 12, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "diag_gbuffer_readback");
    VkCommandBuffer cmd = d.beginOneTime();
    // Both images are SHADER_READ_ONLY_OPTIMAL after the frame (engine/gbuffer.h); they return there.
    for (const Image* img : {&m.targets.depth, &m.targets.normal}) {
        imageBarrier(cmd, img->image, img->aspect, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                     VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferImageCopy region{};
        region.bufferOffset = img == &m.targets.depth ? 0 : pixels * 4;
        region.imageSubresource = {img->aspect, 0, 0, 1};
        region.imageExtent = {m.width, m.height, 1};
        vkCmdCopyImageToBuffer(cmd, img->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rb.buffer, 1, &region);
        imageBarrier(cmd, img->image, img->aspect, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_READ_BIT);
    }
    d.endOneTime(cmd);
    const float* z = rb.as<float>();
    const uint64_t* n = reinterpret_cast<const uint64_t*>(rb.as<char>() + pixels * 4);
    depth.assign(z, z + pixels);
    normal.resize(pixels);
    for (size_t i = 0; i < pixels; ++i)
        normal[i] =
            glm::vec3(glm::unpackHalf2x16(uint32_t(n[i])), glm::unpackHalf2x16(uint32_t(n[i] >> 32)).x);
    destroyBuffer(d, rb);
    return {};
}

uint32_t cullingBoxTests(const Module& module) {
    return state(module).cull.lastBoxTests();
}

SceneCounts sceneCounts(const Module& module) {
    const Module::Impl& m = state(module);
    return {uint32_t(m.meshes.size()), uint32_t(m.instances.size()), uint32_t(m.meshlets.meshlets.size())};
}

bool vsmMeshPath(const Module& module) {
    return state(module).vsm.meshPath();
}

std::vector<VsmMap> vsmMaps(const Module& module) {
    std::vector<VsmMap> out;
    for (const VsmMapInfo& info : state(module).vsm.mapInfo())
        out.push_back({info.inUse, info.light, info.face, info.gpu.info.x == ML_VSM_ORTHOGRAPHIC,
                       (info.gpu.info.y & ML_VSM_MAP_DYNAMIC_ONLY) != 0, info.frustum});
    return out;
}

std::vector<VsmProbe> readVsmProbes(const Module& module, uint32_t* overflow) {
    const Module::Impl& m = state(module);
    std::vector<VsmProbe> out;
    if (overflow) *overflow = 0;
    for (const gpu::GpuVsmProbe& p : m.vsm.readProbes(m.lastSlot, overflow))
        out.push_back({p.texel.x, p.texel.y, p.texel.z, p.texel.w, p.info.x, p.info.y, p.info.z, p.tap.x,
                       VsmProbeStatus(p.info.w)});
    return out;
}

glm::vec3 vsmCasterPoint(const glm::mat4& transform, glm::vec3 position) {
    return gpu::vsmPoint(transform, position);
}

} // namespace diag
} // namespace ml
