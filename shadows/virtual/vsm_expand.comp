#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_expand (culling 3/3 of the mesh path; work expansion, RMVSM section 4 and Fig. 8): one workgroup
// per (caster group, map with a dirty page) pair that vsm_pairs left, one thread per caster of the group
// (indirect). For each dirty mip of the map, the caster passes the same tests as in vsm_cull.comp
// (frustum, HPB at the level where its projected box spans at most 2x2 cells); a surviving caster's
// meshlets are appended to the mip's meshlet-instance list (instance, map | dynamic bit << 31,
// meshlet | cone bit << 31),
// and the mip's task-workgroup count (one VkDrawMeshTasksIndirectCommandEXT per mip, 32 meshlets per
// workgroup) is raised to cover them. Directional clip levels use mip 0, so they share the mip-0 list.
// The cone bit allows the task shader's back-facing test: the mesh is closed and the box lies wholly in
// front of the map's near plane (the light outside it, and no front face clipped where a back face is not).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_math.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_CULL_GROUP) in;

layout(binding = ML_VSM_EXPAND_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_EXPAND_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_EXPAND_PAIRS, std430) readonly buffer Pairs { uvec2 vsmPairs[]; }; // vsm_pairs: (group, map)
layout(binding = ML_VSM_EXPAND_TABLE, std430) readonly buffer Table { uint vsmTable[]; };
layout(binding = ML_VSM_EXPAND_HPB, std430) readonly buffer Hpb { uint vsmHpb[]; }; // every level (vsm_math.h)
layout(binding = ML_VSM_EXPAND_CASTERS, std430) readonly buffer Casters { GpuCaster casters[]; };
layout(binding = ML_VSM_EXPAND_DIRTY_MIPS, std430) readonly buffer MapMips { uint vsmDirtyMips[]; };
layout(binding = ML_VSM_EXPAND_MESHLET_LIST, std430) writeonly buffer List { uint meshletList[]; }; // 3 words per entry, per mip
layout(binding = ML_VSM_EXPAND_MESH_TASKS, std430) buffer Tasks { uint meshTasks[]; };            // per mip: x, y, z groups, count
layout(binding = ML_VSM_EXPAND_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_EXPAND_ORDER, std430) readonly buffer Order { uint vsmCasterOrder[]; }; // workgroup's casters
layout(push_constant) uniform Push { VsmCullPush push; }; // capacity: meshlet entries per mip

#include "shadows/virtual/vsm_cull_common.glsl"

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
    uint n = c.meshlets.y;
    if (c.draw.x == 0u || n == 0u) return;
    uint dirtyCount = bitCount(mipsDirty);
    atomicAdd(vsmCounters.meshletsTotal, n * dirtyCount);

    vec4 planes[6];
    vsmFrustumPlanes(m.viewProj, planes);
    if (!vsmBoxInFrustum(planes, c.lo.xyz, c.hi.xyz)) {
        atomicAdd(vsmCounters.meshletsCulledFrustum, n * dirtyCount);
        return;
    }
    vec2 lo, hi;
    vsmProjectedBounds(m.viewProj, c.lo.xyz, c.hi.xyz, lo, hi);

    uint cone = vsmClosedInFront(m, c) ? 1u << 31 : 0u;

    for (uint mip = 0u; mip < vsm.page.w; ++mip) {
        if ((mipsDirty & (1u << mip)) == 0u) continue;
        if (!vsmHpbAny(map, mip, lo, hi)) {
            atomicAdd(vsmCounters.instancesCulledHpb, 1u);
            atomicAdd(vsmCounters.meshletsCulledHpb, n);
            continue;
        }
        atomicAdd(vsmCounters.instancesDrawn, 1u);
        uint base = atomicAdd(meshTasks[mip * 4u + 3u], n);
        uint end = min(base + n, push.capacity);
        if (base + n > end) atomicAdd(vsmCounters.meshletOverflow, base + n - max(end, base));
        if (end <= base) continue;
        atomicAdd(vsmCounters.meshletsAfterExpansion, end - base);
        atomicMax(meshTasks[mip * 4u], (end + ML_VSM_TASK_GROUP - 1u) / ML_VSM_TASK_GROUP);
        meshTasks[mip * 4u + 1u] = 1u; // y, z: one row of workgroups (zero when nothing was appended)
        meshTasks[mip * 4u + 2u] = 1u;
        for (uint i = base; i < end; ++i) {
            uint e = (mip * push.capacity + i) * 3u;
            meshletList[e + 0u] = instance;
            meshletList[e + 1u] = map | (c.draw.w != 0u ? 1u << 31 : 0u); // dynamic: the task's page test
            meshletList[e + 2u] = (c.meshlets.x + i - base) | cone;
        }
    }
}
