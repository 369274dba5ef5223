#version 460
#extension GL_GOOGLE_include_directive : require
// mip_reduce: mip m of a 2D array image (R32_UINT) from mip m - 1, every layer (one dispatch per mip,
// z = layer). Destination texel (x, y) reduces source texels 2x..2x+1 by 2y..2y+1; on an odd source
// side the last destination column / row also takes the last source column / row, so every source
// texel reaches exactly one destination texel (nothing dropped at non-power-of-two sizes).
// kOp: 0 sum, 1 max, 2 any (1 when a source texel is non-zero: the 2x2 OR of a page pyramid).
// CPU twin: mipReduceReference (tests/gpu/image_mips_test.cpp).
#include "gpu/mip_reduce_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const uint kOp = 0u;
layout(binding = ML_MIP_REDUCE_SRC, r32ui) uniform readonly uimage2DArray src;
layout(binding = ML_MIP_REDUCE_DST, r32ui) uniform writeonly uimage2DArray dst;

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID.xy, gl_WorkGroupID.z);
    ivec2 ds = imageSize(dst).xy, ss = imageSize(src).xy;
    if (p.x >= ds.x || p.y >= ds.y) return;
    ivec2 lo = 2 * p.xy;
    ivec2 hi = min(lo + 1, ss - 1);
    if (p.x == ds.x - 1) hi.x = ss.x - 1;
    if (p.y == ds.y - 1) hi.y = ss.y - 1;
    uint r = 0u;
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            uint v = imageLoad(src, ivec3(x, y, p.z)).x;
            r = kOp == 0u ? r + v : kOp == 1u ? max(r, v) : (r | (v != 0u ? 1u : 0u));
        }
    imageStore(dst, p, uvec4(r));
}
