// Virtual shadow maps for dynamic casters: resolution-matched pages, one shared physical pool, caching.
// Follows RMVSM (Sakmary & Bittner 2025, ../shared/papers/rmvsm-sakmary-bittner-2025.txt):
//
//   per light: a spot light is one virtual map with a mip chain (section 3.2), a point light six (one
//     per cube face, 3.3), a directional light one map per clip level around the camera (3.1). Every
//     map has a page table (one word per page and mip, vsm_types.h); all share one pool of physical
//     pages (pageSize^2 uint depths).
//   each frame, on the GPU, after light culling:
//     vsm_mark    per receiver pixel, for each light of its cluster list with maps that it faces, the
//                 pages its lookup reads (resolution-matched mip, PCF kernel, bias) and, near pool
//                 pressure (VsmSettings::fallbacksOnDemand), two fallback pages (3 mips coarser, and the
//                 coarsest), drawn only in frames under pool pressure; the first want of
//                 an entry appends its priority rank to the request list (stream compaction);
//     vsm_allocate_short_list  one workgroup: closes the list; a list of at most ML_VSM_ONE_GROUP_LIST
//                 entries it also invalidates, sorts and allocates (the steps below in one dispatch, the
//                 same functions: the same pages), and the passes below get 0 groups; a longer one goes
//                 to them (VsmPasses::shortListLimit; where the device lacks the shared memory, vsm_list
//                 alone closes the list);
//     vsm_list    closes the list (capacity, overflow counted), finds the owned pages (a prefix of the
//                 pool: pages are taken in index order and never freed) and sizes the indirect
//                 dispatches below;
//     vsm_sort    sorts the list by rank (block sort, then merges of 8 runs): the allocation is
//                 deterministic;
//     vsm_scan    per owned physical page: clears last frame's DIRTY, invalidation of the owner entry
//                 (light moved, moved casters' old and new projected bounds: "stale" bits prepared by
//                 the CPU, a static caster's also invalidating the page's static twin), page classes per
//                 block (unwanted least recently used; free pages, past the prefix, come first); and in
//                 the same dispatch, per listed entry: LRU refresh, requests;
//     vsm_alloc   one workgroup over block counts: request ranks, available-page list bases;
//     vsm_avail   per owned physical page, only when some request must evict: the available-page list;
//     vsm_assign  per listed entry: pages for the requests in priority order (each light's coarsest level
//                 first) from that list; marked pages that are not valid are rendered (DIRTY);
//     vsm_hpb     per listed entry: a DIRTY page sets its hierarchical page buffer cells (bits in a
//                 buffer, 4.3), so culling tests at most 2x2 cells;
//   every pass above walks the request list or the physical pool, never every entry of every map;
//     vsm_groups  per 64 casters of the culling order (static casters in Morton order): their joint box;
//     vsm_pairs   per (caster group, map with a dirty page): the pairs whose box is inside the frustum;
//     vsm_cull    per caster of a pair left: frustum and HPB tests -> two draw lists per mip (4.2):
//                 closed casters in front of the near plane (back faces culled) and the rest;
//                 mesh path (settings.raster; Auto takes it on GPUs): vsm_expand does the same tests and
//                 appends the caster's meshlets to a per-mip meshlet-instance list; vsm_draw.task culls
//                 meshlets (frustum, back-facing cone of closed casters, HPB), vsm_draw.mesh triangles
//                 covering no sample or back-facing on a closed caster; vsm_draw.frag is shared, so both
//                 paths write the same depths;
//     vsm_clear   the rendered pages' texels to empty (indirect, one workgroup per page), and their static
//                 twins (the static layer, VsmSettings::staticLayer: the static casters' depths alone, in
//                 the pool's second half) unless only a moving dynamic caster invalidated the page;
//     vsm_draw    per mip two indirect-count draws (the lists above), each draw clipped to its dirty
//                 page; fragments of DIRTY
//                 pages take the atomic minimum of their depth in the physical page;
//     vsm_merge   static layer: the static casters went to the twins, the dynamic ones to the pages; each
//                 rendered page takes the minimum of both (the value one layer would hold, bit for bit);
//   and the evaluation pass reads pages through the page table (vsm_common.glsl), falling back to a
//   coarser mip when the pool had no page, so a full pool never leaves a pixel unshadowed silently (a
//   lookup with no page at all is counted; that happens when pressure arrives within the frames in
//   flight, before reservations resume).
//
// "No more than the scene needs": a light with a static bake (shadows/static/) keeps only pages under
// some dynamic caster's projected bounds ("coverage" bits, CPU, per frame) and draws dynamic casters
// only; other lights (moving ones, or without a bake) draw every caster. Lights out of view get no
// marks; lights whose maps nobody needs keep their cached pages until the LRU evicts them, and are
// invalidated whole when they become active again (their maps missed the invalidations meanwhile).
#pragma once
#include "gpu/program.h"
#include "shadows/static/dual_depth.h"
#include "manylights/vsm_settings.h"
#include "shadows/virtual/vsm_types.h"

