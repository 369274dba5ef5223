#version 460
#extension GL_GOOGLE_include_directive : require
// Cluster bounds: one workgroup per screen tile (ML_TILE_SIZE^2 pixels). Each pixel with geometry is
// put in its depth slice, and the world-space AABB of the pixels in each (tile, slice) is reduced
// with shared-memory atomics on order-preserving integer encodings of the floats (min/max are exact
// and order-independent, so the result equals the CPU reference bit for bit). Also writes the tile's
// occupancy as a 64-bit mask (bit s: slice s holds a pixel), which the footprint assignment walks.
#include "shaders/shared/glsl_common.glsl"
#include "shaders/shared/light_math.h"

layout(local_size_x = ML_TILE_SIZE, local_size_y = ML_TILE_SIZE) in;

layout(binding = 0) uniform Frame { FrameConstants frame; };
layout(binding = 1, std430) readonly buffer Slices { float sliceFar[]; }; // slice s ends at sliceFar[s]
#include "shaders/shared/cluster_slice.glsl"
layout(binding = 2) uniform texture2D depthImage;
layout(binding = 3, std430) writeonly buffer Bounds { ClusterBounds bounds[]; };
layout(binding = 4, std430) buffer Counters { FrameCounters counters; };
layout(binding = 5, std430) writeonly buffer TileMasks { uvec2 tileMasks[]; }; // slices 0-31, 32-63

shared uint sMask[2];
shared uint sLo[3][ML_MAX_SLICES];
shared uint sHi[3][ML_MAX_SLICES];

// Monotonic float <-> uint mapping: a < b as floats iff key(a) < key(b) as uints.
uint toKey(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
}
float fromKey(uint k) {
    return uintBitsToFloat((k & 0x80000000u) != 0u ? (k & 0x7fffffffu) : ~k);
}

void main() {
    uint slices = frame.cluster.x;
    uint li = gl_LocalInvocationIndex;
    if (li < 2) sMask[li] = 0u;
    for (uint s = li; s < slices; s += ML_TILE_SIZE * ML_TILE_SIZE) {
        for (int c = 0; c < 3; ++c) { sLo[c][s] = 0xFFFFFFFFu; sHi[c][s] = 0u; }
    }
    barrier();

    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x < frame.size.x && px.y < frame.size.y) {
        float d = texelFetch(depthImage, ivec2(px), 0).r;
        if (hasSurface(d)) {
            vec3 p = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
            float z = linearDepth(d, frame.depth);
            uint s = clusterSlice(z);
            for (int c = 0; c < 3; ++c) {
                atomicMin(sLo[c][s], toKey(p[c]));
                atomicMax(sHi[c][s], toKey(p[c]));
            }
        }
    }
    barrier();

    uint tile = gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x;
    for (uint s = li; s < slices; s += ML_TILE_SIZE * ML_TILE_SIZE) {
        ClusterBounds b;
        bool occupied = sLo[0][s] != 0xFFFFFFFFu;
        b.lo = vec4(fromKey(sLo[0][s]), fromKey(sLo[1][s]), fromKey(sLo[2][s]), occupied ? 1.0 : 0.0);
        b.hi = vec4(fromKey(sHi[0][s]), fromKey(sHi[1][s]), fromKey(sHi[2][s]), 0.0);
        if (!occupied) { b.lo.xyz = vec3(0.0); b.hi.xyz = vec3(0.0); }
        bounds[tile * slices + s] = b;
        if (occupied) {
            atomicAdd(counters.occupiedClusters, 1u);
            atomicOr(sMask[s >> 5], 1u << (s & 31u));
        }
    }
    barrier();
    if (li == 0) tileMasks[tile] = uvec2(sMask[0], sMask[1]);
}
