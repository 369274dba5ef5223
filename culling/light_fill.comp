#version 460
#extension GL_GOOGLE_include_directive : require
// Footprint light assignment, pass C: the hits pass A recorded become the pool's lists, sorted by
// light index, in time linear in the hits (the old rank step read the whole unsorted list per hit:
// the sum over clusters of length^2). Two steps (kSpecStep):
//   0 mark: each hit (c, l) of a non-overflowed cluster finds l's rank among the tile's lights from
//     the tile's light bitmask (pass A) and per-word prefix counts (pass B): tilePrefix[w] +
//     bitCount(tileBits[w] & (bit - 1)); it ORs its slice's bit into tileSlices[tileOff + rank].
//     A fixed number of groups strides over the hits (their count is only known on the GPU).
//   1 append: one thread per tile walks the tile's lights in index order (findLSB over the 128
//     words) and appends each to the lists of the slices its mask names. One thread owns the tile's
//     clusters, so no atomics, and every list comes out sorted: the CPU reference's (cullReference).
// Overflowed clusters are skipped (their pixels test every visible light).
#include "shaders/shared/glsl_common.glsl"
#include "culling/culling_push.h"
#include "culling/culling_bindings.h"

layout(local_size_x = ML_FILL_GROUP) in;
layout(constant_id = 0) const uint kSpecStep = 0;

layout(binding = ML_FILL_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_FILL_HITS, std430) readonly buffer Hits { uvec2 hits[]; }; // (cluster, light)
layout(binding = ML_FILL_RANGES, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_FILL_POOL, std430) writeonly buffer Pool { uint pool[]; };
layout(binding = ML_FILL_WORK, std430) readonly buffer Work { uint workTests; uint hitCount; uint tileCursor; };
layout(binding = ML_FILL_TILE_BITS, std430) readonly buffer TileBits { uint tileBits[]; };     // ML_TILE_WORDS per tile
layout(binding = ML_FILL_TILE_PREFIX, std430) readonly buffer TilePrefix { uint tilePrefix[]; }; // ML_TILE_WORDS per tile
layout(binding = ML_FILL_TILE_RANGES, std430) readonly buffer TileRanges { uvec2 tileRanges[]; }; // (tileOff, T)
layout(binding = ML_FILL_TILE_SLICES, std430) buffer TileSlices { uvec2 tileSlices[]; };         // slice mask per rank
layout(push_constant) uniform Push { CullPush push; };

void main() {
    uint slices = frame.cluster.x;
    if (kSpecStep == 0u) {
        uint n = min(hitCount, push.hitCapacity);
        for (uint i = gl_GlobalInvocationID.x; i < n; i += gl_NumWorkGroups.x * ML_FILL_GROUP) {
            uvec2 h = hits[i];
            if (ranges[h.x].x == ML_CLUSTER_OVERFLOW) continue;
            uint tile = h.x / slices, s = h.x % slices;
            uvec2 tr = tileRanges[tile];
            if (tr.y == 0u) continue; // only when the hits overflowed (every cluster overflowed)
            uint w = tile * ML_TILE_WORDS + (h.y >> 5u);
            uint rank = tilePrefix[w] + uint(bitCount(tileBits[w] & ((1u << (h.y & 31u)) - 1u)));
            uint slot = tr.x + rank;
            if (s < 32u) atomicOr(tileSlices[slot].x, 1u << s);
            else atomicOr(tileSlices[slot].y, 1u << (s - 32u));
        }
        return;
    }
    uint tile = gl_GlobalInvocationID.x;
    if (tile >= frame.size.z * frame.size.w) return;
    uvec2 tr = tileRanges[tile];
    if (tr.y == 0u) return;
    uint fill[ML_MAX_SLICES];
    for (uint s = 0; s < slices; ++s) fill[s] = 0u;
    uint rank = 0, words = (frame.cluster.z + 31u) / 32u; // only visible lights' words can be set
    for (uint word = 0; word < words; ++word) {
        uint bits = tileBits[tile * ML_TILE_WORDS + word];
        while (bits != 0u) {
            uint l = word * 32u + uint(findLSB(bits));
            bits &= bits - 1u;
            uvec2 m = tileSlices[tr.x + rank++];
            for (uint part = 0; part < 2u; ++part) {
                uint sb = m[part];
                while (sb != 0u) {
                    uint s = part * 32u + uint(findLSB(sb));
                    sb &= sb - 1u;
                    uvec2 r = ranges[tile * slices + s];
                    if (r.x != ML_CLUSTER_OVERFLOW) pool[r.x + fill[s]++] = l;
                }
            }
        }
    }
}
