#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_cull (work expansion at the instance level, RMVSM section 4.3): one thread per (caster, active
// map) (x, y). A caster is drawn into mip m of a map when m has dirty pages, its world box is inside the
// map's frustum (range = the far plane), and the hierarchical page buffer has a dirty cell under its
// projected bounds at the level where those bounds span at most 2x2 cells. Maps of lights with a
// static bake take dynamic casters only. Draws go to one list per mip (one indirect-count draw each).
#include "shaders/shared/glsl_common.h"
#include "shadows/virtual/vsm_math.h"

layout(local_size_x = ML_VSM_CULL_GROUP) in;

layout(binding = 0) uniform VsmConst { VsmConstants vsm; };
layout(binding = 1, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = 2, std430) readonly buffer Active { uint vsmActive[]; };
layout(binding = 3, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = 4, std430) readonly buffer Hpb { uint vsmHpb[]; };
layout(binding = 5, std430) readonly buffer Casters { GpuCaster casters[]; };
layout(binding = 6, std430) readonly buffer MapMips { uint vsmDirtyMips[]; };
layout(binding = 7, std430) writeonly buffer Draws { uint draws[]; }; // VkDrawIndexedIndirectCommand
layout(binding = 8, std430) writeonly buffer DrawInfo { uvec2 drawInfo[]; }; // (instance, map)
layout(binding = 9, std430) buffer DrawCounts { uint drawCounts[]; };      // per mip
layout(binding = 10, std430) buffer Counters { VsmCounters vsmCounters; };
layout(push_constant) uniform Push {
    uint casterCount;
    uint activeMaps;
    uint hpbPerMap;
    uint maxDraws; // per mip
};

bool dirtyCell(uint map, uint mip, uint level, uint x, uint y) {
    uint s0 = vsm.page.z;
    if (level == 0u) return (vsmTable[vsmEntry(vsm.sizes.x, s0, map, mip, x, y)] & ML_VSM_DIRTY) != 0u;
    uint side = (s0 >> mip) >> level;
    return vsmHpb[map * hpbPerMap + vsmHpbOffset(s0, vsm.page.w, mip, level) + y * side + x] != 0u;
}

void main() {
    uint instance = gl_GlobalInvocationID.x;
    if (instance >= casterCount || gl_GlobalInvocationID.y >= activeMaps) return;
    uint map = vsmActive[gl_GlobalInvocationID.y];
    uint mipsDirty = vsmDirtyMips[map];
    if (mipsDirty == 0u) return;
    GpuVsmMap m = vsmMaps[map];
    GpuCaster c = casters[instance];
    if ((m.info.y & ML_VSM_MAP_DYNAMIC_ONLY) != 0u && c.draw.w == 0u) return;
    if (c.draw.x == 0u) return;

    // Frustum (the far plane is the light's range): outside when the box is behind one of the six planes
    // of viewProj (Vulkan depth 0..1).
    mat4 M = transpose(m.viewProj); // rows of viewProj as columns
    vec4 planes[6] = vec4[6](M[3] + M[0], M[3] - M[0], M[3] + M[1], M[3] - M[1], M[2], M[3] - M[2]);
    for (uint k = 0u; k < 6u; ++k) {
        vec3 n = planes[k].xyz;
        vec3 far = vec3(n.x >= 0.0 ? c.hi.x : c.lo.x, n.y >= 0.0 ? c.hi.y : c.lo.y, n.z >= 0.0 ? c.hi.z : c.lo.z);
        if (dot(n, far) + planes[k].w < 0.0) return;
    }
    // Projected bounds: NDC rectangle of the 8 corners; a corner behind the light covers the whole map.
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    bool behind = false;
    for (uint k = 0u; k < 8u; ++k) {
        vec3 p = vec3((k & 1u) != 0u ? c.hi.x : c.lo.x, (k & 2u) != 0u ? c.hi.y : c.lo.y, (k & 4u) != 0u ? c.hi.z : c.lo.z);
        vec4 clip = m.viewProj * vec4(p, 1.0);
        if (clip.w <= 1e-6) { behind = true; break; }
        lo = min(lo, clip.xy / clip.w);
        hi = max(hi, clip.xy / clip.w);
    }
    if (behind) { lo = vec2(-1.0); hi = vec2(1.0); }
    // One texel of slack at the finest page size: a triangle on the box's edge covers texel centres there.
    lo -= vec2(2.0 / float(vsm.options.z));
    hi += vec2(2.0 / float(vsm.options.z));

    for (uint mip = 0u; mip < vsm.page.w; ++mip) {
        if ((mipsDirty & (1u << mip)) == 0u) continue;
        int side = int(vsm.page.z >> mip);
        ivec2 p0 = clamp(ivec2(floor((lo * 0.5 + 0.5) * float(side))), ivec2(0), ivec2(side - 1));
        ivec2 p1 = clamp(ivec2(floor((hi * 0.5 + 0.5) * float(side))), ivec2(0), ivec2(side - 1));
        uint level = 0u;
        while ((p1.x >> level) - (p0.x >> level) > 1 || (p1.y >> level) - (p0.y >> level) > 1) ++level;
        bool any = false;
        for (int y = p0.y >> level; y <= (p1.y >> level) && !any; ++y)
            for (int x = p0.x >> level; x <= (p1.x >> level) && !any; ++x)
                any = dirtyCell(map, mip, level, uint(x), uint(y));
        if (!any) {
            atomicAdd(vsmCounters.instancesCulledHpb, 1u);
            continue;
        }
        uint slot = atomicAdd(drawCounts[mip], 1u);
        if (slot >= maxDraws) {
            atomicAdd(vsmCounters.drawOverflow, 1u);
            continue;
        }
        uint d = mip * maxDraws + slot;
        draws[d * 5u + 0u] = c.draw.x; // index count
        draws[d * 5u + 1u] = 1u;       // instance count
        draws[d * 5u + 2u] = c.draw.y; // first index
        draws[d * 5u + 3u] = c.draw.z; // vertex offset
        draws[d * 5u + 4u] = d;        // first instance: this draw's drawInfo
        drawInfo[d] = uvec2(instance, map);
        atomicAdd(vsmCounters.instancesDrawn, 1u);
    }
}
