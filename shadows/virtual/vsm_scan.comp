#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_scan (allocation 1/3): per page-table entry of the scanned slots, in priority order, one block
// of ML_VSM_BLOCK entries per workgroup:
//   - clears last frame's DIRTY bit;
//   - invalidation: a page loses VALID when its light moved (map flag), when a moved caster's old or new
//     projected bounds overlap it (the CPU's stale bits, one per entry), or always with caching off;
//   - a wanted page (marked or reserved as fallback) that has a physical page refreshes its last use (LRU);
//     one without is a request,
//     counted per block for vsm_alloc's prefix sum.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = 2, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = 3, std430) readonly buffer Stale { uint vsmStale[]; };
layout(binding = 4, std430) buffer Table { uint vsmTable[]; };
layout(binding = 5, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = 6, std430) buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = 7, std430) writeonly buffer BlockCounts { uint vsmBlockCounts[]; };
layout(binding = 8, std430) buffer Counters { VsmCounters vsmCounters; };

#include "shadows/virtual/vsm_alloc_common.glsl"

void main() {
    uint block = vsmBlockIndex();
    if (vsmPaddingBlock(block)) return; // uniform per workgroup: no barrier is left waiting
    uint entry, map, mip;
    bool inside = vsmEntryOfOrder(block * ML_VSM_BLOCK + gl_LocalInvocationIndex, vsm, entry, map, mip);
    uint request = 0u;
    if (inside) {
        uint pt = vsmTable[entry];
        uint before = pt;
        pt &= ~ML_VSM_DIRTY;
        if ((pt & ML_VSM_VALID) != 0u) {
            bool stale = vsm.options.y == 0u || (vsmMaps[map].info.y & ML_VSM_MAP_INVALIDATE) != 0u ||
                         (vsmStale[entry >> 5u] & (1u << (entry & 31u))) != 0u;
            if (stale) {
                pt &= ~ML_VSM_VALID;
                atomicAdd(vsmCounters.pagesInvalidated, 1u);
            }
        }
        if (vsmWanted(entry)) {
            if (vsmMarked(entry)) atomicAdd(vsmCounters.pagesMarked, 1u);
            if ((pt & ML_VSM_ALLOCATED) != 0u) vsmLastUsed[pt & ML_VSM_PHYS_MASK] = vsm.sizes.w;
            else request = 1u;
        }
        if (pt != before) vsmTable[entry] = pt;
    }
    uint sum;
    vsmBlockScan(request, sum);
    if (gl_LocalInvocationIndex == 0u) vsmBlockCounts[block] = sum;
}