#include <glm/glm.hpp>

#include <span>
#include <memory>
#include <vector>

namespace ml {

// What the module tells the VSM each frame.
struct VsmLight {
    uint32_t kind = 0; // ML_LIGHT_*
    glm::vec3 position{0.0f}, direction{0.0f, -1.0f, 0.0f};
    float range = 10.0f, outerAngle = 0.6f;
    bool castsShadows = true;
    bool moving = false;     // LightDesc::dynamic
    bool staticBake = false; // every face has a static bake: maps hold dynamic casters only
    // LightDesc::shadowDepthBias / shadowNormalBias: GpuVsmMap.bias (lookups and marking, vsm_math.h).
    float depthBias = 0.5f, normalBias = 1.0f;
    // log2 of LightDesc::shadowTexelScale (-2..3): GpuVsmMap.info.z, read by vsmPerMetre (vsm_math.h).
    int32_t texelScaleLog2 = 0;
    // The host's stamp of the light this was made from (a new value at every change; 0: none, then
    // prepare() compares the fields). Not part of the comparison: a light set to what it was is the same.
    uint64_t version = 0;
    bool operator==(const VsmLight& o) const {
        return kind == o.kind && position == o.position && direction == o.direction && range == o.range &&
               outerAngle == o.outerAngle && castsShadows == o.castsShadows && moving == o.moving &&
               staticBake == o.staticBake && depthBias == o.depthBias && normalBias == o.normalBias &&
               texelScaleLog2 == o.texelScaleLog2;
    }
};
struct VsmInstance {
    glm::vec3 lo{0.0f}, hi{0.0f}; // world bounds this frame
    uint32_t indexCount = 0, firstIndex = 0, vertexOffset = 0;
    uint32_t firstMeshlet = 0, meshletCount = 0; // mesh path
    bool closed = false;                         // the mesh is closed (meshIsClosed): cone culling allowed
    bool dynamic = false;
    bool castsShadows = true;
    // The host's stamp of the inputs this record was made from (a new value at every change; 0: none,
    // then prepare() compares the record field by field): unchanged casters cost a compare of stamps.
    uint64_t version = 0;
};
struct VsmCamera {
    glm::vec3 position{0.0f};
    float fovY = 1.0f;
    uint32_t height = 1;
};

// Per map slot, what the CPU set up this frame (tests and `check vsm` read it).
struct VsmMapInfo {
    bool inUse = false;
    uint32_t light = 0;        // module light id
    uint32_t face = 0;         // cube face or clip level
    uint64_t builtVersion = 0; // builtFrom's VsmLight::version: an equal stamp skips the comparison
    gpu::GpuVsmMap gpu{};
    LightFrustum frustum; // the volume a reference rasteriser uses (clip levels: orthographic)
    VsmLight builtFrom{}; // the light as gpu was built from it (spot and point maps are rebuilt only
                          // when it changes: their matrices do not depend on the camera)
};

// Sizes of the page tables and marks (vsm_types.h's vocabulary).
struct VsmLayout {
    uint32_t pagesPerSide = 0;  // S_0, mip-0 pages per map side
    uint32_t mips = 0;          // log2(S_0) + 1
    uint32_t entriesPerMap = 0; // page-table words per map, every mip
    uint32_t hpbLevels = 0;     // HPB levels 1..mips - 1
    size_t markWords = 0;       // words of one mark region (lookup marks; fallback and wanted marks follow)
    uint32_t hpbWords = 0;      // words of HPB bits per map slot (vsm_math.h)
};
// What prepare() computes per slot on the CPU, uploaded for the passes (tests compare the GPU with it).
struct VsmSlotHost {
    std::vector<uint32_t> coverage, stale; // bits per page-table entry
    std::vector<uint32_t> active;          // active map slots
    std::vector<glm::uvec4> runs;          // allocation order: (first rank, map, mip, entries)
    std::vector<uint32_t> rankBase;        // first rank per (map slot, mip) of the active maps (vsm_mark)
    std::vector<gpu::GpuVsmMap> maps;      // per map slot
    // The CPU work of coverage and stale bits this frame (markCoverageAndStale): box-against-light
    // sphere tests and box projections into maps. Both follow the dynamic and changed instances and
    // the lights near them, not the instance count (VsmCpu.WorkFollowsTheMovingInstances).
    uint64_t sphereTests = 0, projections = 0;
    // Caster records this frame compared or written (uploadSlot): the changes since the slot's last
    // frame, or every instance when its buffer is new.
    uint64_t castersVisited = 0;
};
// Persistent GPU state a host copy can be read of (VirtualShadowMaps::read): the page table (entries of
// the maps in use), physical page owners and last use, marks (lookup then fallback), the page pool, and
// the list's words 0-3 (which buffer ends sorted, 1 or 2 when one workgroup allocated: in shared memory or
// in the list buffers, the list's length).
enum class VsmState { Table, Owners, LastUsed, Marks, PagePool, SortArgs };

// The GPU state the passes share, created with the settings: persistent across frames (page table,
// physical page owners and last use, the pool), and per frame but kept (marks, block counts, lists,
// draw lists, HPB).
struct VsmPages {
    Buffer table, owners, lastUsed, marks, pool, blockCounts, avail, rendered, dirtyMips, draws, drawInfo,
        drawCounts, meshletList, meshTasks;
    Buffer hpb;               // hierarchical page buffer bits, layout().hpbWords per map slot (vsm_math.h)
    Buffer list[2];           // the request list and its sort's ping-pong twin (VsmSettings::requestCapacity)
    Buffer classCounts;       // per owned-page block and page class: counts, then bases (vsm_scan, vsm_alloc)
    Buffer dirtyMaps;         // maps with a page rendered this frame (vsm_assign): the culling's y
    Buffer sortArgs;          // vsm_list: which of list[] ends sorted, and each vsm_sort pass's dispatch
                              // (then the multi-dispatch passes': vsm_allocate_short_list.comp)
    uint32_t mergePasses = 0; // vsm_sort's merge passes at most: log8(capacity / ML_VSM_BLOCK), rounded up
};
// Per frame in flight: what prepare() computes and uploads for the passes.
struct VsmSlot {
    Buffer constants, maps, coverage, stale, active, runs, rankBase, casters, counters, probes;
    Buffer casterGroups; // GPU-only: vsm_groups.comp's bounds per ML_VSM_CULL_GROUP casters, every frame
    Buffer casterOrder;  // the casters in culling order (VirtualShadowMaps::buildCasterOrder)
    Buffer cullPairs;    // GPU-only: vsm_pairs' (group, map) list of pairCapacity entries
    uint32_t pairCapacity = 1;     // every caster group x active map, within the storage-buffer range
    uint64_t casterOrderStamp = 0; // the order's stamp casterOrder holds (0: none)
    VsmSlotHost host;
    uint32_t orderEntries = 0; // page-table entries of the allocation order
    uint32_t lightsWithPages = 0, lightsWithoutSlot = 0, activeCount = 0, casterCount = 0;
    // Coverage and stale bits are sparse (a few maps under moving casters): only the maps whose words
    // were set are cleared, and only those of this frame and of the slot's previous frame uploaded.
    // bitsFull: the buffers are new (slot growth), so everything is uploaded once.
    std::vector<uint32_t> bitMaps;    // maps with a set coverage or stale bit in this slot's buffers
    std::vector<uint32_t> bitUploads; // this frame's word ranges to upload (maps; repeats allowed)
    bool bitsFull = true;
    // What this slot's maps and casters buffers hold (a mirror): only elements that differ are written,
    // so a frame where 1 % of the instances moved writes about 1 % of the casters. Cleared when the
    // buffers are made anew.
    std::vector<gpu::GpuVsmMap> uploadedMaps;
    // Per map, the mapStamp_ host.maps was last written from (~0: never), the maps given a per-frame
    // INVALIDATE flag in this slot's last frame (rewritten next time, the flag gone), and this frame's
    // rewritten or flagged maps: the only ones compared with uploadedMaps.
    std::vector<uint64_t> mapStamp;
    std::vector<uint32_t> flaggedMaps, mapsWritten;
    std::vector<gpu::GpuCaster> uploadedCasters;
    // Per caster, the VsmInstance::version uploadedCasters holds (0: none), and the casters changed
    // since this slot's last frame (prepare's `changed`, appended to every slot's list): only they are
    // compared and written, unless the buffer is new.
    std::vector<uint64_t> casterVersion;
    std::vector<uint32_t> pendingCasters;
    std::vector<uint32_t> uploadedActive, uploadedRankBase;
    std::vector<glm::uvec4> uploadedRuns;
    // Per map slot, what the allocation order reads of host.maps (x info.x: the projection, y light.y:
    // face or clip level, z light.z: levels, w bit 0 the DYNAMIC_ONLY flag, bit 1 in use), 16 B kept
    // beside the 192 B records (buildFrameMaps writes both): the order, the coverage test and readStats
    // read this.
    std::vector<glm::uvec4> mapKey;
    bool mapKeysChanged = true; // some map's key changed since the order was built
    uint32_t orderMaps = 0;     // the maps in use host.runs was built for
    bool orderBuilt = false;
    bool orderChanged = true; // this frame rebuilt runs and rankBase (uploadSlot compares them only then)
    // The request list's length in this slot's last frame, read before uploadSlot clears the counters
    // (~0: none yet). Only the GPU knows this frame's; VsmPasses records the allocation's one workgroup
    // alone when the last one was short (VsmPasses::oneWorkgroupOnly).
    uint32_t listBefore = ~0u;
    bool countersWritten = false; // the counters hold a frame's values (uploadSlot has run once)
};

// The state of the virtual shadow maps: settings, map slots, page tables, pool and per-slot buffers, and
// the CPU part of a frame (prepare). Its GPU passes are VsmPasses (vsm_passes.h).
struct VsmLightGrid; // vsm_prepare.cpp

class VirtualShadowMaps {
  public:
    Result<void> create(const Device& device, const VsmSettings& settings, uint32_t framesInFlight);
    void destroy(const Device& device);
    const VsmSettings& settings() const { return settings_; }
    bool enabled() const { return settings_.enabled; }
    // Pages drawn as meshlets (task and mesh shaders) rather than indexed draws (settings().raster after
    // the device check in create()).
    bool meshPath() const { return settings_.enabled && settings_.raster == VsmRaster::Mesh; }
    void setPcfRadius(uint32_t r) { pcf_ = r; }

