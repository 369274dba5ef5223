#version 460
#extension GL_GOOGLE_include_directive : require
// The one evaluation pass: per pixel, every light of its cluster: visibility (static bake x dynamic
// virtual shadow map) x shading, accumulated in HDR, tone-mapped to the output. Per-pixel light counts
// are a pass of their own (statistics.comp), so this pass times only the frame's work.
// CPU reference: shaders/shared/shading.h compiled for the CPU over the same cluster lists
// (GpuEvaluate.SampledPixelsMatchCpuShading, without shadows) and the static and VSM lookups' own CPU
// twins (shadows/static/static_visibility.cpp, shadows/virtual/vsm_reference.cpp); a host pass built
// from the same include reproduces this image bit for bit (HostShader.*).
// The lookups (cluster list, static x dynamic visibility) are lights/manylights_lights.glsl's, the
// include a host's own shaders use: its 12 buffers take bindings 0-11, the G-buffer and outputs follow.
#include "lights/manylights_lights.glsl"

layout(local_size_x = ML_EVAL_GROUP, local_size_y = ML_EVAL_GROUP) in;
// 0: HDR and the tone-mapped sRGB output; 1: HDR only (the host tone-maps); 2: tone-mapped only
// (lights/evaluate_pass.h, EvaluateOutputs).
layout(constant_id = 0) const uint kSpecOutput = 0;

// The G-buffer (SHADER_READ_ONLY_OPTIMAL): reversed-Z depth (0 = sky), world normal as stored (unit
// up to half-float rounding; the VSM lookup normalises it itself), linear albedo. The outputs (GENERAL)
// are written whole: HDR radiance before exposure, and the exposed, tone-mapped sRGB values.
layout(binding = ML_HOST_BINDING_COUNT + 0) uniform texture2D depthImage;
layout(binding = ML_HOST_BINDING_COUNT + 1) uniform texture2D normalImage;
layout(binding = ML_HOST_BINDING_COUNT + 2) uniform texture2D albedoImage;
layout(binding = ML_HOST_BINDING_COUNT + 3, rgba16f) uniform writeonly image2D hdrImage;
layout(binding = ML_HOST_BINDING_COUNT + 4, rgba8) uniform writeonly image2D outputImage;

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= frame.size.x || px.y >= frame.size.y) return;
    float d = texelFetch(depthImage, ivec2(px), 0).r;
    vec3 hdr = frame.sky.rgb;
    if (hasSurface(d)) {
        vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
        vec3 Nraw = texelFetch(normalImage, ivec2(px), 0).xyz;
        vec3 N = normalize(Nraw);
        vec3 albedo = texelFetch(albedoImage, ivec2(px), 0).rgb;
        vec3 V = normalize(frame.cameraPosition.xyz - P);
        hdr = albedo * frame.ambient.rgb;
        // The host include's loop (a host forward pass writes the same lines).
        uvec2 range = mlClusterRange(px, d);
        for (uint i = 0; i < mlRangeCount(range); ++i) {
            GpuLight L = mlRangeLight(range, i);
            vec3 c = shadeLight(L, P, N, V, albedo);
            if (c != vec3(0.0)) hdr += c * mlLightVisibility(L, P, Nraw);
        }
    }
    if (kSpecOutput != 2u) imageStore(hdrImage, ivec2(px), vec4(hdr, 1.0));
    if (kSpecOutput != 1u) imageStore(outputImage, ivec2(px), vec4(toneMap(hdr * frame.ambient.w), 1.0));
}
