#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_cull (culling 3/3; work expansion at the instance level, RMVSM section 4.3): one workgroup per
// (caster group, map with a dirty page) pair that vsm_pairs left, one thread per caster of the group
// (indirect: cached maps and groups outside a map's frustum launch nothing). A caster is drawn into mip
// m of a map when m has dirty pages, its world box is inside the
// map's frustum (range = the far plane), and the hierarchical page buffer has a dirty cell under its
// projected bounds at the level where those bounds span at most 2x2 cells. Maps of lights with a
// static bake take dynamic casters only. Draws go to two lists per mip, closed and open casters (one
// indirect-count draw each, the closed list with back faces culled):
// one draw per dirty page under the projected bounds, clipped to that page (vsm_page_clip.glsl); a
// static caster skips pages redrawn from their static twin (vsmPageDrawn).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_math.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_CULL_GROUP) in;

layout(binding = ML_VSM_CULL_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_CULL_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_CULL_PAIRS, std430) readonly buffer Pairs { uvec2 vsmPairs[]; }; // vsm_pairs: (group, map)
layout(binding = ML_VSM_CULL_TABLE, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_CULL_HPB, std430) readonly buffer Hpb { uint vsmHpb[]; }; // every level (vsm_math.h)
layout(binding = ML_VSM_CULL_CASTERS, std430) readonly buffer Casters { GpuCaster casters[]; };
layout(binding = ML_VSM_CULL_DIRTY_MIPS, std430) readonly buffer MapMips { uint vsmDirtyMips[]; };
layout(binding = ML_VSM_CULL_DRAWS, std430) writeonly buffer Draws { uint draws[]; }; // VkDrawIndexedIndirectCommand
layout(binding = ML_VSM_CULL_DRAW_INFO, std430) writeonly buffer DrawInfo { uvec4 drawInfo[]; }; // (instance, map, page, 0)
layout(binding = ML_VSM_CULL_DRAW_COUNTS, std430) buffer DrawCounts { uint drawCounts[]; };      // per mip
layout(binding = ML_VSM_CULL_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_CULL_ORDER, std430) readonly buffer Order { uint vsmCasterOrder[]; }; // workgroup's casters
layout(push_constant) uniform Push { VsmCullPush push; }; // capacity: draws per mip

#include "shadows/virtual/vsm_cull_common.glsl"
#include "shadows/virtual/vsm_page_clip.glsl"

void main() {
    // One workgroup per (caster group, map) pair vsm_pairs left (rows of at most 65535 workgroups).
    uint pair = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (pair >= vsmCounters.pairCount) return;
    uint position = vsmPairs[pair].x * ML_VSM_CULL_GROUP + gl_LocalInvocationIndex;
    uint map = vsmPairs[pair].y;
    if (position >= push.casterCount) return;
    uint instance = vsmCasterOrder[position];
    uint mipsDirty = vsmDirtyMips[map];
    GpuVsmMap m = vsmMaps[map];
    GpuCaster c = casters[instance];
    if ((m.info.y & ML_VSM_MAP_DYNAMIC_ONLY) != 0u && c.draw.w == 0u) return;
    if (c.draw.x == 0u) return;

    // Frustum (the far plane is the light's range), then the projected bounds for the HPB test.
    vec4 planes[6];
    vsmFrustumPlanes(m.viewProj, planes);
    if (!vsmBoxInFrustum(planes, c.lo.xyz, c.hi.xyz)) return;
    vec2 lo, hi;
    vsmProjectedBounds(m.viewProj, c.lo.xyz, c.hi.xyz, lo, hi);
    bool closedInFront = vsmClosedInFront(m, c);
    bool dynamicCaster = c.draw.w != 0u;

    for (uint mip = 0u; mip < vsm.page.w; ++mip) {
        if ((mipsDirty & (1u << mip)) == 0u) continue;
        bool any = vsmHpbAny(map, mip, lo, hi);
        if (!any) {
            atomicAdd(vsmCounters.instancesCulledHpb, 1u);
            continue;
        }
        // The dirty pages under the bounds (at least one unless the HPB cell's dirty page lies beside
        // them): count, reserve that many draws at once, then write them.
        ivec2 p0, p1;
        vsmPageRect(mip, lo, hi, p0, p1);
        bool clip = vsm.camera.y != 0.0;
        if (!clip) p1 = p0; // one unclipped draw over the whole mip (VsmSettings::pageClip off)
        uint n = clip ? 0u : 1u;
        for (int y = p0.y; y <= p1.y; ++y)
            for (int x = p0.x; x <= p1.x; ++x)
                if (clip && vsmPageDrawn(map, mip, x, y, dynamicCaster)) ++n;
        // Counted per (instance, map, mip) as vsm_expand counts the mesh path's, whatever the pages.
        atomicAdd(vsmCounters.instancesDrawn, 1u);
        if (n == 0u) continue;
        // Closed casters in front of the near plane go to list 0, drawn with back faces culled (the
        // nearest surface along any ray from the light faces it: the same depths); the rest to list 1.
        uint list = closedInFront ? 0u : 1u;
        uint slot = atomicAdd(drawCounts[list * ML_VSM_MAX_MIPS + mip], n);
        if (slot + n > push.capacity) atomicAdd(vsmCounters.drawOverflow, slot + n - max(slot, push.capacity));
        uint written = 0u;
        for (int y = p0.y; y <= p1.y; ++y)
            for (int x = p0.x; x <= p1.x; ++x) {
                if (clip && !vsmPageDrawn(map, mip, x, y, dynamicCaster)) continue;
                if (slot >= push.capacity) break;
                uint d = (list * vsm.page.w + mip) * push.capacity + slot;
                draws[d * 5u + 0u] = c.draw.x; // index count
                draws[d * 5u + 1u] = 1u;       // instance count
                draws[d * 5u + 2u] = c.draw.y; // first index
                draws[d * 5u + 3u] = c.draw.z; // vertex offset
                draws[d * 5u + 4u] = d;        // first instance: this draw's drawInfo
                drawInfo[d] = uvec4(instance, map, clip ? vsmPackPage(x, y) : ML_VSM_PAGE_NONE, c.draw.w);
                ++slot;
                ++written;
            }
        if (written == 0u) continue;
        atomicAdd(vsmCounters.trianglesRasterized, written * (c.draw.x / 3u)); // submitted: none culled
    }
}
