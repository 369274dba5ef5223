// Declarations shared by vsm_draw.task and vsm_draw.mesh (one graphics program with vsm_draw.frag, whose
// bindings and push constant `mip` these keep). The mesh-path program's bindings: vsm_bindings.h
// (ML_VSM_DRAW_*).
#ifndef ML_VSM_DRAW_MESH_COMMON_GLSL
#define ML_VSM_DRAW_MESH_COMMON_GLSL
#include "shadows/virtual/vsm_bindings.h"

layout(binding = ML_VSM_DRAW_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_DRAW_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(binding = ML_VSM_DRAW_COUNTERS, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = ML_VSM_DRAW_MESHLETS, std430) readonly buffer Meshlets { GpuMeshlet meshlets[]; };
layout(push_constant) uniform Push { VsmDrawPush push; };

// What a task workgroup hands its mesh workgroups: one (instance, map, meshlet, flags: bit 0 back faces
// culled, bit 1 dynamic caster) per survivor,
// and per mesh workgroup the survivor (bits 24..31) and the page it is clipped to (bits 0..23,
// vsm_page_clip.glsl; ML_VSM_PAGE_NONE: unclipped).
struct VsmTaskPayload {
    uvec4 entries[ML_VSM_TASK_GROUP];
    uint pages[ML_VSM_TASK_PAGES];
};

#endif
