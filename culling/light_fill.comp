#version 460
#extension GL_GOOGLE_include_directive : require
// Footprint light assignment, pass C: scatters the hits pass A recorded into the pool. After
// light_alloc, counts[c] is cluster c's list length; each hit (c, l) writes l at
// ranges[c].x + (atomic decrement of counts[c]) - 1, so counts[c] ends at 0 and every slot of the range
// is written once, in the atomics' order (light_sort.comp, pass D, then sorts each list). Overflowed
// clusters are skipped (their pixels test every visible light). A fixed number of groups strides over
// the hits (their count is only known on the GPU).
#include "shaders/shared/glsl_common.glsl"
#include "culling/culling_push.h"

layout(local_size_x = ML_FILL_GROUP) in;

layout(binding = 0, std430) readonly buffer Hits { uvec2 hits[]; };
layout(binding = 1, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = 2, std430) buffer Counts { uint counts[]; };
layout(binding = 3, std430) writeonly buffer Pool { uint pool[]; };
layout(binding = 4, std430) readonly buffer Work { uint workTests; uint hitCount; };
layout(push_constant) uniform Push { CullPush push; };

void main() {
    uint n = min(hitCount, push.hitCapacity);
    for (uint i = gl_GlobalInvocationID.x; i < n; i += gl_NumWorkGroups.x * ML_FILL_GROUP) {
        uvec2 h = hits[i];
        uvec2 r = ranges[h.x];
        if (r.x != ML_CLUSTER_OVERFLOW) pool[r.x + atomicAdd(counts[h.x], 0xFFFFFFFFu) - 1u] = h.y;
    }
}
