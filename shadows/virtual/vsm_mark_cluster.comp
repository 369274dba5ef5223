#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_mark_cluster: page marking per cluster (VsmSettings::clusterMarking, the clustered culling modes):
// one workgroup per screen tile of ML_TILE_SIZE^2 pixels; its lanes share the cluster-light pairs of the
// tile's occupied slices (the tile mask of cluster_bounds), no shared memory and no barrier. The cluster's
// receivers (ClusterReceivers, from cluster_bounds' receiver variant: the AABB of the pixels that
// receive shadows, and a box over their unit normals) bound what it marks: a cluster without receivers
// marks nothing, and a light that every receiver faces away from (vsmBoxFacesAway, with margins that
// keep the per-pixel pass's vsmFacesLight false for each of them) marks nothing. For each other light
// of the cluster's list, a lane marks every page that any receiver inside the box could read
// (vsmBoxPages: vsm_bounds.h's mip, clip-level and texel bounds, the PCF kernel, the normal offset and
// one texel), the box first cut to the part the light reaches (vsmReachBox: range sphere, spot cone)
// and, per mip or clip level, to the receivers that can pick it (vsmMipView, vsmLevelBox); the box's two
// halves (vsmHalfBox) mark instead where they count fewer pages. A light whose box reaches more than
// ML_VSM_CLUSTER_PAGES pages (a box straddling cube faces or grazing a near plane would mark whole mips)
// is refined instead: the tile's receivers in that slice mark for it as vsm_mark does
// (vsmMarkReceiver), up to kRefineBatch pairs of a lane per walk of the tile's pixels.
// The marks and the request list are then those of the per-pixel pass, plus the pages the boxes add.
// CPU twin: vsmMarkClusterReference (bit for bit).
#include "shaders/shared/glsl_common.glsl"
#include "shaders/shared/cluster_receivers.h"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

// One workgroup per tile; its lanes share the tile's cluster-light pairs (main). A tile holds a few
// occupied slices with a few lights each, so one lane per slice, or the lanes over one slice's lights at
// a time, left most lanes idle.
const uint kLanes = ML_VSM_CLUSTER_LANES;
layout(local_size_x = kLanes) in;
// Profiling only (ML_VSM_MARK_STAGE with --vsm-mark cluster, vsm_programs.cpp; tools/vsm_mark_stages.py
// --cluster): 0 marks; 1..5 stop early to time the pass's parts, and then mark nothing (the frame's
// shadows are wrong): 1 returns after the tile mask, receiver bounds and light range, 2 after the light
// loop's reach and facing tests, 3 after counting each pair's whole box, 4 after counting its halves
// too, 5 marks the boxes but refines no pair per pixel.
layout(constant_id = 0) const uint kStage = 0;

layout(binding = ML_VSM_MARK_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_VSM_MARK_SLICES, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = ML_VSM_MARK_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_VSM_MARK_RANGES, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_VSM_MARK_LIGHT_POOL, std430) readonly buffer Pool { uint pool[]; };
layout(binding = ML_VSM_MARK_DEPTH) uniform texture2D depthImage;
layout(binding = ML_VSM_MARK_NORMAL) uniform texture2D normalImage;
layout(binding = ML_VSM_MARK_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_MARK_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_MARK_COVERAGE, std430) readonly buffer Coverage { uint vsmCoverage[]; };
layout(binding = ML_VSM_MARK_MARKS, std430) coherent buffer Marks { uint vsmMarks[]; };
layout(binding = ML_VSM_MARK_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_MARK_RANK_BASE, std430) readonly buffer Ranks { uint vsmRankBase[]; }; // per (map slot, mip)
layout(binding = ML_VSM_MARK_REQUESTS, std430) writeonly buffer List { uint vsmList[]; };
layout(binding = ML_VSM_MARK_RECEIVERS, std430) readonly buffer Receivers { ClusterReceivers clusterReceivers[]; };
layout(binding = ML_VSM_MARK_TILE_MASKS, std430) readonly buffer TileMasks { uvec2 tileMasks[]; }; // bit s: slice s occupied

#define VSM_CONST vsm
#define VSM_MAPS vsmMaps
#define VSM_COVER vsmCoverage
#define VSM_MARKS vsmMarks
#define VSM_COUNTERS vsmCounters
#define VSM_RANKS vsmRankBase
#define VSM_LIST vsmList
#define VSM_MARKING
#include "shaders/shared/cluster_list.glsl"
#include "shadows/virtual/vsm_common.glsl"
#include "shadows/virtual/vsm_mark_box.glsl"

// Refined pairs (slice, light index) are walked over the tile's pixels together, this many at a time
// per lane (registers).
const uint kRefineBatch = 8u;

// vsm_mark.comp's marks of one receiver for one light.
void markReceiver(GpuLight L, vec3 P, vec3 N) {
    if (lightReachesPoint(L, P) && vsmFacesLight(L, P, N)) vsmMarkReceiver(L, L.info.y, P, N);
}

// The tile's receivers mark for the batch's pairs, each receiver for the pairs of its own slice.
void refine(uvec2 tile, uvec2 batch[kRefineBatch], uint n) {
    for (uint k = 0u; k < ML_TILE_SIZE * ML_TILE_SIZE; ++k) {
        uvec2 px = tile * ML_TILE_SIZE + uvec2(k % ML_TILE_SIZE, k / ML_TILE_SIZE);
        if (px.x >= frame.size.x || px.y >= frame.size.y) continue;
        float d = texelFetch(depthImage, ivec2(px), 0).r;
        if (!hasSurface(d)) continue;
        uint s = clusterSlice(linearDepth(d, frame.depth));
        bool mine = false;
        for (uint j = 0u; j < n; ++j) mine = mine || batch[j].x == s;
        if (!mine) continue;
        vec4 stored = texelFetch(normalImage, ivec2(px), 0);
        if (stored.w < 0.0) continue; // ML_NOT_A_RECEIVER: the evaluation looks no shadow up here
        vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
        vec3 N = vsmNormalize(stored.xyz);
        for (uint j = 0u; j < n; ++j)
            if (batch[j].x == s) markReceiver(lights[batch[j].y], P, N);
    }
}

