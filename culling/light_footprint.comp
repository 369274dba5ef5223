#version 460
#extension GL_GOOGLE_include_directive : require
// Footprint light assignment (clustered mode), pass A: count and record the hits; light_alloc.comp
// (B) allocates, light_fill.comp (C) scatters the recorded hits into the pool.
// ML_FOOTPRINT_LANES threads per visible light, several lights per workgroup: the light's footprint
// (lightFootprint: screen rectangle of tiles and depth range, conservative, camera inside the volume
// included) selects tiles; within each tile only
// the occupied slices (the tile's 64-bit mask from cluster_bounds) inside the depth range are tested,
// with the same exact box test as the brute-force pass. So the work is the occupied clusters under
// each light's footprint, not every light times every occupied cluster.
// Per hit (light l touches cluster c): counts[c] += 1, and (c, l) is appended to `hits` (capacity
// hitCapacity; past it only hitCount grows, and light_alloc then overflows every non-empty cluster, so
// nothing is lost). Recording the hits spares pass C a second round of box tests.
#include "shaders/shared/glsl_common.glsl"
#include "culling/culling_push.h"
#include "shaders/shared/light_math.h"

layout(local_size_x = ML_FOOTPRINT_GROUP) in;
layout(push_constant) uniform Push { CullPush push; };

layout(binding = 0) uniform Frame { FrameConstants frame; };
layout(binding = 1, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = 2, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = 3, std430) readonly buffer Bounds { ClusterBounds bounds[]; };
layout(binding = 4, std430) readonly buffer TileMasks { uvec2 tileMasks[]; };
layout(binding = 5, std430) buffer Counts { uint counts[]; };
layout(binding = 6, std430) writeonly buffer Hits { uvec2 hits[]; }; // (cluster, light)
layout(binding = 7, std430) buffer Work { uint workTests; uint hitCount; };

shared uint sTests;

uint sliceOfDepth(float z, uint slices) {
    uint s = 0;
    while (s + 1 < slices && z >= sliceFar[s]) ++s;
    return s;
}

// Bits a..b (inclusive) of a 32-bit word; 0 when a > b.
uint bitsBetween(int a, int b) {
    if (a > b) return 0u;
    uint upTo = b >= 31 ? 0xFFFFFFFFu : ((1u << uint(b + 1)) - 1u);
    return upTo & ~((1u << uint(a)) - 1u);
}

void main() {
    uint li = gl_LocalInvocationIndex;
    uint l = gl_WorkGroupID.x * (ML_FOOTPRINT_GROUP / ML_FOOTPRINT_LANES) + li / ML_FOOTPRINT_LANES;
    uint lane = li % ML_FOOTPRINT_LANES;
    if (li == 0) sTests = 0u;
    barrier();
    GpuLight L = lights[min(l, frame.cluster.z - 1u)];
    ConePlanes planes = conePlanes(L);
    LightFootprint f = lightFootprint(L, frame.viewProj, frame.size, frame.cluster.y, frame.depth.x);
    uint slices = frame.cluster.x;
    int s0 = int(sliceOfDepth(f.depth.x, slices)), s1 = int(sliceOfDepth(f.depth.y, slices));
    uvec2 sliceMask = uvec2(bitsBetween(s0, min(s1, 31)), bitsBetween(max(s0, 32) - 32, s1 - 32));
    uint n = 0, w = 0;
    if (l < frame.cluster.z && f.tiles.x <= f.tiles.z && f.tiles.y <= f.tiles.w) {
        w = f.tiles.z - f.tiles.x + 1u;
        n = w * (f.tiles.w - f.tiles.y + 1u);
    }
    uint tests = 0;
    for (uint i = lane; i < n; i += ML_FOOTPRINT_LANES) {
        uint tile = (f.tiles.y + i / w) * frame.size.z + f.tiles.x + i % w;
        uvec2 m = tileMasks[tile] & sliceMask;
        // Test first, then reserve the tile's hits with one atomic on the shared hit counter.
        uvec2 hitMask = uvec2(0u);
        for (uint word = 0; word < 2; ++word) {
            uint bits = m[word];
            while (bits != 0u) {
                uint bit = uint(findLSB(bits));
                bits &= bits - 1u;
                ClusterBounds b = bounds[tile * slices + word * 32u + bit];
                ++tests;
                if (lightTouchesBoxWith(L, planes, b.lo.xyz, b.hi.xyz)) hitMask[word] |= 1u << bit;
            }
        }
        uint found = uint(bitCount(hitMask.x) + bitCount(hitMask.y));
        if (found == 0u) continue;
        uint h = atomicAdd(hitCount, found);
        for (uint word = 0; word < 2; ++word) {
            uint bits = hitMask[word];
            while (bits != 0u) {
                uint c = tile * slices + word * 32u + uint(findLSB(bits));
                bits &= bits - 1u;
                atomicAdd(counts[c], 1u);
                if (h < push.hitCapacity) hits[h] = uvec2(c, l);
                ++h;
            }
        }
    }
    if (tests > 0u) atomicAdd(sTests, tests);
    barrier();
    if (li == 0 && sTests > 0u) atomicAdd(workTests, sTests);
}
