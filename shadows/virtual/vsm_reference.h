// CPU references of the virtual shadow map passes (shadows/virtual/vsm.h), for the tests:
//   vsmMarkReference      vsm_mark.comp: the mark bits from the G-buffer, the cluster lists, the lights
//                         and the frame's maps (same functions of vsm_math.h, same order: bit for bit);
//   vsmMarkClusterReference  vsm_mark_cluster.comp: the same marks per cluster-light pair (vsm_bounds.h);
//   vsmAllocateReference  vsm_scan (invalidation, LRU refresh) + vsm_alloc + vsm_avail + vsm_assign (the
//                         passes walk the sorted request list and the owned pages; this, every page), and
//                         vsm_allocate_short_list, which does them in one workgroup for a short list:
//                         invalidation, LRU refresh, requests in priority order, the ordered list of free and
//                         evictable pages, assignment, eviction, fallbacks, and which pages render this
//                         frame. The page table, the owners and the last-use frames it leaves equal the GPU's
//                         exactly.
//   vsmCasterGroupsReference  vsm_groups.comp: per ML_VSM_CULL_GROUP casters of the culling order, the
//                         union of the drawing (and of the dynamic drawing) casters' boxes, counts, meshlets;
//   vsmCheckInvariants    what must hold after every frame (no physical page shared, owners and
//                         table agree, the owned pages a prefix of the pool, every marked page
//                         allocated or counted as a fallback).
#pragma once
#include "shaders/shared/gpu_types.h"
#include "shadows/virtual/vsm_types.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace ml {

struct VsmMarkInputs {
    gpu::FrameConstants frame{};
    std::vector<float> sliceFar;
    std::vector<gpu::GpuLight> lights; // visible lights, info.y = first map
    std::vector<glm::uvec2> ranges;    // cluster lists (culling/culling.h)
    std::vector<uint32_t> pool;
    std::vector<float> depth;      // width * height, row-major
    std::vector<glm::vec4> normal; // G-buffer normals as stored (RGBA16F -> float; w < 0: not a receiver)
    gpu::VsmConstants constants{};
    std::vector<gpu::GpuVsmMap> maps; // indexed by map slot
    std::vector<uint32_t> coverage;   // one bit per entry
    size_t markWords = 0;             // size of the mark bit array
};
std::vector<uint32_t> vsmMarkReference(const VsmMarkInputs& in);
// vsm_mark_cluster.comp (VsmSettings::clusterMarking): per tile, the bounds of each slice's receivers
// and of their normals (as cluster_bounds.comp's receiver variant), and per (slice, light) pair none when
// every receiver faces away (vsmBoxFacesAway), else the pages vsm_bounds.h bounds, or the receivers'
// own marks where those exceed ML_VSM_CLUSTER_PAGES. Needs clustered culling (tiles of ML_TILE_SIZE).
// Bit for bit the GPU's. refinedPairs and facingAwayPairs (optional) receive, added, the pairs refined
// per pixel and the pairs vsmBoxFacesAway skipped.
std::vector<uint32_t> vsmMarkClusterReference(const VsmMarkInputs& in, size_t* refinedPairs = nullptr,
                                              size_t* facingAwayPairs = nullptr);

struct VsmAllocState {
    std::vector<uint32_t> table;    // per entry of every slot in use
    std::vector<uint32_t> owners;   // per physical page
    std::vector<uint32_t> lastUsed; // per physical page
};
// One frame of allocation. `marks` (lookup marks, then fallback marks from word constants.options.w)
// and `stale` (dynamic casters' bits, then static casters' from word constants.options.w) are bit
// arrays over entries; `order` the allocation order's runs (first rank, map, mip,
// entries: VirtualShadowMaps::allocationOrder); constants as uploaded (sizes.w = frame).
gpu::VsmCounters vsmAllocateReference(VsmAllocState& state, const std::vector<uint32_t>& marks,
                                      const std::vector<uint32_t>& stale,
                                      const std::vector<gpu::GpuVsmMap>& maps,
                                      const std::vector<glm::uvec4>& order,
                                      const gpu::VsmConstants& constants);

std::vector<gpu::GpuCasterGroup> vsmCasterGroupsReference(const std::vector<gpu::GpuCaster>& casters,
                                                          const std::vector<uint32_t>& order);

// Empty string when the state is consistent, else the first violation.
std::string vsmCheckInvariants(const VsmAllocState& state, const std::vector<uint32_t>& marks,
                               const std::vector<uint32_t>& active, const gpu::VsmConstants& constants,
                               const gpu::VsmCounters& counters);

} // namespace ml
