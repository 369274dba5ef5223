#version 460
#extension GL_GOOGLE_include_directive : require
// vsm_draw: casters into the pages of one mip (viewport = the mip's virtual resolution), one
// indirect-count draw per mip. The draw's firstInstance indexes drawInfo (instance, map). The world
// position is computed with vsmPoint, the same operation order as the CPU reference's casters, so both
// rasterise the same vertices.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_math.h"

layout(binding = 0, std430) readonly buffer Vertices { GpuVertex vertices[]; };
layout(binding = 1, std430) readonly buffer Instances { GpuInstance instances[]; };
layout(binding = 2, std430) readonly buffer DrawInfo { uvec2 drawInfo[]; };
layout(binding = 3, std430) readonly buffer Maps { GpuVsmMap vsmMaps[]; };

layout(location = 0) out float outDepth;
layout(location = 1) flat out uint outMap;

void main() {
    GpuVertex v = vertices[gl_VertexIndex];
    uvec2 info = drawInfo[gl_InstanceIndex];
    GpuVsmMap m = vsmMaps[info.y];
    vec3 world = vsmPoint(instances[info.x].model, vec3(v.px, v.py, v.pz));
    outDepth = -vsmPoint(m.view, world).z;
    outMap = info.y;
    gl_Position = m.viewProj * vec4(world, 1.0);
}
