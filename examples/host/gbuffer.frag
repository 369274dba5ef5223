#version 460
// What manylights reads (manylights/module.h HostTargets): world normal in RGBA16F, linear albedo in RGBA8.
layout(push_constant) uniform Draw { mat4 viewProjModel; vec4 albedo; } draw;
layout(location = 0) in vec3 inNormal;
layout(location = 0) out vec4 outNormal;
layout(location = 1) out vec4 outAlbedo;

void main() {
    outNormal = vec4(normalize(inNormal), 1.0);
    outAlbedo = vec4(draw.albedo.rgb, 1.0);
}
