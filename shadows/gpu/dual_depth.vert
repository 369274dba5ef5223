#version 460
#extension GL_GOOGLE_include_directive : require
// Dual depth bake (shadows/gpu/dual_depth_gpu.h): world-space caster triangles pulled from a storage
// buffer (4 floats per vertex, w = 1 for triangles of closed meshes), projected by the light's tile
// matrix; the view-space depth goes to the fragment shader for the integer depth.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/gpu/dual_depth_push.h"

layout(binding = ML_DUAL_DEPTH_VERTICES, std430) readonly buffer Vertices { vec4 vertices[]; };
layout(push_constant) uniform Push { DualDepthPush push; };
layout(location = 0) out float outDepth;
layout(location = 1) flat out uint outClosed;

void main() {
    vec4 v = vertices[gl_VertexIndex];
    vec4 world = vec4(v.xyz, 1.0);
    outDepth = -(push.view * world).z;
    outClosed = v.w > 0.5 ? 1u : 0u;
    gl_Position = push.viewProj * world;
}