    // CPU part of a frame: map slots, matrices, coverage and stale bits, casters. `lights` holds every
    // module light (by id); `visible` the ids in the visible-light buffer's order. `changed` lists every
    // instance whose record may differ from the one the last successful prepare() saw (repeats allowed;
    // new instances included): only those are compared, so a frame costs the changes, not the instance
    // count. Returns the first map slot per visible light (ML_VSM_NO_MAP: none), to go into
    // GpuLight.info.y. Out of memory (growing the map slots or the caster buffer) is an error; the state
    // stays valid and the next frame retries (with the same `changed` again).
    Result<std::vector<uint32_t>> prepare(const Device& device, uint32_t slot, uint64_t frame,
                                          std::span<const VsmLight> lights, std::span<const uint32_t> visible,
                                          std::span<const VsmInstance> instances,
                                          std::span<const uint32_t> changed, const VsmCamera& camera);
    // When the passes run (VsmPasses, engine/frame.h): the slot has active maps; the probe pass.
    bool active(uint32_t slot) const { return settings_.enabled && slots_[slot].activeCount > 0; }
    bool probing() const { return settings_.enabled && settings_.probeCapacity && mapsInUse_ > 0; }
    uint32_t mapsInUse() const { return mapsInUse_; }
    uint32_t mapCapacity() const { return capacity_; } // map slots now (grows up to settings().maxMaps)
    // The GPU state the passes read and write.
    const VsmPages& pages() const { return pages_; }
    const VsmSlot& slot(uint32_t slot) const { return slots_[slot]; }

