#version 460
#extension GL_GOOGLE_include_directive : require
// Footprint light assignment, pass B: one thread per tile. The tile's occupied clusters (mask from
// cluster_bounds) take consecutive ranges of the pool, allocated with one atomic per tile; a cluster
// whose range would pass the pool's capacity is marked ML_CLUSTER_OVERFLOW and counted (its pixels
// then test every visible light). Every cluster of the tile gets its (offset, count), empty ones (0, 0),
// so `ranges` is the same layout the brute-force pass writes. When pass A recorded more hits than
// `hits` holds, every non-empty cluster is marked overflowed (and counted): correct, slow, and only
// with a pool far too small for the frame (the hit buffer is sized from the pool).
// For the sorted fill (light_fill.comp) the thread also turns the tile's light bitmask (pass A) into
// per-word prefix counts and allocates the tile's T lights (T = its popcount) a cleared range of
// tileSlices: T <= the tile's hits, so the ranges fit the hit capacity whenever the hits did.
#include "shaders/shared/glsl_common.glsl"
#include "culling/culling_push.h"
#include "culling/culling_bindings.h"

layout(local_size_x = ML_ALLOC_GROUP) in;

layout(binding = ML_ALLOC_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_ALLOC_TILE_MASKS, std430) readonly buffer TileMasks { uvec2 tileMasks[]; };
layout(binding = ML_ALLOC_COUNTS, std430) readonly buffer Counts { uint counts[]; };
layout(binding = ML_ALLOC_RANGES, std430) writeonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_ALLOC_COUNTERS, std430) buffer Counters { FrameCounters counters; };
layout(binding = ML_ALLOC_WORK, std430) buffer Work { uint workTests; uint hitCount; uint tileCursor; };
layout(binding = ML_ALLOC_TILE_BITS, std430) readonly buffer TileBits { uint tileBits[]; };
layout(binding = ML_ALLOC_TILE_PREFIX, std430) writeonly buffer TilePrefix { uint tilePrefix[]; };
layout(binding = ML_ALLOC_TILE_RANGES, std430) writeonly buffer TileRanges { uvec2 tileRanges[]; };
layout(binding = ML_ALLOC_TILE_SLICES, std430) writeonly buffer TileSlices { uvec2 tileSlices[]; };
layout(push_constant) uniform Push { CullPush push; };

void main() {
    uint tile = gl_GlobalInvocationID.x;
    if (tile >= frame.size.z * frame.size.w) return;
    uint slices = frame.cluster.x;
    uvec2 mask = tileMasks[tile];
    uint total = 0;
    for (uint s = 0; s < slices; ++s)
        if ((mask[s >> 5] & (1u << (s & 31u))) != 0u) total += counts[tile * slices + s];
    uint offset = total > 0u ? atomicAdd(counters.poolCursor, total) : 0u;
    uint longest = 0;
    for (uint s = 0; s < slices; ++s) {
        uint c = tile * slices + s;
        uint count = (mask[s >> 5] & (1u << (s & 31u))) != 0u ? counts[c] : 0u;
        uvec2 r = uvec2(0u, count);
        if (count > 0u) {
            if (offset + count > frame.limits.x || hitCount > push.hitCapacity) {
                r.x = ML_CLUSTER_OVERFLOW;
                atomicAdd(counters.overflowClusters, 1u);
            } else {
                r.x = offset;
            }
            offset += count;
            longest = max(longest, count);
        }
        ranges[c] = r;
    }
    if (total > 0u) {
        atomicAdd(counters.clusterLightsSum, uint64_t(total));
        atomicMax(counters.maxClusterLights, longest);
    }
    // The tile's lights: prefix counts per word, then a range of T slice masks, cleared. Only the
    // words of visible lights can be set (256 lights: 8 of the 128).
    uint lightsT = 0, words = (frame.cluster.z + 31u) / 32u;
    for (uint w = 0; w < words; ++w) {
        tilePrefix[tile * ML_TILE_WORDS + w] = lightsT;
        lightsT += uint(bitCount(tileBits[tile * ML_TILE_WORDS + w]));
    }
    uint tileOff = lightsT > 0u ? atomicAdd(tileCursor, lightsT) : 0u;
    if (tileOff + lightsT > push.hitCapacity) lightsT = 0u; // only when the hits overflowed too
    tileRanges[tile] = uvec2(tileOff, lightsT);
    for (uint i = 0; i < lightsT; ++i) tileSlices[tileOff + i] = uvec2(0u);
}
