#version 460
#extension GL_GOOGLE_include_directive : require
// A host engine's own pass in a compute shader, written only against the installed include and its
// binding contract (HostShader.ForwardPassMatchesEvaluation): compiled with -I<build>/installed_include
// (the staged copy `cmake --install` installs), never with the source tree on its path. The module's
// buffers are the host's descriptor set 1 (a set of its own, not the module's push descriptors); the
// host's G-buffer and outputs set 0. host_forward.frag is the same pass in a fragment shader.
#define ML_LIGHTS_SET 1
#define ML_LIGHTS_BINDING 0
#include "manylights/manylights.glsl"
#include "host_shade.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// The host's own resources, set 0.
layout(set = 0, binding = 0) uniform texture2D hostDepth;  // reversed Z of Module::viewProjection()
layout(set = 0, binding = 1) uniform texture2D hostNormal; // world normal as stored
layout(set = 0, binding = 2) uniform texture2D hostAlbedo;
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D hostRadiance; // linear HDR
layout(set = 0, binding = 4, std430) writeonly buffer HostCounts { uvec4 counts[]; }; // hostShade's n

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    uvec2 size = frame.size.xy;
    if (px.x >= size.x || px.y >= size.y) return;
    float d = texelFetch(hostDepth, ivec2(px), 0).r;
    vec3 Nraw = texelFetch(hostNormal, ivec2(px), 0).xyz;
    vec3 albedo = texelFetch(hostAlbedo, ivec2(px), 0).rgb;
    uvec4 n;
    vec3 radiance = hostShade(px, d, Nraw, albedo, n);
    imageStore(hostRadiance, ivec2(px), vec4(radiance, 1.0));
    counts[px.y * size.x + px.x] = n;
}