    // Evaluation-pass bindings, in vsm_common.glsl's order: constants, maps, coverage, table, pool.
    const Buffer& constants(uint32_t slot) const { return slots_[slot].constants; }
    const Buffer& maps(uint32_t slot) const { return slots_[slot].maps; }
    const Buffer& coverage(uint32_t slot) const { return slots_[slot].coverage; }
    const Buffer& table() const { return pages_.table; }
    const Buffer& pagePool() const { return pages_.pool; }

    // Statistics of the frame last recorded in `slot` (call once its fence has passed).
    VsmStats readStats(uint32_t slot) const;
    // A completed frame's stats (the module calls it as each frame completes): whether the pool is near
    // pressure, for the fallback reservations of later frames (VsmSettings::fallbacksOnDemand).
    void observe(const VsmStats& stats, uint64_t frame);
    bool reservesFallbacks(uint64_t frame) const;

    // --- for tests, `check vsm` and `bench vsm` (engine/manylights_diagnostics.h wraps them) ---
    VsmLayout layout() const { return {s0_, mips_, entriesPerMap_, hpbLevels_, markWords_, hpbWords_}; }
    const std::vector<VsmMapInfo>& mapInfo() const { return maps_; }
    const gpu::VsmConstants& lastConstants() const { return lastConstants_; }
    // Wall time of the last prepare() on the CPU (the virtual shadow maps' share of record(); bench cpu).
    double lastPrepareMs() const { return lastPrepareMs_; }
    // What the last prepare() of a slot computed on the CPU.
    const VsmSlotHost& slotHost(uint32_t slot) const { return slots_[slot].host; }
    // A host copy of persistent GPU state (the device must be idle): the used part of the buffer.
    std::vector<uint32_t> read(const Device& device, VsmState state) const;
    std::vector<gpu::GpuVsmProbe> readProbes(uint32_t slot, uint32_t* overflow = nullptr) const;
    // The culling order (buildCasterOrder) and the caster groups vsm_groups.comp last wrote in `slot`
    // (the device must be idle), and the casters that slot's buffer holds (its mirror).
    const std::vector<uint32_t>& casterOrder() const { return casterOrder_; }
    std::vector<gpu::GpuCasterGroup> readCasterGroups(const Device& device, uint32_t slot) const;
    const std::vector<gpu::GpuCaster>& slotCasters(uint32_t slot) const {
        return slots_[slot].uploadedCasters;
    }
    // HPB level 1..layout().hpbLevels of one map slot as a grid of S_0 >> (level - 1) by S_0 >> level
    // cells, 0 or 1 each (layout in vsm_math.h), valid for the maps active in the frame last recorded.
    std::vector<uint32_t> readHpb(const Device& device, uint32_t map, uint32_t level) const;

