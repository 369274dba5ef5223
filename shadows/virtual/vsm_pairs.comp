#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_pairs (culling 2/3): which (caster group, map with a dirty page) pairs the culling visits.
//   mode 0, one thread per pair (x: group, y: the map's place in vsm_assign's dirty-map list): a pair
//     survives when the map takes some caster of the group and the group's box (vsm_groups.comp) is
//     inside the map's frustum (vsmGroupMayDraw); survivors are appended to the pair list. Every caster's
//     box lies inside its group's, so a refused group holds no caster the frustum would let through.
//   mode 1, one thread: the culling's indirect dispatch, one workgroup per pair, laid out in rows of
//     push.rowWorkgroups (at most 65535, the guaranteed maxComputeWorkGroupCount), at most 65535 rows;
//     pairs past the list's capacity or the rows are counted (pairOverflow), never silent.
// Before, vsm_cull / vsm_expand ran one invocation per (caster, dirty map): at 4096 night-city lights
// most of them read a caster and a map only to find the caster outside the frustum; now those pairs cost
// one test per 64 casters here, and the culling's workgroups are the pairs left.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_math.h"
#include "shadows/virtual/vsm_bindings.h"

layout(local_size_x = ML_VSM_CULL_GROUP) in;

layout(binding = ML_VSM_PAIRS_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_PAIRS_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_PAIRS_DIRTY_MAPS, std430) readonly buffer DirtyMaps { uint vsmDirtyMaps[]; }; // vsm_assign
layout(binding = ML_VSM_PAIRS_DIRTY_MIPS, std430) readonly buffer MapMips { uint vsmDirtyMips[]; };
layout(binding = ML_VSM_PAIRS_GROUPS, std430) readonly buffer Groups { GpuCasterGroup vsmCasterGroups[]; }; // vsm_groups
layout(binding = ML_VSM_PAIRS_PAIRS, std430) writeonly buffer Pairs { uvec2 vsmPairs[]; }; // (group, map)
layout(binding = ML_VSM_PAIRS_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(push_constant) uniform Push { VsmPairsPush push; };

#define VSM_NO_PAGES
#define VSM_CASTER_GROUPS
#include "shadows/virtual/vsm_cull_common.glsl"

void main() {
    if (push.mode == 1u) {
        if (gl_LocalInvocationIndex != 0u) return;
        // The pairs appended past the capacity were not stored; rows stop at 65535 (the guaranteed
        // maxComputeWorkGroupCount[1]). The culling reads pairCount as the pairs it may visit.
        uint n = vsmCounters.pairCount, stored = min(n, push.capacity);
        uint row = push.rowWorkgroups, rows = min((stored + row - 1u) / row, 65535u);
        uint fit = min(stored, rows * row);
        vsmCounters.pairOverflow = n - fit;
        vsmCounters.pairCount = fit;
        vsmCounters.pairGroupsX = min(fit, row);
        vsmCounters.pairGroupsY = rows;
        vsmCounters.pairGroupsZ = 1u;
        return;
    }
    uint group = gl_GlobalInvocationID.x; // indirect: cullGroupsX (the CPU), cullGroupsY (vsm_assign)
    if (group * ML_VSM_CULL_GROUP >= push.casterCount) return;
    uint map = vsmDirtyMaps[gl_GlobalInvocationID.y]; // indirect: y < maps with a dirty page
    uint refused;
    bool draws = vsmGroupMayDraw(map, group, refused);
    if (refused != 0u && push.countMeshlets != 0u) { // what each caster's own frustum test would count
        atomicAdd(vsmCounters.meshletsTotal, refused);
        atomicAdd(vsmCounters.meshletsCulledFrustum, refused);
    }
    if (!draws) return;
    uint slot = atomicAdd(vsmCounters.pairCount, 1u);
    if (slot < push.capacity) vsmPairs[slot] = uvec2(group, map); // past it: counted by mode 1
}
