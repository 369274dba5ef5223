// Virtual shadow map GPU structs and page-table encoding, defined once for C++ and GLSL (included by
// shadows/virtual/*.cpp and every vsm_*.comp / vsm_draw.* shader), and the push blocks of its passes.
// Layout rules as in shaders/shared/gpu_types.h, static_asserted on the C++ side.
//
// Vocabulary (shadows/virtual/vsm.h has the algorithm):
//   map      one virtual shadow map: a spot light, one cube face of a point light, or one clip level of
//            a directional light. Maps live in slots 0..maxMaps-1; a light's maps are consecutive.
//   page     pageSize^2 texels of a map at one mip. Mip m of a map has S_m = S_0 >> m pages per side,
//            S_0 = virtualResolution / pageSize. Directional clip levels use mip 0 only.
//   entry    one page-table word per (map, mip, page): map * entriesPerMap + mipOffset(m) + y * S_m + x.
//   physical page  pageSize^2 uint depths in the one pool shared by every light.
#ifndef ML_VSM_TYPES_H
#define ML_VSM_TYPES_H

#include "shaders/shared/gpu_types.h"

// Page-table entry bits. The physical page index sits in the low 24 bits (16M pages: far above any
// pool that fits in memory at 4 B per texel).
#define ML_VSM_PHYS_MASK 0x00FFFFFFu
#define ML_VSM_ALLOCATED 0x01000000u // a physical page backs the entry
#define ML_VSM_VALID 0x02000000u     // the physical page holds what a fresh render would (cached)
#define ML_VSM_DIRTY 0x04000000u     // rendered this frame (cleared and drawn into)
// The static layer (VsmSettings::staticLayer): each physical page has a twin in the pool's second half
// holding the depths of the static casters alone. STATIC_VALID: the twin holds what a fresh render of
// the static casters would; DIRTY_STATIC: the twin is rendered this frame too. A page that lost VALID
// to a moving dynamic caster only keeps STATIC_VALID: only the dynamic casters are drawn again, and
// vsm_merge takes the minimum of them and the twin (the static ones are not drawn again).
#define ML_VSM_STATIC_VALID 0x08000000u
#define ML_VSM_DIRTY_STATIC 0x10000000u
// vsm_assign's rendered-page list: this bit on the physical page index when its twin is kept (the clear
// pass empties the page only, not the twin).
#define ML_VSM_RENDER_FROM_STATIC 0x80000000u
#define ML_VSM_NO_OWNER 0xFFFFFFFFu // physical page without a virtual page

// GpuVsmMap.info.x: projection kind.
#define ML_VSM_PERSPECTIVE 0u
#define ML_VSM_ORTHOGRAPHIC 1u
// GpuVsmMap.info.y flags.
#define ML_VSM_MAP_DYNAMIC_ONLY 1u // the light has a static bake: pages hold dynamic casters only
#define ML_VSM_MAP_INVALIDATE 2u   // the light moved or the slot is new: every page is stale

// vsm_mark_cluster.comp's workgroup: one per tile, its lanes sharing the tile's cluster-light pairs.
// Eight is lavapipe's SIMD width: each further group of eight lanes walks the tile's slices again.
#define ML_VSM_CLUSTER_LANES 8u

// Lookup results of the probe pass (GpuVsmProbe.info.w).
#define ML_VSM_PROBE_PAGE 0u      // read from a page at the wanted mip
#define ML_VSM_PROBE_FALLBACK 1u  // read from a coarser allocated page (pool full)
#define ML_VSM_PROBE_NO_CASTER 2u // no dynamic caster's bounds cover the texel: visibility 1
#define ML_VSM_PROBE_MISSING 3u   // no valid page at any mip (counted; must stay 0)