  private:
    using Slot = VsmSlot;
    struct LightState {
        uint32_t firstMap = ML_VSM_NO_MAP, mapCount = 0, kind = 0;
        // VsmLight::version every one of its spot or point maps was last built or checked from (0: not
        // known; reset when its slots change): an equal stamp skips the light in buildFrameMaps.
        uint64_t builtVersion = 0;
    };
    // `count` consecutive free map slots (growing the slot pool when none are left), ML_VSM_NO_MAP when
    // settings().maxMaps are all in use.
    Result<uint32_t> allocateSlots(const Device& device, uint32_t count);
    uint32_t takeSlots(uint32_t count);
    Result<void> resizeMaps(const Device& device, uint32_t capacity);
    // The bit words [first, last) that hold map m's page-table entries (shared words at the ends).
    std::pair<size_t, size_t> mapBitWords(uint32_t m) const {
        return {size_t(m) * entriesPerMap_ / 32, (size_t(m + 1) * entriesPerMap_ + 31) / 32};
    }
    // prepare()'s steps, in order (vsm_prepare.cpp).
    void noteChanges(std::span<const VsmInstance> instances, std::span<const uint32_t> changed);
    std::vector<uint8_t> lightsNeedingMaps(std::span<const VsmLight> lights,
                                           std::span<const uint32_t> visible,
                                           std::span<const VsmInstance> instances) const;
    Result<void> assignMapSlots(const Device& device, Slot& slot, std::span<const VsmLight> lights,
                                const std::vector<uint8_t>& needs);
    void buildFrameMaps(Slot& slot, std::span<const VsmLight> lights, const VsmCamera& camera);
    void markCoverageAndStale(Slot& slot, std::span<const VsmLight> lights,
                              std::span<const VsmInstance> instances, std::span<const uint32_t> changed);
    std::vector<uint32_t> activateMaps(Slot& slot, std::span<const uint32_t> visible,
                                       const std::vector<uint8_t>& needs);
    void buildAllocationOrder(Slot& slot);
    Result<void> uploadSlot(const Device& device, Slot& slot, uint64_t frame,
                            std::span<const VsmInstance> instances, const VsmCamera& camera);
    void buildMap(uint32_t map, const VsmLight& light, uint32_t face, const VsmCamera& camera, bool& moved);

