#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_draw: a caster into one dirty page of one mip (viewport = the mip's virtual resolution, the
// triangles clipped to the page: vsm_page_clip.glsl), one indirect-count draw list per mip. The draw's
// firstInstance indexes drawInfo (instance, map, page, 1 when the caster is dynamic). The world position is computed with vsmPoint,
// the same operation order as the CPU reference's casters, so both rasterise the same vertices.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_math.h"
#include "shadows/virtual/vsm_bindings.h"

layout(binding = ML_VSM_DRAW_VERTICES, std430) readonly buffer Vertices { GpuVertex vertices[]; };
layout(binding = ML_VSM_DRAW_INSTANCES, std430) readonly buffer Instances { GpuInstance instances[]; };
layout(binding = ML_VSM_DRAW_DRAW_INFO, std430) readonly buffer DrawInfo { uvec4 drawInfo[]; };
layout(binding = ML_VSM_DRAW_MAPS, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };
layout(binding = ML_VSM_DRAW_CONSTANTS) uniform VsmConst { VsmConstants vsm; };
layout(push_constant) uniform Push { VsmDrawPush push; };

#include "shadows/virtual/vsm_page_clip.glsl"

layout(location = 0) out float outDepth;
layout(location = 1) flat out uint outMap;
out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[4];
};

void main() {
    GpuVertex v = vertices[gl_VertexIndex];
    uvec4 info = drawInfo[gl_InstanceIndex];
    GpuVsmMap m = vsmMaps[info.y];
    vec3 world = vsmPoint(instances[info.x].model, vec3(v.px, v.py, v.pz));
    outDepth = -vsmPoint(m.view, world).z;
    outMap = info.y | (info.w << 31u); // the fragment shader's static-layer test
    vec4 p = m.viewProj * vec4(world, 1.0);
    gl_Position = p;
    vec4 d = vsmPageClip(p, info.z, push.mip);
    gl_ClipDistance[0] = d.x;
    gl_ClipDistance[1] = d.y;
    gl_ClipDistance[2] = d.z;
    gl_ClipDistance[3] = d.w;
}
