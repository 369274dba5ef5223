#version 460
// The host's G-buffer: one push block per draw, its view-projection times the mesh's model matrix (the
// ground and static box are placed in world space, the moving box is translated: normals unchanged).
layout(push_constant) uniform Draw { mat4 viewProjModel; vec4 albedo; } draw;
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 0) out vec3 outNormal;

void main() {
    outNormal = normal;
    gl_Position = draw.viewProjModel * vec4(position, 1.0);
}
