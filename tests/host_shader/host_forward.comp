#version 460
#extension GL_GOOGLE_include_directive : require
// A host engine's own forward pass, written only against the installed include and its binding
// contract (HostShader.ForwardPassMatchesEvaluation): compiled with -I<build>/installed_include (the
// staged copy `cmake --install` installs), never with the source tree on its path. Per pixel of the
// host's G-buffer: ambient, then every light of the pixel's cluster, shaded with the module's BRDF
// and multiplied by the module's static x dynamic visibility: what the evaluation pass computes, so
// the test compares the two images. The module's buffers are the host's descriptor set 1 (a set of
// its own, not the module's push descriptors).
#define ML_LIGHTS_SET 1
#define ML_LIGHTS_BINDING 0
#include "manylights/manylights.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// The host's own resources, set 0.
layout(set = 0, binding = 0) uniform texture2D hostDepth;  // reversed Z of Module::viewProjection()
layout(set = 0, binding = 1) uniform texture2D hostNormal; // world normal as stored
layout(set = 0, binding = 2) uniform texture2D hostAlbedo;
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D hostRadiance; // linear HDR
// Per pixel: lights in the cluster list, lights shaded (non-zero BRDF), of those the ones with
// visibility < 1, and the ones with a virtual shadow map: the test checks that shadows were looked up.
layout(set = 0, binding = 4, std430) writeonly buffer HostCounts { uvec4 counts[]; };

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    uvec2 size = frame.size.xy;
    if (px.x >= size.x || px.y >= size.y) return;
    float d = texelFetch(hostDepth, ivec2(px), 0).r;
    vec3 radiance = frame.sky.rgb;
    uvec4 n = uvec4(0u);
    if (hasSurface(d)) {
        vec3 P = mlWorldPosition(px, d);
        vec3 Nraw = texelFetch(hostNormal, ivec2(px), 0).xyz;
        vec3 N = normalize(Nraw);
        vec3 albedo = texelFetch(hostAlbedo, ivec2(px), 0).rgb;
        vec3 V = normalize(mlCameraPosition() - P);
        radiance = albedo * frame.ambient.rgb;
        // (a) for each light of the cluster at this pixel and depth
        uvec2 range = mlClusterRange(px, d);
        n.x = mlRangeCount(range);
        for (uint i = 0; i < mlRangeCount(range); ++i) {
            GpuLight L = mlRangeLight(range, i);
            vec3 c = shadeLight(L, P, N, V, albedo);
            if (c == vec3(0.0)) continue;
            // (b) static x dynamic shadow visibility of light L at P with normal N
            float v = mlLightVisibility(L, P, Nraw);
            radiance += c * v;
            n.y += 1u;
            if (v < 1.0) n.z += 1u;
            if (L.info.y != ML_VSM_NO_MAP) n.w += 1u;
        }
    }
    imageStore(hostRadiance, ivec2(px), vec4(radiance, 1.0));
    counts[px.y * size.x + px.x] = n;
}
