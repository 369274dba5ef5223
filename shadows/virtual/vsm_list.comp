#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_list (allocation 1/7), one thread: closes the request list vsm_mark appended to. Entries past the
// list's capacity (VsmConstants.order.z) were not stored: they are counted in listOverflow (reported in
// VsmStats::requestOverflow, never silent) and get no page this frame. Writes the indirect dispatch size
// of the passes that walk the list (vsm_sort, vsm_scan, vsm_assign, vsm_hpb): one group per
// ML_VSM_BLOCK entries, so their work follows the pages wanted, not the maps' virtual size.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = 1) in;

layout(binding = ML_VSM_LIST_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_LIST_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
// Word 0: which list buffer holds the sorted list (vsm_alloc_common.glsl's vsmListRank); word 1: 1 when
// vsm_allocate_short_list allocated in one workgroup, else 0; word 2: its closed length; from word 4,
// per vsm_sort pass, its indirect dispatch (x, y, z).
layout(binding = ML_VSM_LIST_SORT_ARGS, std430) writeonly buffer SortArgs { uint vsmSortArgs[]; };
layout(push_constant) uniform Push { VsmSortPush push; }; // width: the number of merge passes

#define VSM_NO_RUNS
#define VSM_NO_MARKS
#define VSM_CLOSE_LIST
#include "shadows/virtual/vsm_alloc_common.glsl"

void main() {
    uint sorted;
    vsmSortArgs[2] = vsmCloseList(push.width, false, sorted);
    vsmSortArgs[0] = sorted;
    vsmSortArgs[1] = 0u; // not allocated by vsm_allocate_short_list
}
