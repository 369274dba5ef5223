// Virtual shadow maps: the CPU side of a frame (map slots, matrices, coverage and stale bits) and the
// recording of the GPU passes. The algorithm is in vsm.h; the GPU twins of the references are the
// vsm_*.comp shaders beside this file.
#include "shadows/virtual/vsm.h"

#include "shaders/shared/light_math.h"
#include "shadows/static/raster_dual.h"
#include "shadows/virtual/vsm_math.h"

#include "vsm_alloc.comp.spv.h"
#include "vsm_assign.comp.spv.h"
#include "vsm_clear.comp.spv.h"
#include "vsm_cull.comp.spv.h"
#include "vsm_draw.frag.spv.h"
#include "vsm_draw.mesh.spv.h"
#include "vsm_draw.task.spv.h"
#include "vsm_draw.vert.spv.h"
#include "vsm_expand.comp.spv.h"
#include "vsm_hpb.comp.spv.h"
#include "vsm_mark.comp.spv.h"
#include "vsm_probe.comp.spv.h"
#include "vsm_scan.comp.spv.h"
#include "vsm_view.comp.spv.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace ml {

namespace {

constexpr VkBufferUsageFlags kIndirectUsage = kStorageBufferUsage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;

void setBit(std::vector<uint32_t>& bits, uint32_t i) {
    bits[i >> 5] |= 1u << (i & 31u);
}

// Sets the bit of every entry (all mips) of `map` whose pages overlap `rect` (mip-0 pages, inclusive).
void setRectBits(std::vector<uint32_t>& bits, uint32_t map, glm::uvec4 rect, uint32_t s0, uint32_t mips,
                 uint32_t entriesPerMap) {
    for (uint32_t m = 0; m < mips; ++m)
        for (uint32_t y = rect.y >> m; y <= (rect.w >> m); ++y)
            for (uint32_t x = rect.x >> m; x <= (rect.z >> m); ++x)
                setBit(bits, gpu::vsmEntry(entriesPerMap, s0, map, m, x, y));
}

bool sameMap(const gpu::GpuVsmMap& a, const gpu::GpuVsmMap& b) {
    return std::memcmp(&a.viewProj, &b.viewProj, sizeof(glm::mat4)) == 0 &&
           std::memcmp(&a.params, &b.params, sizeof(glm::vec4)) == 0 &&
           (a.info.y & ML_VSM_MAP_DYNAMIC_ONLY) == (b.info.y & ML_VSM_MAP_DYNAMIC_ONLY);
}

bool boxTouchesSphere(glm::vec3 lo, glm::vec3 hi, glm::vec3 c, float r) {
    glm::vec3 d = glm::max(glm::max(lo - c, c - hi), glm::vec3(0.0f));
    return glm::dot(d, d) <= r * r;
}

} // namespace

bool vsmProjectBox(const gpu::GpuVsmMap& map, glm::vec3 lo, glm::vec3 hi, uint32_t s0, glm::uvec4& rect) {
    // Frustum: the six planes of viewProj (Vulkan depth 0..1), as vsm_cull.comp.
    const glm::mat4 M = glm::transpose(map.viewProj);
    const glm::vec4 planes[6] = {M[3] + M[0], M[3] - M[0], M[3] + M[1], M[3] - M[1], M[2], M[3] - M[2]};
    for (const glm::vec4& p : planes) {
        glm::vec3 far(p.x >= 0 ? hi.x : lo.x, p.y >= 0 ? hi.y : lo.y, p.z >= 0 ? hi.z : lo.z);
        if (glm::dot(glm::vec3(p), far) + p.w < 0.0f) return false;
    }
    glm::vec2 nlo(1e30f), nhi(-1e30f);
    bool behind = false;
    for (uint32_t k = 0; k < 8 && !behind; ++k) {
        glm::vec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
        glm::vec4 clip = map.viewProj * glm::vec4(p, 1.0f);
        if (clip.w <= 1e-6f) {
            behind = true;
            break;
        }
        nlo = glm::min(nlo, glm::vec2(clip) / clip.w);
        nhi = glm::max(nhi, glm::vec2(clip) / clip.w);
    }
    if (behind) {
        rect = glm::uvec4(0, 0, s0 - 1, s0 - 1);
        return true;
    }
    // Slack of a few mip-0 texels: the rasteriser covers texel centres a triangle on the box's edge
    // touches, and the lookup's normal offset and PCF kernel reach a few texels further.
    const float slack = 8.0f * 2.0f / float(s0 * 32u);
    auto page = [&](float v) {
        float t = std::floor((v * 0.5f + 0.5f) * float(s0));
        return uint32_t(std::clamp(t, 0.0f, float(s0 - 1)));
    };
    rect = glm::uvec4(page(nlo.x - slack), page(nlo.y - slack), page(nhi.x + slack), page(nhi.y + slack));
    return true;
}

