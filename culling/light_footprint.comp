#version 460
#extension GL_GOOGLE_include_directive : require
// Footprint light assignment (clustered mode), pass A: count and record the hits; light_alloc.comp
// (B) allocates, light_fill.comp (C) turns the recorded hits into sorted lists in the pool. Two variants
// (kSpecWide): the lane variant walks the footprints of the spot and point lights, the wide variant
// gives each wide light (GpuLight.params.w = 1: the directional ones, chosen by the host) one thread
// per tile of its footprint.
// ML_FOOTPRINT_LANES threads per visible light, several lights per workgroup: the light's footprint
// (lightFootprint: screen rectangle of tiles and depth range, conservative, camera inside the volume
// included) selects tiles; within each tile only
// the occupied slices (the tile's 64-bit mask from cluster_bounds) inside the depth range are tested,
// with the same exact box test as the brute-force pass. So the work is the occupied clusters under
// each light's footprint, not every light times every occupied cluster.
// Per hit (light l touches cluster c): counts[c] += 1, and (c, l) is appended to `hits` (capacity
// hitCapacity; past it only hitCount grows, and light_alloc then overflows every non-empty cluster, so
// nothing is lost). Recording the hits spares pass C a second round of box tests. Each (tile, light)
// with a hit also sets the light's bit in the tile's bitmask (tileBits), which sorts the lists.
#include "shaders/shared/glsl_common.glsl"
#include "culling/culling_push.h"
#include "shaders/shared/light_math.h"
#include "culling/culling_bindings.h"

layout(local_size_x = ML_FOOTPRINT_GROUP) in;
// 0: ML_FOOTPRINT_LANES threads per visible light (wide lights skipped); 1: the wide pass, one thread
// per tile of each wide light's footprint (WideLight, culling_push.h), in rows of ML_WIDE_ROW threads.
layout(constant_id = 0) const uint kSpecWide = 0;
layout(push_constant) uniform Push { CullPush push; };

layout(binding = ML_FOOTPRINT_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_FOOTPRINT_SLICES, std430) readonly buffer Slices { float sliceFar[]; };
#include "shaders/shared/cluster_slice.glsl"
layout(binding = ML_FOOTPRINT_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_FOOTPRINT_BOUNDS, std430) readonly buffer Bounds { ClusterBounds bounds[]; };
layout(binding = ML_FOOTPRINT_TILE_MASKS, std430) readonly buffer TileMasks { uvec2 tileMasks[]; };
layout(binding = ML_FOOTPRINT_COUNTS, std430) buffer Counts { uint counts[]; };
layout(binding = ML_FOOTPRINT_HITS, std430) writeonly buffer Hits { uvec2 hits[]; }; // (cluster, light)
layout(binding = ML_FOOTPRINT_WORK, std430) buffer Work { uint workTests; uint hitCount; };
layout(binding = ML_FOOTPRINT_WIDE, std430) readonly buffer WideLights { WideLight wideLights[]; };
// Per tile a bitmask over the visible lights with a hit there (ML_TILE_WORDS words): light_alloc and
// light_fill rank each hit among its tile's lights from it, so the lists come out sorted in linear time.
layout(binding = ML_FOOTPRINT_TILE_BITS, std430) buffer TileBits { uint tileBits[]; };

shared uint sTests;

// Bits a..b (inclusive) of a 32-bit word; 0 when a > b.
uint bitsBetween(int a, int b) {
    if (a > b) return 0u;
    uint upTo = b >= 31 ? 0xFFFFFFFFu : ((1u << uint(b + 1)) - 1u);
    return upTo & ~((1u << uint(a)) - 1u);
}

// Light l against the occupied slices of one tile inside sliceMask: box tests, then the tile's hits
// reserved with one atomic on the shared hit counter. Returns the box tests run.
uint testTile(GpuLight L, ConePlanes planes, uint l, uint tile, uvec2 sliceMask, uint slices) {
    uvec2 m = tileMasks[tile] & sliceMask;
    uvec2 hitMask = uvec2(0u);
    uint tests = 0;
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
    if (found == 0u) return tests;
    uint h = atomicAdd(hitCount, found);
    atomicOr(tileBits[tile * ML_TILE_WORDS + (l >> 5u)], 1u << (l & 31u)); // one per (tile, light)
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
    return tests;
}

// The wide light whose thread range holds thread t: the last entry with first <= t (binary search;
// entries are in order of first, the first one's is 0).
uint wideEntry(uint t) {
    uint lo = 0u, hi = push.wideCount;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (wideLights[mid].first <= t) lo = mid;
        else hi = mid;
    }
    return lo;
}

void main() {
    uint li = gl_LocalInvocationIndex;
    if (li == 0) sTests = 0u;
    barrier();
    uint slices = frame.cluster.x;
    uint tests = 0;
    if (kSpecWide == 0u) {
        uint l = gl_WorkGroupID.x * (ML_FOOTPRINT_GROUP / ML_FOOTPRINT_LANES) + li / ML_FOOTPRINT_LANES;
        uint lane = li % ML_FOOTPRINT_LANES;
        GpuLight L = lights[min(l, frame.cluster.z - 1u)];
        ConePlanes planes = conePlanes(L);
        LightFootprint f = lightFootprint(L, frame.viewProj, frame.size, frame.cluster.y, frame.depth.x);
        int s0 = int(clusterSlice(f.depth.x)), s1 = int(clusterSlice(f.depth.y));
        uvec2 sliceMask = uvec2(bitsBetween(s0, min(s1, 31)), bitsBetween(max(s0, 32) - 32, s1 - 32));
        uint n = 0, w = 0;
        // A wide light (params.w = 1, set by the host) is the wide pass's alone.
        if (l < frame.cluster.z && L.params.w != 1.0 && f.tiles.x <= f.tiles.z && f.tiles.y <= f.tiles.w) {
            w = f.tiles.z - f.tiles.x + 1u;
            n = w * (f.tiles.w - f.tiles.y + 1u);
        }
        for (uint i = lane; i < n; i += ML_FOOTPRINT_LANES) {
            uint tile = (f.tiles.y + i / w) * frame.size.z + f.tiles.x + i % w;
            tests += testTile(L, planes, l, tile, sliceMask, slices);
        }
    } else {
        uint t = gl_GlobalInvocationID.y * ML_WIDE_ROW + gl_GlobalInvocationID.x;
        if (t < push.wideThreads) {
            WideLight e = wideLights[wideEntry(t)];
            GpuLight L = lights[e.light];
            uint i = t - e.first, w = e.tiles.z - e.tiles.x + 1u;
            uint tile = (e.tiles.y + i / w) * frame.size.z + e.tiles.x + i % w;
            int s0 = int(clusterSlice(e.depth.x)), s1 = int(clusterSlice(e.depth.y));
            uvec2 sliceMask = uvec2(bitsBetween(s0, min(s1, 31)), bitsBetween(max(s0, 32) - 32, s1 - 32));
            tests = testTile(L, conePlanes(L), e.light, tile, sliceMask, slices);
        }
    }
    if (tests > 0u) atomicAdd(sTests, tests);
    barrier();
    if (li == 0 && sTests > 0u) atomicAdd(workTests, sTests);
}
