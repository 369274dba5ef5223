#version 460
#extension GL_GOOGLE_include_directive : require
// G-buffer vertices: pulled from storage buffers (no vertex input state); the draw's firstInstance is
// the instance index, so one indirect multi-draw renders every instance.
#include "shaders/shared/glsl_common.glsl"
#include "engine/gbuffer_bindings.h"


layout(binding = ML_GBUFFER_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_GBUFFER_VERTICES, std430) readonly buffer Vertices { GpuVertex vertices[]; };
layout(binding = ML_GBUFFER_INSTANCES, std430) readonly buffer Instances { GpuInstance instances[]; };

layout(location = 0) out vec3 outNormal;
layout(location = 1) out vec3 outAlbedo;
layout(location = 2) flat out vec3 outMaterial; // roughness, metalness, receiver flag (GpuInstance.material)

void main() {
    GpuVertex v = vertices[gl_VertexIndex];
    GpuInstance inst = instances[gl_InstanceIndex];
    vec4 world = inst.model * vec4(v.px, v.py, v.pz, 1.0);
    outNormal = mat3(inst.normalMatrix) * vec3(v.nx, v.ny, v.nz);
    outAlbedo = inst.albedo.rgb;
    outMaterial = inst.material.xyz;
    gl_Position = frame.viewProj * world;
}