    VsmSettings settings_;
    uint32_t pcf_ = 0;
    uint32_t s0_ = 0, mips_ = 0, entriesPerMap_ = 0, mapsInUse_ = 0, capacity_ = 0;
    size_t markWords_ = 0; // words of one mark region (lookup marks; fallback marks follow)
    std::vector<Slot> slots_;
    std::vector<LightState> lightState_;
    std::vector<VsmMapInfo> maps_;
    std::vector<uint32_t> freeSlots_;
    std::vector<uint8_t> wasActive_;
    std::vector<VsmInstance> lastInstances_;
    // The instances that are dynamic shadow casters (coverage boxes, lights needing maps), kept from the
    // changes (noteChanges) instead of a pass over every instance per frame.
    std::vector<uint8_t> dynamicCaster_;
    std::vector<uint32_t> dynamicCasters_;
    // The casters in culling order: spatial neighbours in one culling workgroup (buildCasterOrder), made
    // anew when the instances or the dynamic set change, and a stamp per rebuild (slots upload it then).
    std::vector<uint32_t> casterOrder_;
    uint64_t casterOrderStamp_ = 0;
    void buildCasterOrder(std::span<const VsmInstance> instances);
    // The lights with maps binned for the box tests (vsm_prepare.cpp), rebuilt when they change.
    std::shared_ptr<VsmLightGrid> grid_;
    // Set when the lights with maps (slots, or a light's position, range or bake) may have changed:
    // only then is the grid's input remade. The directional lights with maps take every box.
    bool spheresDirty_ = true;
    std::vector<uint32_t> directionalWithMaps_;
    bool anyBakedMaps_ = false;      // some light with maps is baked (its maps take coverage boxes)
    std::vector<uint8_t> movedMaps_; // buildFrameMaps: maps whose projection changed this frame
    // Bumped (from mapStampNext_) whenever maps_[m]'s record or use changes: the slots' copies follow it.
    std::vector<uint64_t> mapStamp_;
    uint64_t mapStampNext_ = 0;
    void touchMap(uint32_t m) {
        if (mapStamp_.size() <= m) mapStamp_.resize(size_t(m) + 1, 0);
        mapStamp_[m] = ++mapStampNext_;
    }
    gpu::VsmConstants lastConstants_{};
    double lastPrepareMs_ = 0.0;
    bool observed_ = false;          // a frame has completed (observe)
    bool nearPressure_ = false;      // some completed frame was near pool pressure
    uint64_t nearPressureFrame_ = 0; // the last such frame

    VsmPages pages_;
    uint32_t hpbLevels_ = 0, hpbWords_ = 0;
};

// A cone from a spot light's position along its direction that contains its map's square frustum
// (half-angle tangent sqrt(2) tan(outer), 2 % wider); cos < -0.5: none (point and directional lights).
struct VsmCone {
    glm::vec3 axis{0.0f};
    float cos = -1.0f, sin = 0.0f;
    bool operator==(const VsmCone&) const = default;
};
VsmCone vsmSpotCone(const VsmLight& light);
// False only when the box lies wholly outside the cone, so outside the map's frustum: drawing it changes
// no texel of the map (VsmCpu.SpotConeNeverRefusesABoxTheMapTakes). markCoverageAndStale tests it before
// projecting, which saves the map record's read for boxes beside or behind a spot light; it is tighter
// than vsmProjectBox's plane test, which takes some boxes beside the frustum's corners (their stale bits
// were never needed).
bool vsmBoxMayTouchCone(const VsmCone& cone, glm::vec3 apex, glm::vec3 lo, glm::vec3 hi);

// Projected bounds of a world box in a map, in mip-0 pages (inclusive); false when the box is outside
// the map's frustum. A box reaching behind the light covers the whole map. Used for coverage and stale
// bits on the CPU (the GPU culling pass does the same test in vsm_cull.comp).
bool vsmProjectBox(const gpu::GpuVsmMap& map, glm::vec3 lo, glm::vec3 hi, uint32_t pagesPerSide,
                   glm::uvec4& rect);

} // namespace ml
