#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_ballot : require
// vsm_draw: attachment-less raster; each fragment of a page rendered this frame (DIRTY) takes the
// atomic minimum of its quantised linear depth into the page's physical texel (as the static dual-depth
// bake does: order-independent, so the result does not depend on draw order). Draws are clipped to one
// dirty page (vsm_page_clip.glsl); the DIRTY test stays for the mesh path's unclipped overflow draws.
// With the static layer (vsm.camera.w) a static caster's fragment goes to the page's static twin instead
// (the pool's second half), where that is rendered this frame (DIRTY_STATIC; a kept twin already holds
// it), and vsm_merge takes the minimum of page and twin: inMap's bit 31 marks dynamic casters.
// Every invocation is counted (VsmCounters.fragmentsDrawn: one atomic per subgroup, helpers excluded,
// since a helper's atomic has no effect).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_math.h"
#include "shadows/virtual/vsm_bindings.h"

layout(binding = ML_VSM_DRAW_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_DRAW_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_DRAW_TABLE, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_DRAW_PAGE_POOL, std430) buffer PagePool { uint vsmPool[]; };
layout(binding = ML_VSM_DRAW_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(push_constant) uniform Push { VsmDrawPush push; };

layout(location = 0) in float inDepth;
layout(location = 1) flat in uint inMap;

void main() {
    uvec4 real = subgroupBallot(!gl_HelperInvocation);
    if (gl_SubgroupInvocationID == subgroupBallotFindLSB(real))
        atomicAdd(vsmCounters.fragmentsDrawn, subgroupBallotBitCount(real));
    uvec2 t = uvec2(gl_FragCoord.xy);
    uint shift = vsm.page.y, size = vsm.page.x;
    uint map = inMap & 0x7FFFFFFFu;
    uint pt = vsmTable[vsmEntry(vsm.sizes.x, vsm.page.z, map, push.mip, t.x >> shift, t.y >> shift)];
    if ((pt & ML_VSM_DIRTY) == 0u) return;
    uint texel = (pt & ML_VSM_PHYS_MASK) * size * size + (t.y & (size - 1u)) * size + (t.x & (size - 1u));
    uint depth = vsmQuantize(inDepth, vsmMaps[map].params.z);
    if (vsm.camera.w != 0.0 && (inMap & 0x80000000u) == 0u) {
        if ((pt & ML_VSM_DIRTY_STATIC) != 0u) atomicMin(vsmPool[vsm.sizes.z * size * size + texel], depth);
        return;
    }
    atomicMin(vsmPool[texel], depth);
}
