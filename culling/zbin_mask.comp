#version 460
#extension GL_GOOGLE_include_directive : require
// Z-binning, tile masks (culling/zbin.h): each depth-sorted light rasterises its screen rectangle of
// tiles (its footprint, lightFootprint, computed by the host) into the per-tile bitmasks: bit i of
// tile t (word t * words + i / 32) is set when sorted light i's rectangle holds t and, with
// push.depthTest, its depth range spans one of the tile's occupied cluster slices (cluster_bounds'
// 64-bit tile masks; a tile with no pixel then gets no light at all). ML_ZBIN_LANES threads per light
// stride over its tiles, as the footprint pass does; the words were cleared before (vkCmdFillBuffer)
// and bits go in with atomicOr, so the result does not depend on the order of the threads.
#include "shaders/shared/glsl_common.glsl"
#include "culling/zbin_types.h"
#include "culling/zbin_bindings.h"

layout(local_size_x = ML_ZBIN_GROUP) in;
layout(push_constant) uniform Push { ZBinPush push; };

layout(binding = ML_ZBIN_MASK_SORTED, std430) readonly buffer Sorted { ZBinLight sorted[]; };
layout(binding = ML_ZBIN_MASK_TILE_SLICES, std430) readonly buffer TileSlices { uvec2 tileSlices[]; }; // cluster_bounds'
layout(binding = ML_ZBIN_MASK_MASKS, std430) buffer Masks { uint masks[]; };
layout(binding = ML_ZBIN_MASK_FRAME) uniform Frame { FrameConstants frame; };

void main() {
    uint i = gl_GlobalInvocationID.x / ML_ZBIN_LANES, lane = gl_GlobalInvocationID.x % ML_ZBIN_LANES;
    if (i >= push.sorted) return;
    ZBinLight L = sorted[i];
    uint w = L.tiles.z - L.tiles.x + 1u, n = w * (L.tiles.w - L.tiles.y + 1u);
    uint word = i >> 5u, bit = 1u << (i & 31u);
    for (uint k = lane; k < n; k += ML_ZBIN_LANES) {
        uint tile = (L.tiles.y + k / w) * frame.size.z + L.tiles.x + k % w;
        if (push.depthTest != 0u) {
            uvec2 occupied = tileSlices[tile] & L.sliceMask;
            if ((occupied.x | occupied.y) == 0u) continue;
        }
        atomicOr(masks[tile * push.words + word], bit);
    }
}
