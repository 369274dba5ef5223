#version 460
#extension GL_GOOGLE_include_directive : require
// Brute-force light assignment (modes clustered-brute and tiled): one workgroup per screen tile. The tile's occupied clusters (from cluster_bounds)
// are loaded into shared memory; each thread takes one visible light at a time and tests it against
// every occupied cluster (range sphere exact, spot cone against the cluster's bounding sphere).
// Pass A counts, the group allocates each cluster's list from the global pool with one atomic, and
// pass B writes the indices sorted by light index: the lights go in chunks of ML_ASSIGN_GROUP (thread
// li takes light chunk + li), each thread sets bit li of a 64-bit mask per cluster its light touches,
// and a light's place in a cluster's list is the lights before the chunk plus the set bits below li:
// deterministic, no atomics on the order, two barriers per chunk (the masks and counts are double
// buffered by chunk parity, so clearing one overlaps reading the other). A cluster whose list does
// not fit is marked ML_CLUSTER_OVERFLOW and counted; its pixels then test every visible light, so no
// light is ever dropped.
#include "shaders/shared/glsl_common.glsl"
#include "shaders/shared/light_math.h"
#include "culling/culling_bindings.h"

layout(local_size_x = ML_ASSIGN_GROUP) in;

layout(binding = ML_ASSIGN_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_ASSIGN_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_ASSIGN_BOUNDS, std430) readonly buffer Bounds { ClusterBounds bounds[]; };
layout(binding = ML_ASSIGN_RANGES, std430) writeonly buffer Ranges { uvec2 ranges[]; }; // (offset, count) per cluster
layout(binding = ML_ASSIGN_POOL, std430) writeonly buffer Pool { uint pool[]; };
layout(binding = ML_ASSIGN_COUNTERS, std430) buffer Counters { FrameCounters counters; };
layout(binding = ML_ASSIGN_WORK, std430) buffer Work { uint workTests; }; // box tests run (bench's "clusters touched")

shared vec3 sLo[ML_MAX_SLICES];
shared vec3 sHi[ML_MAX_SLICES];
shared uint sOccupied[ML_MAX_SLICES]; // compacted list of occupied slice indices
shared uint sOccupiedCount;
shared uint sCount[ML_MAX_SLICES];
shared uint sOffset[ML_MAX_SLICES];
// Pass B, by chunk parity p: sMask[p][s] (two words: threads 0-31, 32-63) are the chunk's lights that
// touch slice s; sBefore[p][s] the lights of slice s in the earlier chunks.
shared uvec2 sMask[2][ML_MAX_SLICES];
shared uint sBefore[2][ML_MAX_SLICES];

#if ML_ASSIGN_GROUP != 64
#error "pass B's masks hold one bit per thread of the group: 64"
#endif

void main() {
    uint slices = frame.cluster.x;
    uint tile = gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x;
    uint li = gl_LocalInvocationIndex;
    uint lightCount = frame.cluster.z;

    if (li == 0) {
        uint n = 0;
        for (uint s = 0; s < slices; ++s) {
            ClusterBounds b = bounds[tile * slices + s];
            if (b.lo.w != 0.0) { sOccupied[n] = s; sLo[s] = b.lo.xyz; sHi[s] = b.hi.xyz; ++n; }
            sCount[s] = 0;
        }
        sOccupiedCount = n;
        if (n > 0) atomicAdd(workTests, n * lightCount);
    }
    barrier();
    uint occupied = sOccupiedCount;

    // Pass A: count.
    for (uint l = li; l < lightCount; l += ML_ASSIGN_GROUP) {
        GpuLight L = lights[l];
        ConePlanes planes = conePlanes(L);
        for (uint i = 0; i < occupied; ++i) {
            uint s = sOccupied[i];
            if (lightTouchesBoxWith(L, planes, sLo[s], sHi[s])) atomicAdd(sCount[s], 1u);
        }
    }
    barrier();

    // Allocate: one thread per slice.
    for (uint s = li; s < slices; s += ML_ASSIGN_GROUP) {
        uint count = sCount[s];
        uint offset = 0;
        if (count > 0) {
            offset = atomicAdd(counters.poolCursor, count);
            if (offset + count > frame.limits.x) {
                offset = ML_CLUSTER_OVERFLOW;
                atomicAdd(counters.overflowClusters, 1u);
            }
            atomicAdd(counters.clusterLightsSum, uint64_t(count));
            atomicMax(counters.maxClusterLights, count);
        }
        sOffset[s] = offset;
        ranges[tile * slices + s] = uvec2(offset, count);
        sMask[0][s] = uvec2(0u); // pass B's first chunk
        sBefore[0][s] = 0u;
    }
    barrier();

    // Pass B: write, in light order (see the top).
    uint word = li >> 5u, bit = 1u << (li & 31u);
    uint below = bit - 1u; // this thread's lower lanes in its word
    for (uint chunk = 0; chunk < lightCount; chunk += ML_ASSIGN_GROUP) {
        uint p = (chunk / ML_ASSIGN_GROUP) & 1u;
        uint l = chunk + li;
        uvec2 touched = uvec2(0u); // bit s: this thread's light touches occupied slice s
        if (l < lightCount) {
            GpuLight L = lights[l];
            ConePlanes planes = conePlanes(L);
            for (uint i = 0; i < occupied; ++i) {
                uint s = sOccupied[i];
                if (sOffset[s] != ML_CLUSTER_OVERFLOW && lightTouchesBoxWith(L, planes, sLo[s], sHi[s])) {
                    touched[s >> 5u] |= 1u << (s & 31u);
                    if (word == 0u) atomicOr(sMask[p][s].x, bit);
                    else atomicOr(sMask[p][s].y, bit);
                }
            }
        }
        barrier(); // this chunk's masks complete
        for (uint w = 0; w < 2; ++w) {
            uint bits = touched[w];
            while (bits != 0u) {
                uint s = w * 32u + uint(findLSB(bits));
                bits &= bits - 1u;
                uvec2 m = sMask[p][s];
                uint rank = word == 0u ? uint(bitCount(m.x & below))
                                       : uint(bitCount(m.x) + bitCount(m.y & below));
                pool[sOffset[s] + sBefore[p][s] + rank] = l;
            }
        }
        // The other parity's mask was last read in the previous chunk (before this chunk's barrier).
        for (uint s = li; s < slices; s += ML_ASSIGN_GROUP) {
            uvec2 m = sMask[p][s];
            sBefore[p ^ 1u][s] = sBefore[p][s] + uint(bitCount(m.x) + bitCount(m.y));
            sMask[p ^ 1u][s] = uvec2(0u);
        }
        barrier(); // the next chunk's mask cleared and its counts written
    }
}
