#version 460
#extension GL_GOOGLE_include_directive : require
// Cluster bounds: one workgroup per screen tile (ML_TILE_SIZE^2 pixels). Each pixel with geometry is
// put in its depth slice, and the world-space AABB of the pixels in each (tile, slice) is reduced with
// min / max on order-preserving integer encodings of the floats (exact and order-independent, so the
// result equals the CPU reference bit for bit). Also writes the tile's occupancy as a 64-bit mask (bit
// s: slice s holds a pixel), which the footprint assignment walks.
// The receiver variant (kReceivers = 1, for page marking per cluster) also reduces, per cluster, the
// world AABB of the receivers only and a box over their unit normals (shaders/shared/
// cluster_receivers.h), with one more read per pixel (the normal).
// Two builds of this source (culling/culling.cpp picks one):
// - the wave build (ML_WAVE_REDUCE; where the device has subgroup arithmetic in compute and no subgroup
//   under ML_TILE_SIZE lanes): one subgroup per tile, a lane per pixel column, with no shared memory, no
//   barrier and one atomic per tile. The lanes visit the tile's occupied slices in increasing order (the
//   subgroupMin of each lane's next slice), reduce each slice's values over their own rows and then over
//   the subgroup, and one lane writes the cluster. On lavapipe it takes about a third of the time of
//   the per-lane build (docs/virtual-shadow-maps.md, "Receiver bounds and normal bounds"), whose
//   shared memory at per-lane addresses and barriers were most of the pass;
// - the per-lane build (the fallback): a thread per pixel, shared-memory atomics per (tile, slice).
// CPU twins: cullReference (bounds, masks) and cullReceiversReference (receivers), culling/culling.cpp.
#ifdef ML_WAVE_REDUCE
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_control_flow_attributes : require
#endif
#include "shaders/shared/glsl_common.glsl"
#include "shaders/shared/light_math.h"
#include "shaders/shared/cluster_receivers.h"
#include "culling/culling_bindings.h"

layout(constant_id = 0) const uint kReceivers = 0u;

#ifdef ML_WAVE_REDUCE
layout(local_size_x = ML_TILE_SIZE) in; // one subgroup: a lane per column of the tile
#else
layout(local_size_x = ML_TILE_SIZE, local_size_y = ML_TILE_SIZE) in;
#endif

layout(binding = ML_BOUNDS_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_BOUNDS_SLICES, std430) readonly buffer Slices { float sliceFar[]; }; // slice s ends at sliceFar[s]
#include "shaders/shared/cluster_slice.glsl"
layout(binding = ML_BOUNDS_DEPTH) uniform texture2D depthImage;
layout(binding = ML_BOUNDS_OUT, std430) writeonly buffer Bounds { ClusterBounds bounds[]; };
layout(binding = ML_BOUNDS_COUNTERS, std430) buffer Counters { FrameCounters counters; };
layout(binding = ML_BOUNDS_TILE_MASKS, std430) writeonly buffer TileMasks { uvec2 tileMasks[]; }; // slices 0-31, 32-63
layout(binding = ML_BOUNDS_NORMAL) uniform texture2D normalImage; // G-buffer normal (w < 0: not a receiver)
layout(binding = ML_BOUNDS_RECEIVERS, std430) writeonly buffer Receivers { ClusterReceivers receivers[]; };

#ifndef ML_WAVE_REDUCE
shared uint sMask[2];
shared uint sLo[3][ML_MAX_SLICES];
shared uint sHi[3][ML_MAX_SLICES];
// Receiver variant: the receivers' world box (keys) and normal codes (clusterNormalCode), per slice.
shared uint sRLo[3][ML_MAX_SLICES];
shared uint sRHi[3][ML_MAX_SLICES];
shared uint sNLo[3][ML_MAX_SLICES];
shared uint sNHi[3][ML_MAX_SLICES];
#endif

// Monotonic float <-> uint mapping: a < b as floats iff key(a) < key(b) as uints.
uint toKey(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
}
float fromKey(uint k) {
    return uintBitsToFloat((k & 0x80000000u) != 0u ? (k & 0x7fffffffu) : ~k);
}

#ifdef ML_WAVE_REDUCE
const uint kNone = 0xFFFFFFFFu;

