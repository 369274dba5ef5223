#version 460
#extension GL_GOOGLE_include_directive : require
// The host pass of host_forward.comp in a fragment shader (HostShader.FragmentPassMatchesEvaluation): a
// full-screen triangle over the host's G-buffer, one fragment per pixel, so the module's buffers are
// read in the fragment stage (record()'s contract: its writes visible to fragment and compute reads).
// Compiled against the staged install tree only. The module's buffers are set 1, the host's set 0.
#define ML_LIGHTS_SET 1
#define ML_LIGHTS_BINDING 0
#include "manylights/manylights.glsl"
#include "host_shade.glsl"

layout(set = 0, binding = 0) uniform texture2D hostDepth;
layout(set = 0, binding = 1) uniform texture2D hostNormal;
layout(set = 0, binding = 2) uniform texture2D hostAlbedo;
layout(set = 0, binding = 4, std430) writeonly buffer HostCounts { uvec4 counts[]; };
layout(location = 0) out vec4 hostRadiance; // RGBA16F colour attachment, linear HDR

void main() {
    uvec2 px = uvec2(gl_FragCoord.xy);
    float d = texelFetch(hostDepth, ivec2(px), 0).r;
    vec3 Nraw = texelFetch(hostNormal, ivec2(px), 0).xyz;
    vec3 albedo = texelFetch(hostAlbedo, ivec2(px), 0).rgb;
    uvec4 n;
    hostRadiance = vec4(hostShade(px, d, Nraw, albedo, n), 1.0);
    counts[px.y * frame.size.x + px.x] = n;
}