void main() {
    uint slices = frame.cluster.x;
    uint lane = gl_LocalInvocationIndex;
    uvec2 tile = gl_WorkGroupID.xy;
    uint t = tile.y * frame.size.z + tile.x;
    uvec2 mask = tileMasks[t];
    // The tile's cluster-light pairs, slice by slice in increasing order, numbered over the tile: lane l
    // takes pairs l, l + kLanes, l + 2 kLanes, ..., so the lanes stay busy across the slices however few
    // lights each cluster has. Each lane keeps a cursor on the slice of its next pair: `start` and
    // `count` number that slice's pairs, `left` the occupied slices after it.
    uvec2 left = mask;
    uint s = 0u, start = 0u, count = 0u;
    bool all = false;
    uvec2 range = uvec2(0u);
    vec3 lo = vec3(0.0), hi = vec3(0.0), nlo = vec3(0.0), nhi = vec3(0.0);
    uvec2 batch[kRefineBatch];
    uint n = 0u;
    uint kept = 0u;
    for (uint q = lane;; q += kLanes) {
        bool done = false;
        while (q >= start + count) { // the pair lies in a later slice
            start += count;
            count = 0u;
            uint w = left.x != 0u ? 0u : 1u;
            if (left[w] == 0u || (s = w * 32u + uint(findLSB(left[w]))) >= slices) {
                done = true; // no occupied slice left
                break;
            }
            left[w] &= left[w] - 1u; // s: an occupied slice, a surface in the cluster
            ClusterReceivers b = clusterReceivers[t * slices + s];
            if ((b.normalHi & ML_CLUSTER_HAS_RECEIVER) == 0u) continue; // no receiver: no lookup, no page
            range = ranges[t * slices + s];
            all = range.x == ML_CLUSTER_OVERFLOW; // the cluster overflowed: every visible light
            count = all ? frame.cluster.z : range.y;
            lo = b.lo;
            hi = b.hi;
            nlo = vsmNormalLo(b);
            nhi = vsmNormalHi(b);
        }
        if (done) break;
        uint i = q - start;
        // The profiling stages keep their work alive with a test no real frame passes (vsm_mark.comp).
        if (kStage == 1u) {
            kept += floatBitsToUint(lo.x + hi.y + nlo.z + nhi.x) + i;
            continue;
        }
        uint index = all ? i : pool[range.x + i];
        GpuLight L = lights[index];
        // lightTouchesBox is conservative (light_math.h): false only when no point of the box is reached.
        if (L.info.y == ML_VSM_NO_MAP || !lightTouchesBox(L, lo, hi)) continue;
        VsmBox reach = vsmReachBox(L, lo, hi); // the receivers L reaches
        if (vsmBoxEmpty(reach)) continue;
        if (vsmBoxFacesAway(L, reach.lo, reach.hi, nlo, nhi)) continue; // every receiver faces away from L
        if (kStage == 2u) {
            kept += floatBitsToUint(reach.lo.x);
            continue;
        }
        // The box, or its two halves where they count fewer pages (vsmHalfBox; a half whose
        // receivers all face away counts none). Halves only from 4 pages: tried on every pair of
        // 2 or more, the three counts doubled the indoor mark pass for 1 % fewer pages
        // (docs/results/log.md).
        uint whole = vsmBoxPages(L, L.info.y, reach.lo, reach.hi, nlo, nhi, false);
        if (kStage == 3u) {
            kept += whole;
            continue;
        }
        VsmBox h0 = vsmHalfBox(reach, 0u), h1 = vsmHalfBox(reach, 1u);
        bool use0 = !vsmBoxEmpty(h0) && !vsmBoxFacesAway(L, h0.lo, h0.hi, nlo, nhi);
        bool use1 = !vsmBoxEmpty(h1) && !vsmBoxFacesAway(L, h1.lo, h1.hi, nlo, nhi);
        uint halves = whole <= 3u ? whole : (use0 ? vsmBoxPages(L, L.info.y, h0.lo, h0.hi, nlo, nhi, false) : 0u) +
                                                (use1 ? vsmBoxPages(L, L.info.y, h1.lo, h1.hi, nlo, nhi, false) : 0u);
        if (kStage == 4u) {
            kept += halves;
            continue;
        }
        if (min(whole, halves) <= ML_VSM_CLUSTER_PAGES) {
            if (halves < whole) {
                if (use0) vsmBoxPages(L, L.info.y, h0.lo, h0.hi, nlo, nhi, true);
                if (use1) vsmBoxPages(L, L.info.y, h1.lo, h1.hi, nlo, nhi, true);
            } else {
                vsmBoxPages(L, L.info.y, reach.lo, reach.hi, nlo, nhi, true);
            }
            continue;
        }
        if (kStage == 5u) continue;
        batch[n++] = uvec2(s, index);
        if (n == kRefineBatch) {
            refine(tile, batch, n);
            n = 0u;
        }
    }
    if (n > 0u) refine(tile, batch, n);
    if (kept == 0xFFFFFFFFu) atomicAdd(vsmCounters.listCount, 1u);
}
