#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_hpb: one level of the hierarchical page buffer for every active map and mip (one dispatch per
// level, finest first). Cell (x, y) of level l is the OR of cells (2x..2x+1, 2y..2y+1) of level l - 1;
// level 1 reads the page table's DIRTY bits. vsm_cull then tests at most 2x2 cells per caster.
#include "shaders/shared/glsl_common.h"
#include "shadows/virtual/vsm_math.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Active { uint vsmActive[]; };
layout(binding = 2, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = 3, std430) buffer Hpb { uint vsmHpb[]; };
layout(push_constant) uniform Push {
    uint level;       // 1..log2(S_0)
    uint cellsPerMap; // sum over mips of (S_m >> level)^2
    uint activeMaps;
    uint hpbPerMap;
};

void main() {
    uint cell = gl_GlobalInvocationID.x;
    if (cell >= cellsPerMap || gl_GlobalInvocationID.y >= activeMaps) return;
    uint map = vsmActive[gl_GlobalInvocationID.y];
    uint s0 = vsm.page.z, mips = vsm.page.w;
    uint mip = 0u;
    for (; mip < mips; ++mip) {
        uint side = (s0 >> mip) >> level;
        if (cell < side * side) break;
        cell -= side * side;
    }
    if (mip >= mips) return;
    uint side = (s0 >> mip) >> level;
    uint x = cell % side, y = cell / side;
    uint any = 0u;
    for (uint dy = 0u; dy < 2u; ++dy)
        for (uint dx = 0u; dx < 2u; ++dx) {
            uint cx = 2u * x + dx, cy = 2u * y + dy;
            if (level == 1u)
                any |= vsmTable[vsmEntry(vsm.sizes.x, s0, map, mip, cx, cy)] & ML_VSM_DIRTY;
            else
                any |= vsmHpb[map * hpbPerMap + vsmHpbOffset(s0, mips, mip, level - 1u) + cy * (side * 2u) + cx];
        }
    vsmHpb[map * hpbPerMap + vsmHpbOffset(s0, mips, mip, level) + y * side + x] = any != 0u ? 1u : 0u;
}
