#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_assign (allocation 6/6): per entry of the sorted request list (indirect), one block per workgroup.
// A request of global rank r takes the r-th available page (a free one past the owned prefix, else
// avail[r]: vsm_alloc, vsm_avail), evicting that page's previous entry;
// past the list it is a fallback (counted; the lookup reads a coarser page). Every marked entry with a
// page that is not valid is then rendered this frame (and, under pressure, every reserved fallback page
// too): DIRTY | VALID, its physical page appended to the clear list (the clear pass's indirect dispatch
// size), and its map's mip flagged for the draw passes. With the static layer, a page whose static twin
// is still valid is listed to be redrawn from it (ML_VSM_RENDER_FROM_STATIC), else the twin is rendered
// too (STATIC_VALID | DIRTY_STATIC). Only wanted entries are written, and no wanted
// entry is ever evicted, so the writes do not race.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_BLOCK) in;

layout(binding = ML_VSM_ASSIGN_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_ASSIGN_RUNS, std430) readonly buffer Runs { uvec4 vsmRuns[]; };
layout(binding = ML_VSM_ASSIGN_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_ASSIGN_LIST_A, std430) readonly buffer ListA { uint vsmListA[]; }; // vsm_sort's buffers: priority ranks
layout(binding = ML_VSM_ASSIGN_TABLE, std430) buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_ASSIGN_MARKS, std430) readonly buffer Marks { uint vsmMarks[]; };
layout(binding = ML_VSM_ASSIGN_OWNERS, std430) buffer Owner { uint vsmOwner[]; };
layout(binding = ML_VSM_ASSIGN_LAST_USED, std430) buffer LastUsed { uint vsmLastUsed[]; };
layout(binding = ML_VSM_ASSIGN_BLOCK_RANKS, std430) readonly buffer BlockRanks { uint vsmBlockRanks[]; };
layout(binding = ML_VSM_ASSIGN_AVAIL, std430) readonly buffer Avail { uint vsmAvail[]; };
layout(binding = ML_VSM_ASSIGN_RENDERED, std430) writeonly buffer Rendered { uint vsmRendered[]; };
layout(binding = ML_VSM_ASSIGN_DIRTY_MIPS, std430) buffer MapMips { uint vsmDirtyMips[]; };
layout(binding = ML_VSM_ASSIGN_DIRTY_MAPS, std430) writeonly buffer DirtyMaps { uint vsmDirtyMaps[]; };

layout(binding = ML_VSM_ASSIGN_LIST_B, std430) readonly buffer ListB { uint vsmListB[]; };
layout(binding = ML_VSM_ASSIGN_SORT_ARGS, std430) readonly buffer Sorted { uint vsmSortArgs[]; }; // vsm_list
#define vsmSorted vsmSortArgs[0]
#define VSM_LISTS
#define VSM_ASSIGN
#include "shadows/virtual/vsm_alloc_common.glsl"

void main() {
    uint entry, map, mip;
    bool wanted = gl_GlobalInvocationID.x < vsmCounters.listCount &&
                  vsmEntryOfOrder(vsmListRank(gl_GlobalInvocationID.x), vsm, entry, map, mip);
    uint pt = wanted ? vsmTable[entry] : 0u;
    bool request = wanted && (pt & ML_VSM_ALLOCATED) == 0u;
    uint sum;
    uint rank = vsmBlockRanks[gl_WorkGroupID.x] + vsmBlockScan(request ? 1u : 0u, sum);
    if (wanted)
        vsmAssignEntry(entry, map, mip, pt, request, rank, vsmCounters.available, vsmCounters.pressure != 0u,
                       vsmSortArgs[ML_VSM_ARGS_OWNED]);
}
