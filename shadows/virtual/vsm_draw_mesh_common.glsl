// Declarations shared by vsm_draw.task and vsm_draw.mesh (one graphics program with vsm_draw.frag, whose
// bindings 3..7 and push constant `mip` these keep). Binding map of the mesh-path program:
//   0 vertices, 1 instances, 2 meshlet-instance lists, 3 maps, 4 constants, 5 page table, 6 pool (frag),
//   7 counters, 8 meshlet vertices, 9 meshlet triangles, 10 HPB, 11 per-mip task counts, 12 meshlets.
#ifndef ML_VSM_DRAW_MESH_COMMON_GLSL
#define ML_VSM_DRAW_MESH_COMMON_GLSL

layout(binding = 3, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = 4) uniform VsmConst { VsmConstants vsm; };
layout(binding = 7, std430) buffer Counters { VsmCounters vsmCounters; };
layout(binding = 12, std430) readonly buffer Meshlets { GpuMeshlet meshlets[]; };
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
