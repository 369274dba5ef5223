#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_list (allocation 1/6), one thread: closes the request list vsm_mark appended to. Entries past the
// list's capacity (VsmConstants.order.z) were not stored: they are counted in listOverflow (reported in
// VsmStats::requestOverflow, never silent) and get no page this frame. Writes the indirect dispatch size
// of the passes that walk the list (vsm_sort, vsm_scan, vsm_assign, vsm_hpb): one group per
// ML_VSM_BLOCK entries, so their work follows the pages wanted, not the maps' virtual size; and of the
// passes that walk the pool (vsm_scan's first groups; vsm_avail's is vsm_alloc's): one group per ML_VSM_BLOCK
// owned pages, so a larger pool adds none.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = 1) in;

layout(binding = ML_VSM_LIST_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_LIST_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
// Word 0: which list buffer holds the sorted list (vsm_alloc_common.glsl's vsmListRank); word 1: 1 when
// vsm_allocate_short_list allocated in one workgroup, 2 when it sorted in the list buffers, else 0; word 2: its closed length; word 3 the owned
// pages, then the indirect dispatches (x, y, z) of the allocation and sort passes (vsm_types.h).
layout(binding = ML_VSM_LIST_SORT_ARGS, std430) writeonly buffer SortArgs { uint vsmSortArgs[]; };
layout(binding = ML_VSM_LIST_OWNERS, std430) readonly buffer Owner { uint vsmOwner[]; };
layout(push_constant) uniform Push { VsmSortPush push; }; // width: the number of merge passes

#define VSM_NO_RUNS
#define VSM_NO_MARKS
#define VSM_CLOSE_LIST
#include "shadows/virtual/vsm_alloc_common.glsl"

void main() {
    uint sorted;
    uint n = vsmCloseList(push.width, false, sorted);
    vsmSortArgs[2] = n;
    vsmSortArgs[0] = sorted;
    vsmSortArgs[1] = 0u; // not allocated by vsm_allocate_short_list
    vsmAllocArgs(n, vsmOwnedPages(), false);
}
