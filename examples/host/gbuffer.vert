#version 460
// The host's G-buffer: world-space vertices (the example's meshes are placed in world space), one
// push block per draw.
layout(push_constant) uniform Draw { mat4 viewProj; vec4 albedo; } draw;
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 0) out vec3 outNormal;

void main() {
    outNormal = normal;
    gl_Position = draw.viewProj * vec4(position, 1.0);
}
