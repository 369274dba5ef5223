#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_hpb: one level of the hierarchical page buffer, the image mip `level - 1` of every active map's
// layer (one dispatch per level, finest first; layout in vsm_math.h). A texel of level 1 is the OR of
// the DIRTY bits of its 2x2 pages in the page table; a texel of level l > 1 is the OR of its 2x2 texels
// of level l - 1 (`src`). Texels outside every mip's cells are written 0, so the levels above OR zeros
// there. vsm_cull, vsm_expand and the task shader then test at most 2x2 cells per caster or meshlet.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_math.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Active { uint vsmActive[]; };
layout(binding = 2, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = 3, r32ui) uniform readonly uimage2DArray src;  // level - 1 (level 1: not read)
layout(binding = 4, r32ui) uniform writeonly uimage2DArray dst; // this level
layout(push_constant) uniform Push { VsmHpbPush push; };

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    uvec2 size = uvec2(imageSize(dst).xy);
    if (p.x >= size.x || p.y >= size.y || gl_WorkGroupID.z >= push.activeMaps) return;
    uint map = vsmActive[gl_WorkGroupID.z];
    uint any = 0u;
    if (push.level == 1u) {
        uint s0 = vsm.page.z, mips = vsm.page.w;
        for (uint mip = 0u; mip < mips; ++mip) { // the mip whose level-1 cells hold column p.x
            uint side = (s0 >> mip) >> 1u, first = vsmHpbColumn(s0, mip) >> 1u;
            if (side == 0u || p.x < first) break;
            if (p.x >= first + side) continue;
            if (p.y < side)
                for (uint dy = 0u; dy < 2u; ++dy)
                    for (uint dx = 0u; dx < 2u; ++dx) {
                        uint px = 2u * (p.x - first) + dx, py = 2u * p.y + dy;
                        any |= vsmTable[vsmEntry(vsm.sizes.x, s0, map, mip, px, py)] & ML_VSM_DIRTY;
                    }
            break;
        }
    } else {
        for (uint dy = 0u; dy < 2u; ++dy)
            for (uint dx = 0u; dx < 2u; ++dx) any |= imageLoad(src, ivec3(2u * p.x + dx, 2u * p.y + dy, map)).x;
    }
    imageStore(dst, ivec3(p, map), uvec4(any != 0u ? 1u : 0u));
}
