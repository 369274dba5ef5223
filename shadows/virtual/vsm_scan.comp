#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_scan (allocation 4/7): per entry of the sorted request list (indirect: vsm_list), one block of
// ML_VSM_BLOCK entries per workgroup. A wanted entry (marked, or reserved as a fallback) that has a
// physical page refreshes its last use (LRU); one without is a request, counted per block for
// vsm_alloc's prefix sum.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = 2, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = 3, std430) readonly buffer ListA { uint vsmListA[]; }; // vsm_sort's buffers: priority ranks
layout(binding = 4, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = 5, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = 6, std430) buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = 7, std430) writeonly buffer BlockCounts { uint vsmBlockCounts[]; };

layout(binding = 8, std430) readonly buffer ListB { uint vsmListB[]; };
layout(binding = 9, std430) readonly buffer Sorted { uint vsmSortArgs[]; }; // vsm_list
#define vsmSorted vsmSortArgs[0]
#define VSM_LISTS
#include "shadows/virtual/vsm_alloc_common.glsl"

void main() {
    uint request = 0u, entry, map, mip;
    if (gl_GlobalInvocationID.x < vsmCounters.listCount &&
        vsmEntryOfOrder(vsmListRank(gl_GlobalInvocationID.x), vsm, entry, map, mip)) {
        uint pt = vsmTable[entry];
        if (vsmMarked(entry)) atomicAdd(vsmCounters.pagesMarked, 1u);
        if ((pt & ML_VSM_ALLOCATED) != 0u) vsmLastUsed[pt & ML_VSM_PHYS_MASK] = vsm.sizes.w;
        else request = 1u;
    }
    uint sum;
    vsmBlockScan(request, sum);
    if (gl_LocalInvocationIndex == 0u) vsmBlockCounts[gl_WorkGroupID.x] = sum;
}
