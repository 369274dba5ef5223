#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_list (allocation 1/7), one thread: closes the request list vsm_mark appended to. Entries past the
// list's capacity (VsmConstants.order.z) were not stored: they are counted in listOverflow (reported in
// VsmStats::requestOverflow, never silent) and get no page this frame. Writes the indirect dispatch size
// of the passes that walk the list (vsm_sort, vsm_scan, vsm_assign, vsm_hpb): one group per
// ML_VSM_BLOCK entries, so their work follows the pages wanted, not the maps' virtual size.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"

layout(local_size_x = 1) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) buffer Counters { VsmCounters vsmCounters; };
// Word 0: which list buffer holds the sorted list (vsm_alloc_common.glsl's vsmListRank); from word 4,
// per vsm_sort pass, its indirect dispatch (x, y, z).
layout(binding = 2, std430) writeonly buffer SortArgs { uint vsmSortArgs[]; };
layout(push_constant) uniform Push { VsmSortPush push; }; // width: the number of merge passes

void main() {
    uint n = vsmCounters.listCount;
    uint capacity = vsm.order.z;
    if (n > capacity) {
        vsmCounters.listOverflow = n - capacity;
        n = capacity;
        vsmCounters.listCount = n;
    }
    uint groups = (n + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    vsmCounters.listGroupsX = groups;
    vsmCounters.listGroupsY = 1u;
    vsmCounters.listGroupsZ = 1u;
    // The block sort always runs; a merge of runs of width w only while w < n (otherwise its dispatch is
    // empty), so the passes run follow the list's length: log2(n / ML_VSM_BLOCK), not the capacity's.
    uint run = 1u;
    for (uint pass = 0u; pass <= push.width; ++pass) {
        bool needed = pass == 0u || (uint(ML_VSM_BLOCK) << (pass - 1u)) < n;
        vsmSortArgs[4u + 3u * pass] = needed ? groups : 0u;
        vsmSortArgs[4u + 3u * pass + 1u] = 1u;
        vsmSortArgs[4u + 3u * pass + 2u] = 1u;
        if (needed && pass > 0u) ++run;
    }
    vsmSortArgs[0] = run % 2u; // pass p writes list[(p + 1) % 2]
}