#ifdef __cplusplus
namespace ml::gpu {
#endif

// One virtual map, 192 bytes, written by the CPU each frame (shadows/virtual/vsm.cpp).
ML_STRUCT(GpuVsmMap) {
    mat4 viewProj; // world -> clip of the whole map (NDC [-1,1]^2; viewport of the mip rescales)
    mat4 view;     // world -> light view, looking down -Z
    vec4 params;   // x tan(fov/2) (perspective) or half extent (orthographic), y near, z far, w unused
    uvec4 info;    // x ML_VSM_PERSPECTIVE/ORTHOGRAPHIC, y flags, z log2 of the light's texel scale as a
                   // signed integer (vsmPerMetre), w unused
    uvec4 light;   // x module light id, y clip level (directional) or face, z mips, w unused
    vec4 bias;     // the light's shadow bias (LightDesc): x depth bias in texels of the mip read (default
                   // 0.5), y scale on the one-texel normal offset (default 1), zw 0
};

// Frame-wide constants of the VSM passes (uniform), 80 bytes.
ML_STRUCT(VsmConstants) {
    uvec4 page;    // x page size, y log2(page size), z S_0 (pages per side at mip 0), w mips of a map
    uvec4 sizes;   // x entries per map, y maps in use (slots 0..y-1 are scanned), z pool pages, w frame
    uvec4 options; // x PCF radius, y caching (0: every marked page is redrawn), z virtual resolution,
                   // w first word of the fallback marks (they follow the lookup marks in one buffer)
    vec4 camera;   // x pixel footprint per metre of distance (2 tan(fovY/2) / height), y 1 when page draws
                   // are clipped to their page (VsmSettings::pageClip), else 0; z 1 when receivers reserve
                   // fallback pages this frame (VsmSettings::fallbacksOnDemand), else 0; w 1 with the
                   // static layer (VsmSettings::staticLayer: the pool's second half) and caching, else 0
    uvec4 order;   // x runs of the allocation order (vsm_alloc_common.glsl), y entries in them, z capacity
                   // of the request list (a power of two >= ML_VSM_BLOCK), w HPB words per map slot
};

// Counters written by the VSM passes with atomics, read back when the frame's slot comes round.
ML_STRUCT(VsmCounters) {
    uint pagesMarked;        // entries marked this frame
    uint pagesCached;        // marked entries whose page was allocated and valid (not redrawn)
    uint pagesRendered;      // marked entries cleared and drawn this frame
    uint pagesInvalidated;   // entries that lost VALID this frame (moved caster or light)
    uint pagesEvicted;       // cached pages given to another entry (least recently used first)
    uint fallbacks;          // marked entries left without a page (pool full): lookups use a coarser mip
    uint requests;           // marked entries without a page at the start of allocation
    uint available;          // physical pages free or evictable this frame
    uint pagesAllocated;     // entries with a physical page after allocation
    uint instancesDrawn;     // (instance, map, mip) draws emitted
    uint instancesCulledHpb; // (instance, map, mip) pairs inside range and frustum but over no dirty page
    uint drawOverflow;       // draws that did not fit the draw buffer (counted, never silent)
    uint dispatchX, dispatchY, dispatchZ; // clear pass: one workgroup per rendered page (indirect)
    uint pressure; // 1 when requests exceed the available pages: fallback pages are rendered this frame
    // Mesh path (vsm_expand.comp, vsm_draw.task, vsm_draw.mesh), in meshlets of (instance, map, mip):
    uint meshletsTotal;          // of every (caster, active map, dirty mip) the map takes (before culling)
    uint meshletsCulledFrustum;  // expansion: the instance's box outside the map's frustum
    uint meshletsCulledHpb;      // expansion: the instance's box over no dirty page (HPB)
    uint meshletsAfterExpansion; // appended to the meshlet-instance lists
    uint meshletOverflow;        // did not fit a list (counted, never silent)
    uint taskCulledFrustum;      // task: the meshlet's sphere outside the frustum
    uint taskCulledCone;         // task: every triangle faces away from the light (closed casters only)
    uint taskCulledHpb;          // task: the meshlet's bounds over no dirty page (HPB)
    uint meshletsAfterTask;      // meshlets past the task shader (one mesh workgroup per dirty page each)
    uint trianglesAfterTask;     // triangles of those meshlets, once per page each is clipped to
    uint trianglesRasterized; // triangles the mesh shader emitted (not culled as zero-area or sample-free);
                              // vertex path: triangles of the indexed draws
    // The request list (vsm_mark appends the priority rank of every entry wanted this frame, once):
    uint listCount;    // entries in the list (vsm_list clamps it to the capacity, VsmConstants.order.z)
    uint listOverflow; // wanted entries that did not fit the list (counted, never silent)
    uint listGroupsX, listGroupsY, listGroupsZ; // the list passes' indirect dispatch: ML_VSM_BLOCK per group
    // vsm_pairs' indirect dispatch: x workgroups of ML_VSM_CULL_GROUP caster groups (the CPU), y maps
    // with a dirty page (vsm_assign appends each to the dirty-map list), z 1.
    uint cullGroupsX, cullGroupsY, cullGroupsZ;
    // Page draws (vsm_draw.frag): fragment-shader invocations, helpers excluded. Each draw is clipped to
    // one dirty page (both raster paths), so this follows the dirty pages' texels times the casters'
    // depth complexity there, not the mips' virtual resolution.
    uint fragmentsDrawn;
    uint pageClipOverflow; // mesh path: meshlets drawn unclipped (whole mip, fragments outside dirty pages
                           // discarded) because their task group's page list was full (ML_VSM_TASK_PAGES)
    // Why pages are rendered (cached frames: what caching could not keep):
    uint pagesNew;               // rendered entries that took a physical page this frame (new to the view,
                                 // or evicted before); the rest of pagesRendered had a page that lost VALID
    uint pagesInvalidatedCaster; // of pagesInvalidated: by a moved caster's bounds only (stale bits)
    uint pagesRenderedDynamic;   // rendered from their static twin: only dynamic casters drawn
    // The culling's caster groups (vsm_groups.comp), per (group, map with a dirty page) workgroup:
    uint groupTests;    // groups tested against a map's frustum (they had casters the map takes)
    uint groupsRefused; // of those, outside it: none of the group's casters was read
    // vsm_pairs: the (group, map) pairs left, one vsm_cull / vsm_expand workgroup each, and the culling's
    // indirect dispatch (x, y: vsm_pairs' closing thread, within the limits). pairOverflow: pairs past
    // the list's capacity or the dispatch's rows, whose casters were not culled or drawn (counted,
    // never silent; the capacity holds every group with every active map, so it stays 0 unless the
    // device's storage-buffer range cut the list).
    uint pairCount;
    uint pairOverflow;
    uint pairGroupsX, pairGroupsY, pairGroupsZ;
};

// A caster for the draw passes: world bounds and the indexed draw of its mesh. 64 bytes.
ML_STRUCT(GpuCaster) {
    vec4 lo;        // world AABB min, w unused
    vec4 hi;        // world AABB max, w unused
    uvec4 draw;     // x index count, y first index, z vertex offset, w 1 when dynamic
    uvec4 meshlets; // x first meshlet, y meshlet count, z 1 when the mesh is closed (cone culling), w unused
};

// ML_VSM_CULL_GROUP consecutive casters (one vsm_cull / vsm_expand workgroup's), written by vsm_groups.comp
// every frame: the union of the world boxes of those that draw (index count > 0), and of the dynamic ones
// among them (a baked light's maps take only those), with their counts and meshlets. vsm_pairs refuses a
// (group, map) pair whose group box lies outside the map's frustum with one test instead of 64: every
// caster's box lies inside its group's, so the plane that refuses the group refuses each caster
// (vsmBoxInFrustum is `precise`: monotone in the box). 80 bytes.
ML_STRUCT(GpuCasterGroup) {
    vec4 lo;        // xyz min over the drawing casters' boxes (w unused)
    vec4 hi;        // xyz max
    vec4 dynamicLo; // the same over the dynamic drawing casters
    vec4 dynamicHi;
    uvec4 counts; // x drawing casters, y their meshlets, z dynamic drawing casters, w their meshlets
};

// One meshlet (meshoptimizer, built at Module::addMesh; sizes in shaders/shared/config.h), 64 bytes.
// Bounds are in the mesh's object space; the task shader takes them to world space with the instance's
// model matrix (sphere) or takes the light to object space (cone).
ML_STRUCT(GpuMeshlet) {
    vec4 sphere; // xyz centre, w radius
    vec4 cone;   // xyz axis (unit), w cutoff: every triangle faces away from viewers v with
                 // dot(normalize(apex - v), axis) >= cutoff
    vec4 apex;   // xyz cone apex, w unused
    uvec4 data;  // x first vertex (into the meshlet vertex list: global vertex indices), y first
                 // triangle (into the packed list: one word a | b << 8 | c << 16 of local indices),
                 // z vertex count, w triangle count
};

// One shaded pixel's lookup for one light, written by the probe pass (check vsm, tests).
ML_STRUCT(GpuVsmProbe) {
    uvec4 texel; // x map, y mip used, z texel x, w texel y (at the mip used)
    uvec4 info;  // x pixel index, y light id, z depth read (kDepthEmpty: empty texel), w ML_VSM_PROBE_*
    uvec4 tap;   // x the receiver's biased depth the texel is compared with, yzw unused
};

// The words of VsmPages::sortArgs (written by vsm_list or vsm_allocate_short_list each frame): 0 which
// list buffer ends sorted, 1 one when one workgroup allocated, 2 the closed list's length, 3 the pages
// owned at the allocation's start (a prefix of the pool: vsmOwnedPages); then indirect dispatches (x, y,
// z) of vsm_scan (one group per ML_VSM_BLOCK owned pages, then per ML_VSM_BLOCK list entries),
// vsm_assign (per ML_VSM_BLOCK list entries), vsm_alloc (one group), vsm_avail (written by vsm_alloc:
// the owned pages' groups when requests exceed the free pages, else none), then one per vsm_sort pass.
// All 0 groups after a list one workgroup allocated.
#define ML_VSM_ARGS_OWNED 3u
#define ML_VSM_ARGS_SCAN 4u
#define ML_VSM_ARGS_ASSIGN 7u
#define ML_VSM_ARGS_ALLOC 10u
#define ML_VSM_ARGS_AVAIL 13u
#define ML_VSM_ARGS_SORT 16u

// Push blocks. vsm_sort: width 0 sorts each block of ML_VSM_BLOCK list entries in shared memory; a width
// w >= ML_VSM_BLOCK merges groups of 2^ML_VSM_MERGE_WAYS_LOG2 sorted runs of w entries. vsm_list,
// vsm_allocate_short_list: width is the number of merge passes; shortList the longest list one workgroup
// sorts in shared memory (0: none, and in vsm_sort, vsm_list), with ML_VSM_ANY_LENGTH set when the
// multi-dispatch passes are not recorded (vsm_passes.cpp): longer lists are then allocated in the same
// workgroup too, sorted in the list buffers. 8 bytes.
#define ML_VSM_ANY_LENGTH 0x80000000u
ML_STRUCT(VsmSortPush) {
    uint width;
    uint shortList;
};

// vsm_cull and vsm_expand: one thread per (caster, map with a dirty page); `capacity` is the per-mip
// list size (cull: draws, VsmSettings::maxDrawsPerMip; expand: meshlet entries, maxMeshletsPerMip).
// 8 bytes.
ML_STRUCT(VsmCullPush) {
    uint casterCount;
    uint capacity;
};

// vsm_pairs: mode 0 tests (caster group, map with a dirty page) pairs into a list of `capacity`; mode 1
// (one thread) writes the culling's dispatch size, rows of rowWorkgroups (VsmSettings::cullRowWorkgroups).
// countMeshlets: the mesh path's meshlet counters take the refused groups'. 20 bytes.
ML_STRUCT(VsmPairsPush) {
    uint casterCount;
    uint countMeshlets;
    uint mode;
    uint rowWorkgroups;
    uint capacity;
};

// vsm_draw (raster path: .vert / .frag; mesh path: .task / .mesh / .frag): the mip drawn, and the mesh
// path's meshlet entries per mip (the raster path leaves it unused). 8 bytes.
ML_STRUCT(VsmDrawPush) {
    uint mip;
    uint maxMeshlets;
};

#ifdef __cplusplus
static_assert(sizeof(VsmSortPush) == 8);
static_assert(offsetof(VsmCounters, listGroupsX) == 116);
static_assert(sizeof(VsmCullPush) == 8);
static_assert(sizeof(VsmDrawPush) == 8);
static_assert(sizeof(VsmPairsPush) == 20);
static_assert(sizeof(GpuVsmMap) == 192);
static_assert(offsetof(GpuVsmMap, bias) == 176);
static_assert(offsetof(GpuVsmMap, params) == 128);
static_assert(offsetof(GpuVsmMap, light) == 160);
static_assert(sizeof(VsmConstants) == 80);
static_assert(sizeof(VsmCounters) == 188);
static_assert(offsetof(VsmCounters, pairGroupsX) == 176);
static_assert(offsetof(VsmCounters, fragmentsDrawn) == 140);
static_assert(offsetof(VsmCounters, cullGroupsX) == 128);
static_assert(offsetof(VsmCounters, meshletsTotal) == 64);
static_assert(sizeof(GpuCaster) == 64);
static_assert(offsetof(GpuCaster, meshlets) == 48);
static_assert(sizeof(GpuCasterGroup) == 80);
static_assert(offsetof(GpuCasterGroup, counts) == 64);
static_assert(sizeof(GpuMeshlet) == 64);
static_assert(offsetof(GpuMeshlet, data) == 48);
static_assert(sizeof(GpuVsmProbe) == 48);
} // namespace ml::gpu
#endif

#endif
