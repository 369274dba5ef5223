#version 460
#extension GL_GOOGLE_include_directive : require
// Footprint light assignment, pass C: the hits pass A recorded become the pool's lists, sorted by
// light index. Three steps (kSpecStep), each a fixed number of groups striding over the hits (their
// count is only known on the GPU), so only non-empty clusters cost anything:
//   0 scatter: after light_alloc, counts[c] is cluster c's list length; each hit (c, l) writes l at
//     ranges[c].x + (atomic decrement of counts[c]) - 1, so counts[c] ends at 0 and every slot of the
//     range is written once, in the atomics' order.
//   1 rank: each hit (c, l) of a cluster with two or more lights counts the lights of the (unsorted)
//     list smaller than l: that is l's place in the sorted list (the light indices of a cluster are
//     unique). The pool slot goes into the hit's first word (the cluster is no longer needed);
//     ML_CLUSTER_OVERFLOW where nothing moves (overflowed cluster, list of one). No private array, no
//     shared memory, no barrier: a loop of list-length reads per hit, the sum over clusters of
//     length^2 in all (at 4096 lights, 640x360: 0.27 M entries; docs/culling.md has the cost).
//   2 place: each ranked hit writes its light at its slot. A pass of its own because step 1 reads the
//     unsorted lists that this one overwrites.
// The result is the CPU reference's list (cullReference: sorted), independent of the atomics' order.
// Overflowed clusters are skipped (their pixels test every visible light).
#include "shaders/shared/glsl_common.glsl"
#include "culling/culling_push.h"

layout(local_size_x = ML_FILL_GROUP) in;
layout(constant_id = 0) const uint kSpecStep = 0;

layout(binding = 0, std430) buffer Hits { uvec2 hits[]; }; // (cluster, light); after step 1 (slot, light)
layout(binding = 1, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = 2, std430) buffer Counts { uint counts[]; };
layout(binding = 3, std430) buffer Pool { uint pool[]; };
layout(binding = 4, std430) readonly buffer Work { uint workTests; uint hitCount; };
layout(push_constant) uniform Push { CullPush push; };

void main() {
    uint n = min(hitCount, push.hitCapacity);
    for (uint i = gl_GlobalInvocationID.x; i < n; i += gl_NumWorkGroups.x * ML_FILL_GROUP) {
        uvec2 h = hits[i];
        if (kSpecStep == 2u) {
            if (h.x != ML_CLUSTER_OVERFLOW) pool[h.x] = h.y;
            continue;
        }
        uvec2 r = ranges[h.x];
        if (kSpecStep == 0u) {
            if (r.x != ML_CLUSTER_OVERFLOW) pool[r.x + atomicAdd(counts[h.x], 0xFFFFFFFFu) - 1u] = h.y;
        } else {
            uint slot = ML_CLUSTER_OVERFLOW;
            if (r.x != ML_CLUSTER_OVERFLOW && r.y > 1u) {
                uint rank = 0;
                for (uint j = 0; j < r.y; ++j) rank += pool[r.x + j] < h.y ? 1u : 0u;
                slot = r.x + rank;
            }
            hits[i].x = slot;
        }
    }
}
