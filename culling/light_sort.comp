#version 460
#extension GL_GOOGLE_include_directive : require
// Footprint light assignment, pass D: sorts each cluster list light_fill (C) scattered in the atomics'
// order, so lists come out sorted by light index, equal to the CPU reference's (cullReference) and the
// same every frame. One group per tile that light_alloc (B) listed (a tile with a list of two or more
// lights that did not overflow; dispatched indirectly, so empty tiles and single-light lists cost
// nothing). Per such cluster of the tile (its lists are consecutive in the pool), a rank sort: the
// list is copied into shared memory, and each entry's place is the number of entries smaller than it
// (a cluster's light indices are unique, so ranks are distinct and the result deterministic).
// n^2 / ML_SORT_GROUP compares per list of n, each on a subgroup-uniform shared address; no private
// array (lavapipe puts dynamically indexed private arrays in scratch memory: an insertion sort per
// cluster in one made assignment 4-7x slower, docs/culling.md). Writes go from shared memory to the
// pool, so no entry is overwritten before it was read.
#include "shaders/shared/glsl_common.glsl"
#include "culling/culling_push.h"

layout(local_size_x = ML_SORT_GROUP) in;

layout(binding = 0) uniform Frame { FrameConstants frame; };
layout(binding = 1, std430) readonly buffer TileMasks { uvec2 tileMasks[]; };
layout(binding = 2, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = 3, std430) buffer Pool { uint pool[]; };
layout(binding = 4, std430) readonly buffer SortTiles { SortList sort; uint sortTiles[]; };

// A list holds at most the visible lights (ML_MAX_LIGHTS): 16 KiB, Vulkan's minimum
// maxComputeSharedMemorySize.
shared uint sList[ML_MAX_LIGHTS];

void main() {
    uint li = gl_LocalInvocationIndex;
    uint tile = sortTiles[gl_WorkGroupID.x];
    uint slices = frame.cluster.x;
    uvec2 mask = tileMasks[tile];
    for (uint w = 0; w < 2; ++w) {
        uint bits = mask[w];
        while (bits != 0u) {
            uint s = w * 32u + uint(findLSB(bits));
            bits &= bits - 1u;
            uvec2 r = ranges[tile * slices + s]; // the same for the whole group: barriers stay uniform
            if (r.x == ML_CLUSTER_OVERFLOW || r.y < 2u) continue;
            for (uint j = li; j < r.y; j += ML_SORT_GROUP) sList[j] = pool[r.x + j];
            barrier();
            for (uint j = li; j < r.y; j += ML_SORT_GROUP) {
                uint v = sList[j], rank = 0;
                for (uint k = 0; k < r.y; ++k) rank += sList[k] < v ? 1u : 0u;
                pool[r.x + rank] = v;
            }
            barrier(); // the next list reuses sList
        }
    }
}
