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

void main() {
    uint n = vsmCounters.listCount;
    uint capacity = vsm.order.z;
    if (n > capacity) {
        vsmCounters.listOverflow = n - capacity;
        n = capacity;
        vsmCounters.listCount = n;
    }
    vsmCounters.listGroupsX = (n + ML_VSM_BLOCK - 1u) / ML_VSM_BLOCK;
    vsmCounters.listGroupsY = 1u;
    vsmCounters.listGroupsZ = 1u;
}
