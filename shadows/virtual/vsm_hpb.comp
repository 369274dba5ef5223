#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_hpb: the hierarchical page buffer (layout in vsm_math.h: bits, VsmConstants.order.w words per map
// slot, cleared for the maps in use at the frame's start). One thread per entry of the sorted request
// list (indirect: only pages rendered this frame are DIRTY, and they are all wanted): a DIRTY entry sets
// the bit of every HPB cell above it, level 1 (2x2 pages) to the mip's last level (one cell). vsm_cull,
// vsm_expand and the task shader then test at most 2x2 cells per caster or meshlet.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_HPB_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_HPB_RUNS, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = ML_VSM_HPB_COUNTERS, std430) readonly buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_HPB_LIST_A, std430) readonly buffer ListA { uint vsmListA[]; }; // vsm_sort's buffers: priority ranks
layout(binding = ML_VSM_HPB_TABLE, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_HPB_MARKS, std430) readonly buffer Marks { uint vsmMarks[]; }; // (vsm_alloc_common.glsl)
layout(binding = ML_VSM_HPB_HPB, std430) buffer Hpb { uint vsmHpb[]; };

layout(binding = ML_VSM_HPB_LIST_B, std430) readonly buffer ListB { uint vsmListB[]; };
layout(binding = ML_VSM_HPB_SORT_ARGS, std430) readonly buffer Sorted { uint vsmSortArgs[]; }; // vsm_list
#define vsmSorted vsmSortArgs[0]
#define VSM_LISTS
#define VSM_HPB
#include "shadows/virtual/vsm_alloc_common.glsl"

void main() {
    uint entry, map, mip;
    if (gl_GlobalInvocationID.x >= vsmCounters.listCount ||
        !vsmEntryOfOrder(vsmListRank(gl_GlobalInvocationID.x), vsm, entry, map, mip))
        return;
    vsmHpbMarkEntry(entry, map, mip);
}
