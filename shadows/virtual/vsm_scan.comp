#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_scan (allocation 4/7): per entry of the sorted request list (indirect: vsm_list), one block of
// ML_VSM_BLOCK entries per workgroup. A wanted entry (marked, or reserved as a fallback) that has a
// physical page refreshes its last use (LRU); one without is a request, counted per block for
// vsm_alloc's prefix sum.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_SCAN_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_SCAN_RUNS, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = ML_VSM_SCAN_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_SCAN_LIST_A, std430) readonly buffer ListA { uint vsmListA[]; }; // vsm_sort's buffers: priority ranks
layout(binding = ML_VSM_SCAN_TABLE, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_SCAN_MARKS, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = ML_VSM_SCAN_LAST_USED, std430) buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = ML_VSM_SCAN_BLOCK_COUNTS, std430) writeonly buffer BlockCounts { uint vsmBlockCounts[]; };

layout(binding = ML_VSM_SCAN_LIST_B, std430) readonly buffer ListB { uint vsmListB[]; };
layout(binding = ML_VSM_SCAN_SORT_ARGS, std430) readonly buffer Sorted { uint vsmSortArgs[]; }; // vsm_list
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
