#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_assign (allocation 3/3): per entry in priority order, one block per workgroup. A request of
// global rank r takes avail[r] (vsm_alloc), evicting that page's previous entry; past the list it is
// a fallback (counted; the lookup reads a coarser page). Every marked entry with a page that is not
// valid is then rendered this frame (and, under pressure, every reserved fallback page too): DIRTY |
// VALID, its physical page appended to the clear list (the clear pass's indirect dispatch size), and
// its map's mip flagged for the draw passes. Only wanted entries are written, and no wanted entry is
// ever evicted, so the writes do not race.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = 2, std430) buffer Table { uint vsmTable[]; };
layout(binding = 3, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = 4, std430) buffer Owner { uint vsmOwner[]; };
layout(binding = 5, std430) buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = 6, std430) readonly buffer BlockRanks { uint vsmBlockRanks[]; };
layout(binding = 7, std430) readonly buffer Avail { uint vsmAvail[]; };
layout(binding = 8, std430) writeonly buffer Rendered { uint vsmRendered[]; };
layout(binding = 9, std430) buffer MapMips { uint vsmDirtyMips[]; };
layout(binding = 10, std430) buffer Counters { VsmCounters vsmCounters; };

#include "shadows/virtual/vsm_alloc_common.glsl"

void main() {
    uint block = vsmBlockIndex();
    if (vsmPaddingBlock(block)) return; // uniform per workgroup: no barrier is left waiting
    uint entry, map, mip;
    bool inside = vsmEntryOfOrder(block * ML_VSM_BLOCK + gl_LocalInvocationIndex, vsm, entry, map, mip);
    bool wanted = inside && vsmWanted(entry);
    uint pt = wanted ? vsmTable[entry] : 0u;
    bool request = wanted && (pt & ML_VSM_ALLOCATED) == 0u;
    uint sum;
    uint rank = vsmBlockRanks[block] + vsmBlockScan(request ? 1u : 0u, sum);
    if (!wanted) return;
    bool marked = vsmMarked(entry);
    if (request) {
        if (rank < vsmCounters.available) {
            uint p = vsmAvail[rank];
            uint old = vsmOwner[p];
            if (old != ML_VSM_NO_OWNER) {
                vsmTable[old] = 0u;
                atomicAdd(vsmCounters.pagesEvicted, 1u);
            }
            vsmOwner[p] = entry;
            vsmLastUsed[p] = vsm.sizes.w;
            pt = ML_VSM_ALLOCATED | p;
        } else {
            atomicAdd(vsmCounters.fallbacks, 1u);
            return;
        }
    }
    if ((pt & ML_VSM_VALID) == 0u && (marked || vsmCounters.pressure != 0u)) {
        pt |= ML_VSM_VALID | ML_VSM_DIRTY;
        uint slot = atomicAdd(vsmCounters.dispatchX, 1u);
        vsmRendered[slot] = pt & ML_VSM_PHYS_MASK;
        atomicOr(vsmDirtyMips[map], 1u << mip);
        atomicAdd(vsmCounters.pagesRendered, 1u);
    } else if (marked && (pt & ML_VSM_VALID) != 0u) {
        atomicAdd(vsmCounters.pagesCached, 1u);
    }
    vsmTable[entry] = pt;
}
