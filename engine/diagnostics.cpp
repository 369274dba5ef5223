// The Module members that hand out device handles and submit a frame for headless hosts, and the
// diagnostics read-backs (engine/manylights_diagnostics.h). Kept out of module.cpp: these read the
// module's state after the fact and take no part in recording a frame.
#include "engine/manylights_diagnostics.h"

#include "engine/module_impl.h"
#include "shadows/virtual/vsm_math.h"

#include <glm/gtc/packing.hpp>

#include <cmath>

namespace ml {

DeviceInfo Module::deviceInfo() const {
    const Device& d = *impl_->device;
    return {d.instance, d.physicalDevice,      d.device,           d.queue, d.queueFamily,
            d.name,     d.validationEnabled(), d.memoryPlacement()};
}

Result<void> Module::submitFrame() {
    const Device& d = *impl_->device;
    auto cmd = d.tryBeginOneTime("submitFrame");
    if (!cmd) return fail("submitFrame: " + cmd.error());
    auto r = record(cmd.value());
    // Submitted even after a refusal: the one-off buffer is then empty.
    if (auto e = d.tryEndOneTime(cmd.value(), "submitFrame"); !e && r)
        return fail("submitFrame: " + e.error());
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
    ML_VK_CHECK(d.waitQueue());
    const size_t pixels = size_t(m.width) * m.height;
    Buffer rb = createBuffer(d, pixels * 12, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "diag_gbuffer_readback",
                             MemoryRole::Readback);
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

double vsmPrepareMs(const Module& module) {
    return state(module).vsm.lastPrepareMs();
}

uint32_t cullingBoxTests(const Module& module) {
    return state(module).cull.lastBoxTests();
}

SceneCounts sceneCounts(const Module& module) {
    const Module::Impl& m = state(module);
    return {uint32_t(m.meshes.size()), uint32_t(m.instances.size()), uint32_t(m.meshlets.meshlets.size())};
}

uint64_t deviceWaitCount(const Module& module) {
    return state(module).deviceWaits;
}

QueueAccessCounts queueAccessCounts(const Module& module) {
    const Device& d = *state(module).device;
    const Device::QueueCounts all = d.queueCounts(), inRecord = d.recordQueueCounts();
    return {all.submits,    all.waits,          inRecord.submits,
            inRecord.waits, d.pipelineBuilds(), d.recordPipelineBuilds()};
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

struct VsmPageState {
    gpu::VsmConstants c{};
    std::vector<gpu::GpuVsmMap> maps;
    std::vector<uint32_t> coverage, table, pool;

    uint32_t entryOf(uint32_t map, uint32_t mip, int x, int y) const {
        const uint32_t shift = c.page.y;
        return gpu::vsmEntry(c.sizes.x, c.page.z, map, mip, uint32_t(x) >> shift, uint32_t(y) >> shift);
    }
    bool needsPage(uint32_t map, uint32_t entry) const {
        return (maps[map].info.y & ML_VSM_MAP_DYNAMIC_ONLY) == 0u ||
               ((coverage[entry >> 5] >> (entry & 31u)) & 1u);
    }
};

std::shared_ptr<const VsmPageState> readVsmPageState(Module& module) {
    Module::Impl& m = internals(module);
    auto s = std::make_shared<VsmPageState>();
    s->c = m.vsm.lastConstants();
    s->maps = m.vsm.slotHost(m.lastSlot).maps;
    s->coverage = m.vsm.slotHost(m.lastSlot).coverage;
    s->table = m.vsm.read(*m.device, VsmState::Table);
    s->pool = m.vsm.read(*m.device, VsmState::PagePool);
    return s;
}

bool vsmTexelNeedsPage(const VsmPageState& s, uint32_t map, uint32_t mip, int x, int y) {
    return s.needsPage(map, s.entryOf(map, mip, x, y));
}

int vsmKernelLit(const VsmPageState& s, uint32_t map, uint32_t mip, int tx, int ty, uint32_t receiver, int r,
                 uint32_t& centre) {
    centre = 0xFFFFFFFFu;
    const int res = int(s.c.options.z >> mip);
    const uint32_t size = s.c.page.x;
    int lit = 0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const int x = tx + dx, y = ty + dy;
            if (x < 0 || y < 0 || x >= res || y >= res) { // outside the map: the light does not reach
                ++lit;
                continue;
            }
            const uint32_t entry = s.entryOf(map, mip, x, y);
            if (!s.needsPage(map, entry)) { // no dynamic caster over it: lit
                ++lit;
                continue;
            }
            const uint32_t pt = s.table[entry];
            if ((pt & (ML_VSM_ALLOCATED | ML_VSM_VALID)) != (ML_VSM_ALLOCATED | ML_VSM_VALID)) return -1;
            const size_t texel = size_t(pt & ML_VSM_PHYS_MASK) * size * size +
                                 (uint32_t(y) & (size - 1u)) * size + (uint32_t(x) & (size - 1u));
            const uint32_t d = s.pool[texel];
            if (dx == 0 && dy == 0) centre = d;
            lit += receiver <= d;
        }
    return lit;
}

float vsmBilinearLit(const VsmPageState& s, uint32_t map, uint32_t mip, glm::vec3 P, glm::vec3 N, int x,
                     int y, uint32_t receiver) {
    // vsmLocate's position (vsm_math.h: the normal offset, then the projection) before its floor.
    const gpu::GpuVsmMap& m = s.maps[map];
    const uint32_t res = s.c.options.z >> mip;
    const bool ortho = m.info.x == ML_VSM_ORTHOGRAPHIC;
    const glm::vec3 vp = gpu::vsmPoint(m.view, P), vn = gpu::vsmDirection(m.view, N);
    const float extent = ortho ? m.params.x : (-vp.z) * m.params.x;
    const float offset = 2.0f * extent / float(res) * m.bias.y;
    const glm::vec3 q = vp + vn * offset;
    const float scale = ortho ? m.params.x : (-q.z) * m.params.x;
    if (!(scale > 0.0f)) return -1.0f;
    const float fx = (q.x / scale * 0.5f + 0.5f) * float(res), fy = (q.y / scale * 0.5f + 0.5f) * float(res);
    if (int(std::floor(fx)) != x || int(std::floor(fy)) != y) return -1.0f; // not the probe's texel
    // The four texels whose centres surround the position, weighted by its distance to them.
    const float sx = fx - 0.5f, sy = fy - 0.5f;
    const int x0 = int(std::floor(sx)), y0 = int(std::floor(sy));
    const float wx = sx - float(x0), wy = sy - float(y0);
    float lit = 0.0f;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            uint32_t centre = 0;
            const int tap = vsmKernelLit(s, map, mip, x0 + i, y0 + j, receiver, 0, centre);
            if (tap < 0) return -1.0f;
            lit += float(tap) * (i ? wx : 1.0f - wx) * (j ? wy : 1.0f - wy);
        }
    return lit;
}

glm::vec3 vsmCasterPoint(const glm::mat4& transform, glm::vec3 position) {
    return gpu::vsmPoint(transform, position);
}

} // namespace diag
} // namespace ml