void main() {
    uint slices = frame.cluster.x;
    uint x = gl_WorkGroupID.x * ML_TILE_SIZE + gl_LocalInvocationID.x;
    uint tile = gl_WorkGroupID.y * frame.size.z + gl_WorkGroupID.x;
    // This lane's pixels (one per row): slice (kNone without a surface), world key, receiver flag and
    // the keys of the unit normal's components. clusterNormalCode is non-decreasing in its component (a
    // chain of correctly rounded operations, floor and clamps), so the smallest lower code of a cluster
    // is the code of its smallest component and the largest upper code that of its largest: the codes
    // are taken once per cluster, from the reduced components, equal to the reference's per-pixel ones.
    uint sl[ML_TILE_SIZE];
    uvec3 key[ML_TILE_SIZE], nkey[ML_TILE_SIZE];
    bool rec[ML_TILE_SIZE];
    uint next = kNone; // the lane's smallest slice not yet reduced
    [[unroll]] for (uint r = 0u; r < ML_TILE_SIZE; ++r) {
        uint y = gl_WorkGroupID.y * ML_TILE_SIZE + r;
        sl[r] = kNone;
        key[r] = uvec3(0u);
        nkey[r] = uvec3(0u);
        rec[r] = false;
        if (x >= frame.size.x || y >= frame.size.y) continue;
        float d = texelFetch(depthImage, ivec2(x, y), 0).r;
        if (!hasSurface(d)) continue;
        vec3 p = worldFromPixel(x, y, d, frame.invViewProj, frame.size);
        sl[r] = clusterSlice(linearDepth(d, frame.depth));
        key[r] = uvec3(toKey(p.x), toKey(p.y), toKey(p.z));
        if (kReceivers != 0u) {
            vec4 stored = texelFetch(normalImage, ivec2(x, y), 0);
            rec[r] = !(stored.w < 0.0); // as vsm_mark: ML_NOT_A_RECEIVER is -1
            if (rec[r]) {
                vec3 n = clusterUnitNormal(stored.xyz);
                nkey[r] = uvec3(toKey(n.x), toKey(n.y), toKey(n.z));
            }
        }
        next = min(next, sl[r]);
    }
    uvec2 mask = uvec2(0u);
    // The loop's condition is uniform (a subgroupMin), so every lane takes every turn.
    for (uint s = subgroupMin(next); s != kNone; s = subgroupMin(next)) {
        // The cluster's box takes the non-receivers here (the receivers' box is added at the write).
        uvec3 lo = uvec3(kNone), hi = uvec3(0u), rlo = uvec3(kNone), rhi = uvec3(0u);
        uvec3 nlo = uvec3(kNone), nhi = uvec3(0u);
        next = kNone;
        [[unroll]] for (uint r = 0u; r < ML_TILE_SIZE; ++r) {
            if (sl[r] == s) {
                if (rec[r]) {
                    rlo = min(rlo, key[r]);
                    rhi = max(rhi, key[r]);
                    nlo = min(nlo, nkey[r]);
                    nhi = max(nhi, nkey[r]);
                } else {
                    lo = min(lo, key[r]);
                    hi = max(hi, key[r]);
                }
            } else if (sl[r] > s && sl[r] != kNone) {
                next = min(next, sl[r]);
            }
        }
        if (kReceivers != 0u) {
            rlo = subgroupMin(rlo);
            rhi = subgroupMax(rhi);
            nlo = subgroupMin(nlo);
            nhi = subgroupMax(nhi);
        }
        lo = min(subgroupMin(lo), rlo);
        hi = max(subgroupMax(hi), rhi);
        mask[s >> 5] |= 1u << (s & 31u);
        if (subgroupElect()) {
            ClusterBounds b;
            b.lo = vec4(fromKey(lo.x), fromKey(lo.y), fromKey(lo.z), 1.0);
            b.hi = vec4(fromKey(hi.x), fromKey(hi.y), fromKey(hi.z), 0.0);
            bounds[tile * slices + s] = b;
            if (kReceivers != 0u) {
                ClusterReceivers rc;
                rc.lo = vec3(0.0);
                rc.hi = vec3(0.0);
                rc.normalLo = 0u;
                rc.normalHi = 0u;
                if (rlo.x != kNone) {
                    rc.lo = vec3(fromKey(rlo.x), fromKey(rlo.y), fromKey(rlo.z));
                    rc.hi = vec3(fromKey(rhi.x), fromKey(rhi.y), fromKey(rhi.z));
                    uvec3 cl, ch;
                    for (int c = 0; c < 3; ++c) {
                        cl[c] = clusterNormalCode(fromKey(nlo[c]), false);
                        ch[c] = clusterNormalCode(fromKey(nhi[c]), true);
                    }
                    rc.normalLo = cl.x | (cl.y << 10u) | (cl.z << 20u);
                    rc.normalHi = ch.x | (ch.y << 10u) | (ch.z << 20u) | ML_CLUSTER_HAS_RECEIVER;
                }
                receivers[tile * slices + s] = rc;
            }
        }
    }
    // The empty clusters (other addresses than the writes above): zero bounds, as the per-lane build.
    for (uint s = gl_LocalInvocationID.x; s < slices; s += ML_TILE_SIZE)
        if ((mask[s >> 5] & (1u << (s & 31u))) == 0u)
            bounds[tile * slices + s] = ClusterBounds(vec4(0.0), vec4(0.0));
    if (subgroupElect()) {
        tileMasks[tile] = mask;
        uint occupied = uint(bitCount(mask.x) + bitCount(mask.y));
        if (occupied > 0u) atomicAdd(counters.occupiedClusters, occupied);
    }
}
#else
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
#ifndef ML_WAVE_REDUCE
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
                // nothing. Most pixels of a cluster share its normal, so most of these are skipped; 12
                // unconditional atomics a pixel made the variant 1.8x the plain pass on lavapipe
                // (docs/results/log.md has the run).
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
#endif
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
#endif