void VirtualShadowMaps::create(const Device& d, const VsmSettings& s, uint32_t framesInFlight) {
    settings_ = s;
    if (!s.enabled) return;
    s0_ = s.resolution / s.pageSize;
    mips_ = uint32_t(std::countr_zero(s0_)) + 1;
    entriesPerMap_ = gpu::vsmMipOffset(s0_, mips_);
    const size_t entries = size_t(s.maxMaps) * entriesPerMap_;
    const size_t bitWords = (entries + 31) / 32;

    // Persistent GPU state, device-local: the host reads it only through readBuffer (tests, check vsm).
    table_ = createDeviceBuffer(d, entries * 4, kStorageBufferUsage, "vsm_page_table");
    owners_ =
        createDeviceBuffer(d, size_t(s.poolPages) * 4, kStorageBufferUsage, "vsm_owners", ML_VSM_NO_OWNER);
    lastUsed_ = createDeviceBuffer(d, size_t(s.poolPages) * 4, kStorageBufferUsage, "vsm_last_used");
    markWords_ = bitWords;
    marks_ = createDeviceBuffer(d, 2 * bitWords * 4, kStorageBufferUsage,
                                "vsm_marks"); // lookup, then fallback marks
    pagePool_ = createDeviceBuffer(d, size_t(s.poolPages) * s.pageSize * s.pageSize * 4, kStorageBufferUsage,
                                   "vsm_pool", 0xFFFFFFFFu);
    blockCounts_ =
        createDeviceBuffer(d, (entries / ML_VSM_BLOCK + 1) * 4, kStorageBufferUsage, "vsm_block_counts");
    avail_ = createDeviceBuffer(d, size_t(s.poolPages) * 4, kStorageBufferUsage, "vsm_avail");
    rendered_ = createDeviceBuffer(d, size_t(s.poolPages) * 4, kStorageBufferUsage, "vsm_rendered");
    dirtyMips_ = createDeviceBuffer(d, size_t(s.maxMaps) * 4, kStorageBufferUsage, "vsm_dirty_mips");
    // HPB levels 1..log2(S_0) as image mips 0.. (none when a map is one page). Rebuilt every frame for the
    // active maps before it is read: PerFrame. One layer per map slot: maxMaps <= maxImageArrayLayers.
    hpbLevels_ = mips_ - 1;
    ImageDesc hpb;
    hpb.width = s0_;
    hpb.height = std::max(1u, s0_ / 2);
    hpb.format = VK_FORMAT_R32_UINT;
    hpb.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    hpb.mips = std::max(1u, hpbLevels_);
    hpb.layers = s.maxMaps;
    hpb.lifetime = Lifetime::PerFrame;
    hpb.arrayViews = true; // one map slot is still an array of one
    hpb.name = "vsm_hpb";
    hpb_ = createImage(d, hpb);
    const size_t draws = size_t(mips_) * s.maxDrawsPerMip;
    draws_ = createDeviceBuffer(d, draws * sizeof(VkDrawIndexedIndirectCommand), kIndirectUsage, "vsm_draws");
    drawInfo_ = createDeviceBuffer(d, draws * 8, kStorageBufferUsage, "vsm_draw_info");
    drawCounts_ = createDeviceBuffer(d, ML_VSM_MAX_MIPS * 4, kIndirectUsage, "vsm_draw_counts");
    if (settings_.raster != VsmRaster::Vertex && !d.cmdDrawMeshTasksIndirect) {
        std::fprintf(stderr, "vsm: %s has no mesh shaders: shadow pages are drawn with the vertex path\n",
                     d.name.c_str());
        settings_.raster = VsmRaster::Vertex;
    } else if (settings_.raster == VsmRaster::Auto) {
        const bool cpu = d.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
        settings_.raster = cpu ? VsmRaster::Vertex : VsmRaster::Mesh;
        std::fprintf(stderr, "vsm: %s: shadow pages drawn with the %s\n", d.name.c_str(),
                     cpu ? "vertex path (CPU device: faster there than task/mesh shaders, README)"
                         : "mesh path (meshlets, task and mesh shaders)");
    }
    if (settings_.raster == VsmRaster::Mesh) {
        // One task workgroup per 32 list entries, at most 65535 workgroups per mip's draw.
        settings_.maxMeshletsPerMip = std::clamp(settings_.maxMeshletsPerMip, 1u, 65535u * ML_VSM_TASK_GROUP);
        meshletList_ = createDeviceBuffer(d, size_t(mips_) * settings_.maxMeshletsPerMip * 12,
                                          kStorageBufferUsage, "vsm_meshlet_list");
        meshTasks_ = createDeviceBuffer(d, size_t(mips_) * 16, kIndirectUsage, "vsm_mesh_tasks");
    }

    slots_.resize(framesInFlight);
    for (Slot& sl : slots_) {
        sl.constants =
            createBuffer(d, sizeof(gpu::VsmConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, "vsm_constants");
        sl.maps =
            createBuffer(d, size_t(s.maxMaps) * sizeof(gpu::GpuVsmMap), kStorageBufferUsage, "vsm_maps");
        sl.coverage = createBuffer(d, bitWords * 4, kStorageBufferUsage, "vsm_coverage");
        sl.stale = createBuffer(d, bitWords * 4, kStorageBufferUsage, "vsm_stale");
        sl.active = createBuffer(d, size_t(s.maxMaps) * 4, kStorageBufferUsage, "vsm_active");
        // At most one run per active map and level of detail.
        sl.runs = createBuffer(d, size_t(s.maxMaps) * std::max(mips_, s.clipLevels) * sizeof(glm::uvec4),
                               kStorageBufferUsage, "vsm_runs");
        sl.counters = createBuffer(d, sizeof(gpu::VsmCounters), kIndirectUsage, "vsm_counters");
        sl.probes = createBuffer(d, 16 + size_t(s.probeCapacity) * sizeof(gpu::GpuVsmProbe),
                                 kStorageBufferUsage, "vsm_probes");
        sl.coverageHost.assign(bitWords, 0);
        sl.staleHost.assign(bitWords, 0);
        sl.mapsHost.assign(s.maxMaps, gpu::GpuVsmMap{});
    }
    maps_.assign(s.maxMaps, VsmMapInfo{});
    wasActive_.assign(s.maxMaps, 0);
    for (uint32_t i = s.maxMaps; i-- > 0;) freeSlots_.push_back(i);

    markShader_ = ML_SHADER(d, spv_vsm_mark_comp);
    scanShader_ = ML_SHADER(d, spv_vsm_scan_comp);
    allocShader_ = ML_SHADER(d, spv_vsm_alloc_comp);
    assignShader_ = ML_SHADER(d, spv_vsm_assign_comp);
    hpbShader_ = ML_SHADER(d, spv_vsm_hpb_comp);
    cullShader_ = ML_SHADER(d, spv_vsm_cull_comp);
    clearShader_ = ML_SHADER(d, spv_vsm_clear_comp);
    probeShader_ = ML_SHADER(d, spv_vsm_probe_comp);
    viewShader_ = ML_SHADER(d, spv_vsm_view_comp);
    drawVert_ = ML_SHADER(d, spv_vsm_draw_vert);
    drawFrag_ = ML_SHADER(d, spv_vsm_draw_frag);
    markProgram_ = createComputeProgram(d, markShader_);
    scanProgram_ = createComputeProgram(d, scanShader_);
    allocProgram_ = createComputeProgram(d, allocShader_);
    assignProgram_ = createComputeProgram(d, assignShader_);
    hpbProgram_ = createComputeProgram(d, hpbShader_);
    cullProgram_ = createComputeProgram(d, cullShader_);
    clearProgram_ = createComputeProgram(d, clearShader_);
    probeProgram_ = createComputeProgram(d, probeShader_);
    viewProgram_ = createComputeProgram(d, viewShader_);
    GraphicsState gs; // attachment-less: depth goes to the pool with atomics
    gs.cull = VK_CULL_MODE_NONE;
    gs.depthTest = false;
    gs.depthWrite = false;
    drawProgram_ = createGraphicsProgram(d, {&drawVert_, &drawFrag_}, gs);
    if (settings_.raster == VsmRaster::Mesh) {
        expandShader_ = ML_SHADER(d, spv_vsm_expand_comp);
        drawTask_ = ML_SHADER(d, spv_vsm_draw_task);
        drawMesh_ = ML_SHADER(d, spv_vsm_draw_mesh);
        expandProgram_ = createComputeProgram(d, expandShader_);
        meshProgram_ = createGraphicsProgram(d, {&drawTask_, &drawMesh_, &drawFrag_}, gs);
    }
}

void VirtualShadowMaps::destroy(const Device& d) {
    if (!settings_.enabled) return;
    for (Program* p :
         {&markProgram_, &scanProgram_, &allocProgram_, &assignProgram_, &hpbProgram_, &cullProgram_,
          &clearProgram_, &probeProgram_, &viewProgram_, &drawProgram_, &expandProgram_, &meshProgram_})
        destroyProgram(d, *p);
    for (ShaderModule* s :
         {&markShader_, &scanShader_, &allocShader_, &assignShader_, &hpbShader_, &cullShader_, &clearShader_,
          &probeShader_, &viewShader_, &drawVert_, &drawFrag_, &expandShader_, &drawTask_, &drawMesh_})
        destroyShader(d, *s);
    for (Buffer* b : {&table_, &owners_, &lastUsed_, &marks_, &pagePool_, &blockCounts_, &avail_, &rendered_,
                      &dirtyMips_, &draws_, &drawInfo_, &drawCounts_, &meshletList_, &meshTasks_})
        destroyBuffer(d, *b);
    destroyImage(d, hpb_);
    for (Slot& s : slots_)
        for (Buffer* b : {&s.constants, &s.maps, &s.coverage, &s.stale, &s.active, &s.runs, &s.casters,
                          &s.counters, &s.probes})
            destroyBuffer(d, *b);
    slots_.clear();
}

uint32_t VirtualShadowMaps::allocateSlots(uint32_t count) {
    // Consecutive slots: take the lowest run of `count` free slots (free list kept sorted descending,
    // so the back is the lowest free slot).
    std::vector<uint32_t> sorted(freeSlots_.rbegin(), freeSlots_.rend());
    for (size_t i = 0; i + count <= sorted.size(); ++i) {
        if (sorted[i + count - 1] - sorted[i] != count - 1) continue;
        uint32_t first = sorted[i];
        sorted.erase(sorted.begin() + long(i), sorted.begin() + long(i + count));
        freeSlots_.assign(sorted.rbegin(), sorted.rend());
        mapsInUse_ = std::max(mapsInUse_, first + count);
        return first;
    }
    return ML_VSM_NO_MAP;
}

void VirtualShadowMaps::buildMap(uint32_t map, const VsmLight& l, uint32_t face, const VsmCamera& camera,
                                 bool& moved) {
    VsmMapInfo& info = maps_[map];
    gpu::GpuVsmMap g{};
    g.light = glm::uvec4(info.light, face, l.kind == ML_LIGHT_DIRECTIONAL ? settings_.clipLevels : mips_, 0);
    g.info.y = l.staticBake ? ML_VSM_MAP_DYNAMIC_ONLY : 0u;
    if (l.kind == ML_LIGHT_DIRECTIONAL) {
        // Clip level `face`: a square of half extent h around the camera, snapped to whole pages in the
        // light's plane (and to 1/8 of the depth span along it) so that cached pages stay valid while the
        // camera moves within a page.
        const float h = settings_.clipHalfExtent * float(1u << face);
        const float pageWorld = 2.0f * h / float(s0_);
        glm::vec3 dir = glm::normalize(l.direction);
        glm::vec3 up = std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
        glm::vec3 right = glm::normalize(glm::cross(dir, up));
        glm::vec3 upv = glm::cross(right, dir);
        const float depthStep = settings_.clipDepth / 8.0f;
        float cx = std::floor(glm::dot(camera.position, right) / pageWorld + 0.5f) * pageWorld;
        float cy = std::floor(glm::dot(camera.position, upv) / pageWorld + 0.5f) * pageWorld;
        float cz = std::floor(glm::dot(camera.position, dir) / depthStep + 0.5f) * depthStep;
        glm::vec3 centre = right * cx + upv * cy + dir * cz;
        glm::vec3 eye = centre - dir * (0.5f * settings_.clipDepth);
        g.view = glm::lookAt(eye, centre, upv);
        glm::mat4 proj = glm::orthoRH_ZO(-h, h, -h, h, 0.0f, settings_.clipDepth);
        g.viewProj = proj * g.view;
        g.params = glm::vec4(h, 0.0f, settings_.clipDepth, 0.0f);
        g.info.x = ML_VSM_ORTHOGRAPHIC;
        // The same volume for a reference rasteriser (check vsm): depth is view -z over [0, clipDepth].
        info.frustum = LightFrustum{};
        info.frustum.view = g.view;
        info.frustum.nearPlane = 0.0f;
        info.frustum.farPlane = settings_.clipDepth;
        info.frustum.orthoHalf = h;
    } else {
        LightShape sl;
        sl.type = l.kind == ML_LIGHT_POINT ? LightKind::Point : LightKind::Spot;
        sl.position = l.position;
        sl.direction = l.direction;
        sl.range = l.range;
        sl.outerAngle = l.outerAngle;
        LightFrustum f = l.kind == ML_LIGHT_POINT ? pointLightFaceFrustum(sl, face) : spotLightFrustum(sl);
        // The projection of the static dual-depth bake (shadows/gpu/dual_depth_gpu.cpp), so a reference
        // rasteriser with the same frustum sees the same texel centres.
        glm::mat4 proj = glm::perspectiveRH_ZO(f.fov, 1.0f, f.nearPlane, f.farPlane);
        g.view = f.view;
        g.viewProj = proj * f.view;
        g.params = glm::vec4(std::tan(f.fov * 0.5f), f.nearPlane, f.farPlane, 0.0f);
        g.info.x = ML_VSM_PERSPECTIVE;
        info.frustum = f;
    }
    moved = !info.inUse || !sameMap(info.gpu, g);
    info.inUse = true;
    info.face = face;
    info.gpu = g;
}

std::vector<uint32_t> VirtualShadowMaps::prepare(const Device& device, uint32_t slotIndex, uint64_t frame,
                                                 std::span<const VsmLight> lights,
                                                 std::span<const uint32_t> visible,
                                                 std::span<const VsmInstance> instances,
                                                 const VsmCamera& camera) {
    std::vector<uint32_t> firstMap(visible.size(), ML_VSM_NO_MAP);
    if (!settings_.enabled) return firstMap;
    Slot& slot = slots_[slotIndex];
    if (lightState_.size() < lights.size()) lightState_.resize(lights.size());

    // Which visible lights need maps this frame. A light with a static bake needs them only while a
    // dynamic caster is inside its range; moving lights and lights without a bake always do.
    slot.lightsWithPages = slot.lightsWithoutSlot = 0;
    std::vector<uint8_t> needs(lights.size(), 0);
    for (uint32_t id : visible) {
        const VsmLight& l = lights[id];
        if (!l.castsShadows || !(settings_.kinds & (1u << l.kind))) continue;
        if (l.moving ? !settings_.movingLights : !settings_.staticLights) continue;
        bool need = !l.staticBake;
        for (size_t i = 0; i < instances.size() && !need; ++i)
            need = instances[i].dynamic && instances[i].castsShadows &&
                   (l.kind == ML_LIGHT_DIRECTIONAL ||
                    boxTouchesSphere(instances[i].lo, instances[i].hi, l.position, l.range));
        needs[id] = need ? 1 : 0;
    }
    // Slots: assigned on first need, kept while the light keeps its kind (its cached pages stay useful
    // when it comes back into view); a kind change frees them.
    for (uint32_t id = 0; id < lights.size(); ++id) {
        LightState& st = lightState_[id];
        const uint32_t count = lights[id].kind == ML_LIGHT_POINT         ? 6u
                               : lights[id].kind == ML_LIGHT_DIRECTIONAL ? settings_.clipLevels
                                                                         : 1u;
        if (st.firstMap != ML_VSM_NO_MAP && (st.kind != lights[id].kind || st.mapCount != count)) {
            for (uint32_t m = 0; m < st.mapCount; ++m) {
                maps_[st.firstMap + m].inUse = false;
                freeSlots_.push_back(st.firstMap + m);
            }
            std::sort(freeSlots_.rbegin(), freeSlots_.rend());
            st.firstMap = ML_VSM_NO_MAP;
        }
        if (needs[id] && st.firstMap == ML_VSM_NO_MAP) {
            st.firstMap = allocateSlots(count);
            if (st.firstMap == ML_VSM_NO_MAP) {
                ++slot.lightsWithoutSlot;
                continue;
            }
            st.mapCount = count;
            st.kind = lights[id].kind;
            for (uint32_t m = 0; m < count; ++m) {
                maps_[st.firstMap + m] = VsmMapInfo{};
                maps_[st.firstMap + m].light = id;
            }
        }
    }

    // Matrices of every map in use; a map whose projection or caster set changed is stale as a whole.
    std::fill(slot.coverageHost.begin(), slot.coverageHost.end(), 0u);
    std::fill(slot.staleHost.begin(), slot.staleHost.end(), 0u);
    for (uint32_t m = 0; m < mapsInUse_; ++m) slot.mapsHost[m] = gpu::GpuVsmMap{};
    for (uint32_t id = 0; id < lights.size(); ++id) {
        const LightState& st = lightState_[id];
        if (st.firstMap == ML_VSM_NO_MAP) continue;
        for (uint32_t f = 0; f < st.mapCount; ++f) {
            bool moved = false;
            buildMap(st.firstMap + f, lights[id], f, camera, moved);
            slot.mapsHost[st.firstMap + f] = maps_[st.firstMap + f].gpu;
            if (moved) slot.mapsHost[st.firstMap + f].info.y |= ML_VSM_MAP_INVALIDATE;
        }
    }
    // Coverage (maps of baked lights: pages under dynamic casters) and stale bits (pages under a moved,
    // added or removed caster's old or new bounds).
    const bool firstFrame = lastInstances_.size() != instances.size();
    for (uint32_t m = 0; m < mapsInUse_; ++m) {
        if (!maps_[m].inUse) continue;
        const gpu::GpuVsmMap& g = slot.mapsHost[m];
        const bool dynamicOnly = (g.info.y & ML_VSM_MAP_DYNAMIC_ONLY) != 0;
        for (size_t i = 0; i < instances.size(); ++i) {
            const VsmInstance& in = instances[i];
            if (dynamicOnly && !in.dynamic) continue;
            glm::uvec4 rect;
            if (dynamicOnly && in.castsShadows && vsmProjectBox(g, in.lo, in.hi, s0_, rect))
                setRectBits(slot.coverageHost, m, rect, s0_, mips_, entriesPerMap_);
            if (firstFrame) continue;
            const VsmInstance& old = lastInstances_[i];
            if (old.lo == in.lo && old.hi == in.hi && old.castsShadows == in.castsShadows) continue;
            for (const VsmInstance* b : {&old, &in})
                if (vsmProjectBox(g, b->lo, b->hi, s0_, rect))
                    setRectBits(slot.staleHost, m, rect, s0_, mips_, entriesPerMap_);
        }
    }
    if (firstFrame)
        for (uint32_t m = 0; m < mapsInUse_; ++m) slot.mapsHost[m].info.y |= ML_VSM_MAP_INVALIDATE;
    lastInstances_.assign(instances.begin(), instances.end());

    // Active maps: those of visible lights with maps (only they get marks, allocation, HPB and draws).
    // A map that was not active last frame missed the invalidations in between: stale as a whole.
    slot.activeHost.clear();
    std::vector<uint8_t> active(maps_.size(), 0);
    for (size_t v = 0; v < visible.size(); ++v) {
        const LightState& st = lightState_[visible[v]];
        if (!needs[visible[v]] || st.firstMap == ML_VSM_NO_MAP) continue;
        firstMap[v] = st.firstMap;
        ++slot.lightsWithPages;
        for (uint32_t f = 0; f < st.mapCount; ++f) {
            const uint32_t m = st.firstMap + f;
            slot.activeHost.push_back(m);
            active[m] = 1;
            if (!wasActive_[m]) slot.mapsHost[m].info.y |= ML_VSM_MAP_INVALIDATE;
        }
    }
    wasActive_ = active;
    slot.activeCount = uint32_t(slot.activeHost.size());
    // Allocation order (vsm_alloc_common.glsl): every light's coarsest level first (the coarsest mip of a
    // perspective map, the coarsest clip level of a directional light), then one level finer, and so on;
    // within a level, active map order.
    slot.runsHost.clear();
    uint32_t rank = 0;
    const uint32_t steps = std::max(mips_, settings_.clipLevels);
    for (uint32_t r = 0; r < steps; ++r)
        for (uint32_t m : slot.activeHost) {
            const gpu::GpuVsmMap& g = slot.mapsHost[m];
            const bool ortho = g.info.x == ML_VSM_ORTHOGRAPHIC;
            const uint32_t count = ortho ? g.light.z : mips_; // clip levels, or mips
            if (r >= count) continue;
            const uint32_t level = count - 1 - r;
            if (ortho && g.light.y != level) continue;
            const uint32_t mip = ortho ? 0u : level;
            const uint32_t n = (s0_ >> mip) * (s0_ >> mip);
            slot.runsHost.push_back(glm::uvec4(rank, m, mip, n));
            rank += n;
        }

    // Casters.
    std::vector<gpu::GpuCaster> casters(instances.size());
    for (size_t i = 0; i < instances.size(); ++i) {
        const VsmInstance& in = instances[i];
        casters[i].lo = glm::vec4(in.lo, 0.0f);
        casters[i].hi = glm::vec4(in.hi, 0.0f);
        casters[i].draw = glm::uvec4(in.castsShadows ? in.indexCount : 0u, in.firstIndex, in.vertexOffset,
                                     in.dynamic ? 1u : 0u);
        casters[i].meshlets = glm::uvec4(in.firstMeshlet, in.meshletCount, in.closed ? 1u : 0u, 0u);
    }
    slot.casterCount = uint32_t(casters.size());

    gpu::VsmConstants c{};
    c.page = glm::uvec4(settings_.pageSize, uint32_t(std::countr_zero(settings_.pageSize)), s0_, mips_);
    c.sizes = glm::uvec4(entriesPerMap_, slot.activeCount, settings_.poolPages, uint32_t(frame + 1));
    c.options = glm::uvec4(pcf_, settings_.caching ? 1u : 0u, settings_.resolution, uint32_t(markWords_));
    // The pixel footprint per metre, divided by the texels wanted per pixel: the mip (or clip level) a
    // lookup picks then has texels that much smaller than the pixel (VsmSettings::texelsPerPixel).
    c.camera = glm::vec4(2.0f * std::tan(camera.fovY * 0.5f) / float(std::max(camera.height, 1u)) /
                             settings_.texelsPerPixel,
                         0, 0, 0);
    c.order = glm::uvec4(uint32_t(slot.runsHost.size()), rank, 0, 0);
    slot.orderEntries = rank;
    lastConstants_ = c;

    // Upload (this slot's previous frame has completed: the module waited for its fence).
    upload(slot.constants, &c, sizeof(c));
    upload(slot.maps, slot.mapsHost.data(), size_t(mapsInUse_) * sizeof(gpu::GpuVsmMap));
    const size_t usedWords = (size_t(mapsInUse_) * entriesPerMap_ + 31) / 32;
    upload(slot.coverage, slot.coverageHost.data(), usedWords * 4);
    upload(slot.stale, slot.staleHost.data(), usedWords * 4);
    if (!slot.activeHost.empty()) upload(slot.active, slot.activeHost.data(), slot.activeHost.size() * 4);
    if (!slot.runsHost.empty())
        upload(slot.runs, slot.runsHost.data(), slot.runsHost.size() * sizeof(glm::uvec4));
    ensureBuffer(device, slot.casters, casters.size() * sizeof(gpu::GpuCaster), kStorageBufferUsage,
                 "vsm_casters");
    if (!casters.empty()) upload(slot.casters, casters.data(), casters.size() * sizeof(gpu::GpuCaster));
    gpu::VsmCounters zero{};
    zero.dispatchY = zero.dispatchZ = 1;
    upload(slot.counters, &zero, sizeof(zero));
    if (settings_.probeCapacity) {
        uint32_t header[4] = {0, settings_.probeCapacity, 0, 0};
        upload(slot.probes, header, sizeof(header));
    }
    return firstMap;
}

VsmStats VirtualShadowMaps::readStats(uint32_t slotIndex) const {
    VsmStats s;
    if (!settings_.enabled) return s;
    const Slot& slot = slots_[slotIndex];
    const auto& c = *slot.counters.as<gpu::VsmCounters>();
    s.pagesMarked = c.pagesMarked;
    s.pagesAllocated = c.pagesAllocated;
    s.pagesCached = c.pagesCached;
    s.pagesRendered = c.pagesRendered;
    s.pagesInvalidated = c.pagesInvalidated;
    s.pagesEvicted = c.pagesEvicted;
    s.fallbacks = c.fallbacks;
    s.requests = c.requests;
    s.instancesDrawn = c.instancesDrawn;
    s.instancesCulledHpb = c.instancesCulledHpb;
    s.drawOverflow = c.drawOverflow;
    s.meshPath = meshPath();
    s.meshletsTotal = c.meshletsTotal;
    s.meshletsCulledFrustum = c.meshletsCulledFrustum;
    s.meshletsCulledHpb = c.meshletsCulledHpb;
    s.meshletsAfterExpansion = c.meshletsAfterExpansion;
    s.meshletOverflow = c.meshletOverflow;
    s.taskCulledFrustum = c.taskCulledFrustum;
    s.taskCulledCone = c.taskCulledCone;
    s.taskCulledHpb = c.taskCulledHpb;
    s.meshletsAfterTask = c.meshletsAfterTask;
    s.trianglesAfterTask = c.trianglesAfterTask;
    s.trianglesRasterized = c.trianglesRasterized;
    s.poolPages = settings_.poolPages;
    s.lightsWithPages = slot.lightsWithPages;
    s.lightsWithoutSlot = slot.lightsWithoutSlot;
    s.mapsActive = slot.activeCount;
    const uint64_t page = uint64_t(settings_.pageSize) * settings_.pageSize * 4;
    s.poolBytes = page * settings_.poolPages;
    s.usedBytes = page * c.pagesAllocated;
    const uint64_t mip0 = uint64_t(settings_.resolution) * settings_.resolution * 4;
    uint64_t allMips = 0;
    for (uint32_t m = 0; m < mips_; ++m) allMips += mip0 >> (2 * m);
    for (uint32_t map : slot.activeHost) {
        const bool ortho = maps_[map].gpu.info.x == ML_VSM_ORTHOGRAPHIC;
        s.virtualBytes += ortho ? mip0 : allMips;
        s.atlasBytes += mip0;
    }
    return s;
}

namespace {
std::vector<uint32_t> readWords(const Device& d, const Buffer& b, size_t words) {
    std::vector<uint8_t> bytes = readBuffer(d, b, 0, words * 4);
    std::vector<uint32_t> out(words);
    std::memcpy(out.data(), bytes.data(), words * 4);
    return out;
}
} // namespace

std::vector<uint32_t> VirtualShadowMaps::readTable(const Device& d) const {
    return readWords(d, table_, size_t(mapsInUse_) * entriesPerMap_);
}
std::vector<uint32_t> VirtualShadowMaps::readOwners(const Device& d) const {
    return readWords(d, owners_, settings_.poolPages);
}
std::vector<uint32_t> VirtualShadowMaps::readLastUsed(const Device& d) const {
    return readWords(d, lastUsed_, settings_.poolPages);
}
std::vector<uint32_t> VirtualShadowMaps::readMarks(const Device& d) const {
    return readWords(d, marks_, 2 * markWords_);
}
std::vector<uint32_t> VirtualShadowMaps::readPagePool(const Device& d) const {
    return readWords(d, pagePool_, size_t(settings_.poolPages) * settings_.pageSize * settings_.pageSize);
}
std::vector<uint32_t> VirtualShadowMaps::readHpb(const Device& d, uint32_t map, uint32_t level) const {
    std::vector<uint8_t> bytes = readImage(d, hpb_, level - 1, map, VK_IMAGE_LAYOUT_GENERAL);
    std::vector<uint32_t> out(bytes.size() / 4);
    std::memcpy(out.data(), bytes.data(), out.size() * 4);
    return out;
}
std::vector<gpu::GpuVsmProbe> VirtualShadowMaps::readProbes(uint32_t slotIndex, uint32_t* overflow) const {
    const Slot& slot = slots_[slotIndex];
    if (!settings_.probeCapacity) return {};
    const auto* header = slot.probes.as<uint32_t>();
    if (overflow) *overflow = header[2];
    const uint32_t n = std::min(header[0], settings_.probeCapacity);
    const auto* first = reinterpret_cast<const gpu::GpuVsmProbe*>(header + 4);
    return std::vector<gpu::GpuVsmProbe>(first, first + n);
}

} // namespace ml
