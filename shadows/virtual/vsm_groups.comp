#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_groups (culling 1/3): one thread per group of ML_VSM_CULL_GROUP casters, consecutive in the
// culling order (VirtualShadowMaps::buildCasterOrder: static casters in Morton order), writes the
// group's bounds (GpuCasterGroup: the union of the drawing casters' boxes, and of the dynamic ones, with
// their counts and meshlets). vsm_pairs then tests a group against a map once for its 64 casters: on the
// night city at 4096 lights 82 % of the (caster group, dirty map) pairs lie outside the map's frustum. Recomputed every frame (a
// loop of 64 box reads per group; the casters are an upload buffer the host rewrites where they changed).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_CULL_GROUP) in;

layout(binding = ML_VSM_GROUPS_CASTERS, std430) readonly buffer Casters { GpuCaster casters[]; };
layout(binding = ML_VSM_GROUPS_ORDER, std430) readonly buffer Order { uint casterOrder[]; }; // buildCasterOrder (CPU)
layout(binding = ML_VSM_GROUPS_GROUPS, std430) writeonly buffer Groups { GpuCasterGroup groups[]; };
layout(push_constant) uniform Push { VsmCullPush push; }; // casterCount (capacity unused)

void main() {
    uint g = gl_GlobalInvocationID.x;
    uint first = g * ML_VSM_CULL_GROUP;
    if (first >= push.casterCount) return;
    uint last = min(first + ML_VSM_CULL_GROUP, push.casterCount);
    GpuCasterGroup b;
    b.lo = vec4(1e30, 1e30, 1e30, 0.0); // empty: the counts say so, the boxes are never read
    b.hi = vec4(-1e30, -1e30, -1e30, 0.0);
    b.dynamicLo = b.lo;
    b.dynamicHi = b.hi;
    b.counts = uvec4(0u);
    for (uint i = first; i < last; ++i) {
        GpuCaster c = casters[casterOrder[i]];
        if (c.draw.x == 0u) continue; // casts no shadow: vsm_cull and vsm_expand skip it too
        b.lo.xyz = min(b.lo.xyz, c.lo.xyz);
        b.hi.xyz = max(b.hi.xyz, c.hi.xyz);
        b.counts.xy += uvec2(1u, c.meshlets.y);
        if (c.draw.w == 0u) continue;
        b.dynamicLo.xyz = min(b.dynamicLo.xyz, c.lo.xyz);
        b.dynamicHi.xyz = max(b.dynamicHi.xyz, c.hi.xyz);
        b.counts.zw += uvec2(1u, c.meshlets.y);
    }
    groups[g] = b;
}
