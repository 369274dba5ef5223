#version 460
#extension GL_GOOGLE_include_directive : require
// Footprint light assignment (clustered mode), passes A (count) and C (fill); light_alloc.comp is B.
// ML_FOOTPRINT_LANES threads per visible light, several lights per workgroup: the light's footprint (lightFootprint: screen rectangle of tiles and
// depth range, conservative, camera inside the volume included) selects tiles; within each tile only
// the occupied slices (the tile's 64-bit mask from cluster_bounds) inside the depth range are tested,
// with the same exact box test as the brute-force pass. So the work is the occupied clusters under
// each light's footprint, not every light times every occupied cluster.
//   kSpecFill = false: counts[c] += 1 per light touching cluster c; work.tests += box tests run.
//   kSpecFill = true:  after light_alloc set ranges and left counts[c] = list length, each light
//                      writes its index at ranges[c].x + (atomic decrement of counts[c]) - 1, so
//                      counts[c] ends at 0. Overflowed clusters are skipped (their pixels test every
//                      visible light in the evaluation pass).
#include "shaders/shared/glsl_common.h"
#include "shaders/shared/light_math.h"

layout(local_size_x = ML_FOOTPRINT_GROUP) in;
layout(constant_id = 0) const bool kSpecFill = false;

layout(binding = 0) uniform Frame { FrameConstants frame; };
layout(binding = 1, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = 2, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = 3, std430) readonly buffer Bounds { ClusterBounds bounds[]; };
layout(binding = 4, std430) readonly buffer TileMasks { uvec2 tileMasks[]; };
layout(binding = 5, std430) buffer Counts { uint counts[]; };
layout(binding = 6, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = 7, std430) writeonly buffer Pool { uint pool[]; };
layout(binding = 8, std430) buffer Work { uint workTests; };

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
    if (!kSpecFill) {
        if (li == 0) sTests = 0u;
        barrier();
    }
    GpuLight L = lights[min(l, frame.cluster.z - 1u)];
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
        for (uint word = 0; word < 2; ++word) {
            uint bits = m[word];
            while (bits != 0u) {
                uint s = word * 32u + uint(findLSB(bits));
                bits &= bits - 1u;
                uint c = tile * slices + s;
                ++tests;
                ClusterBounds b = bounds[c];
                if (!lightTouchesBox(L, b.lo.xyz, b.hi.xyz)) continue;
                if (!kSpecFill) {
                    atomicAdd(counts[c], 1u);
                } else {
                    uvec2 r = ranges[c];
                    if (r.x != ML_CLUSTER_OVERFLOW) pool[r.x + atomicAdd(counts[c], 0xFFFFFFFFu) - 1u] = l;
                }
            }
        }
    }
    if (!kSpecFill) {
        if (tests > 0u) atomicAdd(sTests, tests);
        barrier();
        if (li == 0 && sTests > 0u) atomicAdd(workTests, sTests);
    }
}
