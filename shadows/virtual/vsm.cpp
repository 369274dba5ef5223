// Virtual shadow maps: the GPU resources (creation, growth of the map slots, destruction), each map's
// matrices (buildMap), the box projections the CPU frame uses, and the read-backs of stats and state.
// The CPU frame is vsm_prepare.cpp, the GPU passes are recorded in vsm_passes.cpp; the algorithm is in
// vsm.h; the GPU twins of the references are the vsm_*.comp shaders beside this file.
#include "shadows/virtual/vsm.h"

#include "shaders/shared/light_math.h"
#include "shadows/static/raster_dual.h"
#include "shadows/virtual/vsm_math.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace ml {

namespace {

constexpr VkBufferUsageFlags kIndirectUsage = kStorageBufferUsage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;

bool sameMap(const gpu::GpuVsmMap& a, const gpu::GpuVsmMap& b) {
    return std::memcmp(&a.viewProj, &b.viewProj, sizeof(glm::mat4)) == 0 &&
           std::memcmp(&a.params, &b.params, sizeof(glm::vec4)) == 0 &&
           (a.info.y & ML_VSM_MAP_DYNAMIC_ONLY) == (b.info.y & ML_VSM_MAP_DYNAMIC_ONLY);
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

VsmCone vsmSpotCone(const VsmLight& l) {
    VsmCone c;
    if (l.kind != ML_LIGHT_SPOT) return c;
    // spotLightFrustum: fov 2 x outer, square, so its corner rays have tangent sqrt(2) tan(outer).
    const float t = 1.02f * std::sqrt(2.0f) * std::tan(l.outerAngle);
    if (!(t < 50.0f)) return c; // nearly a half space: no cone
    c.axis = glm::normalize(l.direction);
    c.cos = 1.0f / std::sqrt(1.0f + t * t);
    c.sin = t * c.cos;
    return c;
}

bool vsmBoxMayTouchCone(const VsmCone& c, glm::vec3 apex, glm::vec3 lo, glm::vec3 hi) {
    if (c.cos < -0.5f) return true;
    // The bounding sphere's distance to the cone's generator lines (a lower bound of its distance to
    // the cone, also behind the apex) against its radius, with a little slack for rounding.
    const glm::vec3 v = 0.5f * (lo + hi) - apex;
    const float r = 0.5f * glm::length(hi - lo);
    const float a = glm::dot(v, c.axis);
    const float perp = std::sqrt(std::max(glm::dot(v, v) - a * a, 0.0f));
    return perp * c.cos - a * c.sin <= r * 1.001f + 1e-3f;
}

Result<void> VirtualShadowMaps::create(const Device& d, const VsmSettings& s, uint32_t framesInFlight) {
    settings_ = s;
    if (!s.enabled) return {};
    s0_ = s.resolution / s.pageSize;
    mips_ = uint32_t(std::countr_zero(s0_)) + 1;
    entriesPerMap_ = gpu::vsmMipOffset(s0_, mips_);

    // Persistent GPU state, device-local: the host reads it only through readBuffer (tests, check vsm).
    // The map-sized buffers (page table, marks, HPB, per-slot maps and bits) are made by resizeMaps.
    ML_TRY(createDeviceBuffer(d, pages_.owners, size_t(s.poolPages) * 4, kStorageBufferUsage, "vsm_owners",
                              ML_VSM_NO_OWNER));
    ML_TRY(createDeviceBuffer(d, pages_.lastUsed, size_t(s.poolPages) * 4, kStorageBufferUsage,
                              "vsm_last_used"));
    // With the static layer the second half holds each page's static twin (vsm_types.h).
    ML_TRY(createDeviceBuffer(d, pages_.pool,
                              size_t(s.poolPages) * s.pageSize * s.pageSize * 4 * (s.staticLayer ? 2 : 1),
                              kStorageBufferUsage, "vsm_pool", 0xFFFFFFFFu));
    // The request list: a power of two, so vsm_sort's merge passes end on one sorted run.
    const uint32_t capacity = std::bit_ceil(std::clamp(s.requestCapacity, uint32_t(ML_VSM_BLOCK), 1u << 26));
    settings_.requestCapacity = capacity;
    // ML_VSM_MERGE_WAYS_LOG2 doublings of the run width per merge pass.
    pages_.mergePasses = (uint32_t(std::countr_zero(capacity / ML_VSM_BLOCK)) + ML_VSM_MERGE_WAYS_LOG2 - 1) /
                         ML_VSM_MERGE_WAYS_LOG2;
    // Words 0-3, the allocation passes' four dispatches, then each sort pass's (vsm_types.h).
    ML_TRY(createDeviceBuffer(d, pages_.sortArgs, (ML_VSM_ARGS_SORT + 3 * (pages_.mergePasses + 1)) * 4,
                              kIndirectUsage, "vsm_sort_args"));
    for (uint32_t i = 0; i < 2; ++i)
        ML_TRY(createDeviceBuffer(d, pages_.list[i], size_t(capacity) * 4, kStorageBufferUsage,
                                  "vsm_request_list"));
    ML_TRY(createDeviceBuffer(d, pages_.blockCounts, (capacity / ML_VSM_BLOCK + 1) * 4, kStorageBufferUsage,
                              "vsm_block_counts"));
    const uint32_t poolBlocks = (s.poolPages + ML_VSM_BLOCK - 1) / ML_VSM_BLOCK;
    ML_TRY(createDeviceBuffer(d, pages_.classCounts, size_t(poolBlocks) * 9 * 4, kStorageBufferUsage,
                              "vsm_class_counts"));
    ML_TRY(createDeviceBuffer(d, pages_.avail, size_t(s.poolPages) * 4, kStorageBufferUsage, "vsm_avail"));
    ML_TRY(
        createDeviceBuffer(d, pages_.rendered, size_t(s.poolPages) * 4, kStorageBufferUsage, "vsm_rendered"));
    // HPB levels 1..log2(S_0) as bits, hpbWords_ per map slot (2730 bits at S_0 = 64): a buffer, so map
    // slots are not bounded by maxImageArrayLayers. Cleared for the maps in use at every frame's start.
    hpbLevels_ = mips_ - 1;
    hpbWords_ = std::max(1u, (gpu::vsmHpbLevelOffset(s0_, mips_) + 31) / 32);
    // Two draw lists per mip (vsm_cull.comp): closed casters (drawn with back faces culled) and open ones.
    const size_t draws = 2 * size_t(mips_) * s.maxDrawsPerMip;
    ML_TRY(createDeviceBuffer(d, pages_.draws, draws * sizeof(VkDrawIndexedIndirectCommand), kIndirectUsage,
                              "vsm_draws"));
    ML_TRY(createDeviceBuffer(d, pages_.drawInfo, draws * 16, kStorageBufferUsage,
                              "vsm_draw_info")); // uvec4 (instance, map, page, 0) per draw
    ML_TRY(
        createDeviceBuffer(d, pages_.drawCounts, 2 * ML_VSM_MAX_MIPS * 4, kIndirectUsage, "vsm_draw_counts"));
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
        ML_TRY(createDeviceBuffer(d, pages_.meshletList, size_t(mips_) * settings_.maxMeshletsPerMip * 12,
                                  kStorageBufferUsage, "vsm_meshlet_list"));
        ML_TRY(createDeviceBuffer(d, pages_.meshTasks, size_t(mips_) * 16, kIndirectUsage, "vsm_mesh_tasks"));
    }

    slots_.resize(framesInFlight);
    for (Slot& sl : slots_) {
        ML_TRY(createBuffer(d, sl.constants, sizeof(gpu::VsmConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                            "vsm_constants"));
        ML_TRY(createBuffer(d, sl.counters, sizeof(gpu::VsmCounters), kIndirectUsage, "vsm_counters",
                            MemoryRole::Readback));
        ML_TRY(createBuffer(d, sl.probes, 16 + size_t(s.probeCapacity) * sizeof(gpu::GpuVsmProbe),
                            kStorageBufferUsage, "vsm_probes", MemoryRole::Readback));
    }
    return resizeMaps(
        d, std::min({s.maxMaps, std::max(s.initialMaps, 1u), uint32_t(0xFFFFFFFFull / entriesPerMap_)}));
}

Result<void> VirtualShadowMaps::resizeMaps(const Device& d, uint32_t capacity) {
    // Map slots come from a pool that grows (doubling, up to settings().maxMaps) when a light needs slots
    // and none are free: the page table keeps its entries (copied), the per-frame buffers are remade
    // (every frame rewrites them), and the new slots join the free list. Nothing waits: the copy is
    // recorded into the frame being prepared and the old buffers are released after it (FrameSetup).
    // Every new buffer is made before anything is replaced: out of memory leaves the old slots as they
    // were (the new ones are destroyed) and is returned.
    const uint32_t old = capacity_;
    const size_t entries = size_t(capacity) * entriesPerMap_;
    const size_t bitWords = (entries + 31) / 32;
    VsmPages next; // the map-sized buffers only
    std::vector<Slot> nextSlots(slots_.size());
    auto made = [&]() -> Result<void> {
        ML_TRY(createDeviceBuffer(d, next.table, entries * 4, kStorageBufferUsage, "vsm_page_table"));
        // lookup, fallback, then wanted (either) marks
        ML_TRY(createDeviceBuffer(d, next.marks, 3 * bitWords * 4, kStorageBufferUsage, "vsm_marks"));
        ML_TRY(createDeviceBuffer(d, next.dirtyMips, size_t(capacity) * 4, kStorageBufferUsage,
                                  "vsm_dirty_mips"));
        ML_TRY(createDeviceBuffer(d, next.dirtyMaps, size_t(capacity) * 4, kStorageBufferUsage,
                                  "vsm_dirty_maps"));
        ML_TRY(createDeviceBuffer(d, next.hpb, size_t(capacity) * hpbWords_ * 4, kStorageBufferUsage,
                                  "vsm_hpb"));
        for (Slot& sl : nextSlots) {
            ML_TRY(createBuffer(d, sl.maps, size_t(capacity) * sizeof(gpu::GpuVsmMap), kStorageBufferUsage,
                                "vsm_maps"));
            ML_TRY(createBuffer(d, sl.coverage, bitWords * 4, kStorageBufferUsage, "vsm_coverage"));
            // Two regions: any caster's bounds changed, then a static caster's (the static twins).
            ML_TRY(createBuffer(d, sl.stale, 2 * bitWords * 4, kStorageBufferUsage, "vsm_stale"));
            ML_TRY(createBuffer(d, sl.active, size_t(capacity) * 4, kStorageBufferUsage, "vsm_active"));
            // At most one run per active map and level of detail.
            ML_TRY(createBuffer(d, sl.runs,
                                size_t(capacity) * std::max(mips_, settings_.clipLevels) * sizeof(glm::uvec4),
                                kStorageBufferUsage, "vsm_runs"));
            ML_TRY(createBuffer(d, sl.rankBase, size_t(capacity) * mips_ * 4, kStorageBufferUsage,
                                "vsm_rank_base"));
        }
        return {};
    }();
    auto mapSized = [](VsmPages& p) {
        return std::array<Buffer*, 5>{&p.table, &p.marks, &p.dirtyMips, &p.dirtyMaps, &p.hpb};
    };
    auto slotSized = [](Slot& sl) {
        return std::array<Buffer*, 6>{&sl.maps, &sl.coverage, &sl.stale, &sl.active, &sl.runs, &sl.rankBase};
    };
    if (!made) {
        for (Buffer* b : mapSized(next)) destroyBuffer(d, *b);
        for (Slot& sl : nextSlots)
            for (Buffer* b : slotSized(sl)) destroyBuffer(d, *b);
        return made;
    }
    if (old > 0) {
        // The old slots' entries, copied by the frame being recorded (FrameSetup) after the new table's
        // fill: no submit or wait on the host's queue. Outside record() a one-time copy, waited for.
        const VkBufferCopy region{0, 0, VkDeviceSize(old) * entriesPerMap_ * 4};
        if (auto r = copyBufferInFrame(d, pages_.table, next.table, region, "vsm_page_table_grow"); !r) {
            for (Buffer* b : mapSized(next)) destroyBuffer(d, *b);
            for (Slot& sl : nextSlots)
                for (Buffer* b : slotSized(sl)) destroyBuffer(d, *b);
            return r;
        }
    }
    // Frames in flight (and the copy above) may still read the old buffers: released after the frame.
    for (Buffer* b : mapSized(pages_)) releaseAfterFrame(d, *b);
    const auto nextBuffers = mapSized(next);
    const auto ownBuffers = mapSized(pages_);
    for (size_t i = 0; i < ownBuffers.size(); ++i) *ownBuffers[i] = *nextBuffers[i];
    markWords_ = bitWords;
    for (size_t k = 0; k < slots_.size(); ++k) {
        Slot& sl = slots_[k];
        for (Buffer* b : slotSized(sl)) releaseAfterFrame(d, *b);
        const auto from = slotSized(nextSlots[k]);
        const auto to = slotSized(sl);
        for (size_t i = 0; i < to.size(); ++i) *to[i] = *from[i];
        sl.host.coverage.resize(bitWords, 0);
        sl.host.stale.assign(2 * bitWords, 0);
        sl.bitsFull = true; // new buffers: uploaded whole once
        sl.uploadedMaps.clear();
        sl.mapStamp.clear(); // host.maps rewritten from maps_ in full next frame
        sl.uploadedActive.clear();
        sl.uploadedRankBase.clear();
        sl.uploadedRuns.clear();
        sl.orderBuilt = false; // rankBase was resized
        sl.host.maps.resize(capacity, gpu::GpuVsmMap{});
        sl.mapKey.resize(capacity, glm::uvec4(0));
        sl.host.rankBase.resize(size_t(capacity) * mips_, 0);
    }
    maps_.resize(capacity, VsmMapInfo{});
    wasActive_.resize(capacity, 0);
    for (uint32_t i = old; i < capacity; ++i) freeSlots_.push_back(i);
    std::sort(freeSlots_.rbegin(), freeSlots_.rend()); // descending: the back is the lowest
    capacity_ = capacity;
    return {};
}

void VirtualShadowMaps::destroy(const Device& d) {
    if (!settings_.enabled) return;
    for (Buffer* b :
         {&pages_.table,       &pages_.owners,     &pages_.lastUsed,    &pages_.marks,     &pages_.pool,
          &pages_.blockCounts, &pages_.avail,      &pages_.rendered,    &pages_.dirtyMips, &pages_.draws,
          &pages_.drawInfo,    &pages_.drawCounts, &pages_.meshletList, &pages_.meshTasks, &pages_.hpb,
          &pages_.list[0],     &pages_.list[1],    &pages_.classCounts, &pages_.sortArgs,  &pages_.dirtyMaps})
        destroyBuffer(d, *b);
    for (Slot& s : slots_)
        for (Buffer* b : {&s.constants, &s.maps, &s.coverage, &s.stale, &s.active, &s.runs, &s.rankBase,
                          &s.casters, &s.counters, &s.probes, &s.casterGroups, &s.casterOrder, &s.cullPairs})
            destroyBuffer(d, *b);
    slots_.clear();
}

Result<uint32_t> VirtualShadowMaps::allocateSlots(const Device& d, uint32_t count) {
    // The pool's bound: settings().maxMaps, and entry indices (map x entries per map) below 2^32.
    const uint32_t limit = uint32_t(std::min<uint64_t>(settings_.maxMaps, 0xFFFFFFFFull / entriesPerMap_));
    const uint32_t first = takeSlots(count);
    if (first != ML_VSM_NO_MAP || capacity_ + count > limit) return first;
    ML_TRY(resizeMaps(d, std::min(limit, std::max(2 * capacity_, capacity_ + count))));
    return takeSlots(count);
}

uint32_t VirtualShadowMaps::takeSlots(uint32_t count) {
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
    g.bias = glm::vec4(l.depthBias, l.normalBias, 0.0f, 0.0f); // texel contents do not depend on it
    g.info.z = uint32_t(l.texelScaleLog2);                     // nor on this (vsmPerMetre)
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
    if (!info.inUse || std::memcmp(&info.gpu, &g, sizeof(g)) != 0) touchMap(map);
    info.inUse = true;
    info.builtFrom = l;
    info.face = face;
    info.gpu = g;
}

void VirtualShadowMaps::observe(const VsmStats& s, uint64_t frame) {
    // A frame with no active map says nothing about the pool (a baked scene before any dynamic caster
    // comes near a light): it leaves the policy as it was.
    if (!settings_.enabled || s.mapsActive == 0) return;
    observed_ = true;
    // Near pressure: half the pool marked, or lookups already short of pages.
    if (uint64_t(s.pagesMarked) * 2 >= settings_.poolPages || s.fallbacks > 0 || s.requestOverflow > 0) {
        nearPressure_ = true;
        nearPressureFrame_ = std::max(nearPressureFrame_, frame);
    }
}

bool VirtualShadowMaps::reservesFallbacks(uint64_t frame) const {
    if (!settings_.fallbacksOnDemand || !observed_) return true;
    return nearPressure_ && frame <= nearPressureFrame_ + settings_.fallbackHoldFrames;
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
    s.fragmentsDrawn = c.fragmentsDrawn;
    s.dirtyPageTexels = uint64_t(c.pagesRendered) * settings_.pageSize * settings_.pageSize;
    s.pageClipOverflow = c.pageClipOverflow;
    s.pagesNew = c.pagesNew;
    s.pagesInvalidatedCaster = c.pagesInvalidatedCaster;
    s.pagesRenderedDynamic = c.pagesRenderedDynamic;
    s.groupTests = c.groupTests;
    s.groupsRefused = c.groupsRefused;
    s.pairOverflow = c.pairOverflow;
    s.poolPages = settings_.poolPages;
    s.lightsWithPages = slot.lightsWithPages;
    s.lightsWithoutSlot = slot.lightsWithoutSlot;
    s.requestOverflow = c.listOverflow;
    s.mapsActive = slot.activeCount;
    const uint64_t page = uint64_t(settings_.pageSize) * settings_.pageSize * 4;
    s.poolBytes = page * settings_.poolPages * (settings_.staticLayer ? 2 : 1); // with the static twins
    // An allocated page holds its static twin too (only written with caching: it is the pool's memory).
    s.usedBytes = page * c.pagesAllocated * (settings_.staticLayer ? 2 : 1);
    const uint64_t mip0 = uint64_t(settings_.resolution) * settings_.resolution * 4;
    uint64_t allMips = 0;
    for (uint32_t m = 0; m < mips_; ++m) allMips += mip0 >> (2 * m);
    // The projection kind per active map from its key (16 B a map) rather than its record.
    for (uint32_t map : slot.host.active) {
        const bool ortho = slot.mapKey[map].x == ML_VSM_ORTHOGRAPHIC;
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

std::vector<uint32_t> VirtualShadowMaps::read(const Device& d, VsmState state) const {
    switch (state) {
    case VsmState::Table:
        return readWords(d, pages_.table, size_t(mapsInUse_) * entriesPerMap_);
    case VsmState::Owners:
        return readWords(d, pages_.owners, settings_.poolPages);
    case VsmState::LastUsed:
        return readWords(d, pages_.lastUsed, settings_.poolPages);
    case VsmState::Marks: // lookup and fallback marks (the wanted bits are their OR)
        return readWords(d, pages_.marks, 2 * markWords_);
    case VsmState::SortArgs: // words 0-3: sorted buffer, one-workgroup flag, list length
        return readWords(d, pages_.sortArgs, 4);
    case VsmState::PagePool:
        break;
    }
    return readWords(d, pages_.pool, size_t(settings_.poolPages) * settings_.pageSize * settings_.pageSize);
}
std::vector<uint32_t> VirtualShadowMaps::readHpb(const Device& d, uint32_t map, uint32_t level) const {
    std::vector<uint8_t> bytes =
        readBuffer(d, pages_.hpb, VkDeviceSize(map) * hpbWords_ * 4, size_t(hpbWords_) * 4);
    std::vector<uint32_t> bits(hpbWords_);
    std::memcpy(bits.data(), bytes.data(), bytes.size());
    const uint32_t width = s0_ >> (level - 1), height = s0_ >> level;
    const uint32_t first = gpu::vsmHpbLevelOffset(s0_, level);
    std::vector<uint32_t> out(size_t(width) * height);
    for (size_t i = 0; i < out.size(); ++i) {
        const size_t bit = first + i;
        out[i] = (bits[bit >> 5] >> (bit & 31u)) & 1u;
    }
    return out;
}
std::vector<gpu::GpuCasterGroup> VirtualShadowMaps::readCasterGroups(const Device& d,
                                                                     uint32_t slotIndex) const {
    const Slot& slot = slots_[slotIndex];
    std::vector<gpu::GpuCasterGroup> out((slot.casterCount + ML_VSM_CULL_GROUP - 1) / ML_VSM_CULL_GROUP);
    if (out.empty()) return out;
    std::vector<uint8_t> bytes =
        readBuffer(d, slot.casterGroups, 0, out.size() * sizeof(gpu::GpuCasterGroup));
    std::memcpy(out.data(), bytes.data(), bytes.size());
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
