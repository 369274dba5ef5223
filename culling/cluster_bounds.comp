#version 460
#extension GL_GOOGLE_include_directive : require
// Cluster bounds: one workgroup per screen tile (ML_TILE_SIZE^2 pixels). Each pixel with geometry is
// put in its depth slice, and the world-space AABB of the pixels in each (tile, slice) is reduced
// with shared-memory atomics on order-preserving integer encodings of the floats (min/max are exact
// and order-independent, so the result equals the CPU reference bit for bit). Also writes the tile's
// occupancy as a 64-bit mask (bit s: slice s holds a pixel), which the footprint assignment walks.
// The receiver variant (kReceivers = 1, for page marking per cluster) also reduces, per cluster, the
// world AABB of the receivers only and a box over their unit normals (shaders/shared/
// cluster_receivers.h): 12 more shared atomics per receiver pixel and one normal read per pixel.
// CPU twins: cullReference (bounds, masks) and cullReceiversReference (receivers), culling/culling.cpp.
#include "shaders/shared/glsl_common.glsl"
#include "shaders/shared/light_math.h"
#include "shaders/shared/cluster_receivers.h"
#include "culling/culling_bindings.h"

layout(constant_id = 0) const uint kReceivers = 0u;

layout(local_size_x = ML_TILE_SIZE, local_size_y = ML_TILE_SIZE) in;

layout(binding = ML_BOUNDS_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_BOUNDS_SLICES, std430) readonly buffer Slices { float sliceFar[]; }; // slice s ends at sliceFar[s]
#include "shaders/shared/cluster_slice.glsl"
layout(binding = ML_BOUNDS_DEPTH) uniform texture2D depthImage;
layout(binding = ML_BOUNDS_OUT, std430) writeonly buffer Bounds { ClusterBounds bounds[]; };
layout(binding = ML_BOUNDS_COUNTERS, std430) buffer Counters { FrameCounters counters; };
layout(binding = ML_BOUNDS_TILE_MASKS, std430) writeonly buffer TileMasks { uvec2 tileMasks[]; }; // slices 0-31, 32-63
layout(binding = ML_BOUNDS_NORMAL) uniform texture2D normalImage; // G-buffer normal (w < 0: not a receiver)
layout(binding = ML_BOUNDS_RECEIVERS, std430) writeonly buffer Receivers { ClusterReceivers receivers[]; };

shared uint sMask[2];
shared uint sLo[3][ML_MAX_SLICES];
shared uint sHi[3][ML_MAX_SLICES];
// Receiver variant: the receivers' world box (keys) and normal codes (clusterNormalCode), per slice.
shared uint sRLo[3][ML_MAX_SLICES];
shared uint sRHi[3][ML_MAX_SLICES];
shared uint sNLo[3][ML_MAX_SLICES];
shared uint sNHi[3][ML_MAX_SLICES];

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
        if (kReceivers != 0u)
            for (int c = 0; c < 3; ++c) {
                sRLo[c][s] = 0xFFFFFFFFu;
                sRHi[c][s] = 0u;
                sNLo[c][s] = 1023u;
                sNHi[c][s] = 0u;
            }
    }
    barrier();

    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x < frame.size.x && px.y < frame.size.y) {
        float d = texelFetch(depthImage, ivec2(px), 0).r;
        if (hasSurface(d)) {
            vec3 p = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
            float z = linearDepth(d, frame.depth);
            uint s = clusterSlice(z);
            bool receiver = false;
            vec4 stored = vec4(0.0);
            if (kReceivers != 0u) {
                stored = texelFetch(normalImage, ivec2(px), 0);
                receiver = !(stored.w < 0.0); // as vsm_mark: ML_NOT_A_RECEIVER is -1
            }
            if (!receiver) {
                for (int c = 0; c < 3; ++c) {
                    atomicMin(sLo[c][s], toKey(p[c]));
                    atomicMax(sHi[c][s], toKey(p[c]));
                }
            } else {
                // A receiver's point goes to the receivers' box only (the cluster's box is the union of
                // both, at the end), and each atomic is skipped when the value already read bounds the
                // pixel's: the shared value only moves towards it, so a skipped atomic would have changed
                // nothing. Most pixels of a cluster share its normal, so most of these are skipped; with
                // 12 unconditional atomics the variant cost 1.8x the plain pass on lavapipe (90 against
                // 51 ms at 640x360, night city).
                vec3 n = clusterUnitNormal(stored.xyz);
                for (int c = 0; c < 3; ++c) {
                    uint k = toKey(p[c]);
                    if (k < sRLo[c][s]) atomicMin(sRLo[c][s], k);
                    if (k > sRHi[c][s]) atomicMax(sRHi[c][s], k);
                    uint lo = clusterNormalCode(n[c], false), hi = clusterNormalCode(n[c], true);
                    if (lo < sNLo[c][s]) atomicMin(sNLo[c][s], lo);
                    if (hi > sNHi[c][s]) atomicMax(sNHi[c][s], hi);
                }
            }
        }
    }
    barrier();

    uint tile = gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x;
    for (uint s = li; s < slices; s += ML_TILE_SIZE * ML_TILE_SIZE) {
        if (kReceivers != 0u)
            for (int c = 0; c < 3; ++c) { // the cluster's box: non-receivers' and receivers' boxes
                sLo[c][s] = min(sLo[c][s], sRLo[c][s]);
                sHi[c][s] = max(sHi[c][s], sRHi[c][s]);
            }
        ClusterBounds b;
        bool occupied = sLo[0][s] != 0xFFFFFFFFu;
        b.lo = vec4(fromKey(sLo[0][s]), fromKey(sLo[1][s]), fromKey(sLo[2][s]), occupied ? 1.0 : 0.0);
        b.hi = vec4(fromKey(sHi[0][s]), fromKey(sHi[1][s]), fromKey(sHi[2][s]), 0.0);
        if (!occupied) { b.lo.xyz = vec3(0.0); b.hi.xyz = vec3(0.0); }
        bounds[tile * slices + s] = b;
        // Only occupied clusters' receivers are read (vsm_mark_cluster walks the tile mask).
        if (kReceivers != 0u && occupied) {
            ClusterReceivers r;
            r.lo = vec3(0.0);
            r.hi = vec3(0.0);
            r.normalLo = 0u;
            r.normalHi = 0u;
            if (sRLo[0][s] != 0xFFFFFFFFu) {
                r.lo = vec3(fromKey(sRLo[0][s]), fromKey(sRLo[1][s]), fromKey(sRLo[2][s]));
                r.hi = vec3(fromKey(sRHi[0][s]), fromKey(sRHi[1][s]), fromKey(sRHi[2][s]));
                r.normalLo = sNLo[0][s] | (sNLo[1][s] << 10u) | (sNLo[2][s] << 20u);
                r.normalHi = sNHi[0][s] | (sNHi[1][s] << 10u) | (sNHi[2][s] << 20u) | ML_CLUSTER_HAS_RECEIVER;
            }
            receivers[tile * slices + s] = r;
        }
        if (occupied) {
            atomicAdd(counters.occupiedClusters, 1u);
            atomicOr(sMask[s >> 5], 1u << (s & 31u));
        }
    }
    barrier();
    if (li == 0) tileMasks[tile] = uvec2(sMask[0], sMask[1]);
}
