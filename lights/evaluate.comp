#version 460
#extension GL_GOOGLE_include_directive : require
#ifdef ML_WAVE_LOOP
// The build with the wave-uniform loop (evaluate_wave, CMakeLists.txt); the plain build is the
// fallback for devices without subgroup arithmetic in compute (lights/evaluate_pass.cpp checks).
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif
// The one evaluation pass: per pixel, every light of its cluster: visibility (static bake x dynamic
// virtual shadow map) x shading, accumulated in HDR, tone-mapped to the output. Per-pixel light counts
// are a pass of their own (statistics.comp), so this pass times only the frame's work.
// CPU reference: shaders/shared/shading.h compiled for the CPU over the same cluster lists
// (GpuEvaluate.SampledPixelsMatchCpuShading, without shadows) and the static and VSM lookups' own CPU
// twins (shadows/static/static_visibility.cpp, shadows/virtual/vsm_reference.cpp); a host pass built
// from the same include reproduces this image bit for bit (HostShader.*).
// The lookups (cluster list, static x dynamic visibility) are lights/manylights_lights.glsl's, the
// include a host's own shaders use: its 12 buffers take bindings 0-11 (ML_LIGHTS_BINDING left at 0, so
// they are the ML_HOST_* numbers the C++ binds by), the G-buffer and outputs follow
// (lights/evaluate_bindings.h).
#include "lights/manylights_lights.glsl"
#include "lights/evaluate_bindings.h"
#if ML_LIGHTS_BINDING != 0
#error "the evaluation binds its buffers at the ML_HOST_* numbers themselves"
#endif
#include "shaders/shared/brdf.h"

layout(local_size_x = ML_EVAL_GROUP, local_size_y = ML_EVAL_GROUP) in;
// 0: HDR and the tone-mapped sRGB output; 1: HDR only (the host tone-maps); 2: tone-mapped only
// (lights/evaluate_pass.h, EvaluateOutputs).
layout(constant_id = 0) const uint kSpecOutput = 0;
// 1: GGX from the material target (binding ML_EVAL_MATERIAL, shaders/shared/brdf.h);
// 0: Lambert + Blinn-Phong (shading.h), that binding unread.
layout(constant_id = 1) const uint kSpecPbr = 0;
// 1: the wave-uniform light loop. Cluster lists are sorted by light index (culling/culling.h), so a
// subgroup walks the union of its lanes' lists in increasing order: next = subgroupMin of each lane's
// next light (~0 when done); the lanes whose list holds it shade it and advance. The light index is
// subgroup-uniform, so the lanes shading together shade the same light (its GpuLight, shadow record
// and map are one address for the subgroup, not a gather).
// Each lane still adds its own lights in list order: the image is bit-identical to the per-lane
// loop (0; GpuEvaluate.UniformLoopIsBitIdentical).
#ifdef ML_WAVE_LOOP
layout(constant_id = 2) const uint kUniformLoop = 0; // the host sets it (EvaluatePass::setUniformLoop)
#else
const uint kUniformLoop = 0;
#endif

// The G-buffer (SHADER_READ_ONLY_OPTIMAL): reversed-Z depth (0 = sky), world normal as stored (unit
// up to half-float rounding; the VSM lookup normalises it itself), linear albedo. The outputs (GENERAL)
// are written whole: HDR radiance before exposure, and the exposed, tone-mapped sRGB values.
layout(binding = ML_EVAL_DEPTH) uniform texture2D depthImage;
layout(binding = ML_EVAL_NORMAL) uniform texture2D normalImage;
layout(binding = ML_EVAL_ALBEDO) uniform texture2D albedoImage;
layout(binding = ML_EVAL_HDR, rgba16f) uniform writeonly image2D hdrImage;
layout(binding = ML_EVAL_OUTPUT, rgba8) uniform writeonly image2D outputImage;
// The optional material target: r perceptual roughness, g metalness (read only when kSpecPbr is 1).
layout(binding = ML_EVAL_MATERIAL) uniform texture2D materialImage;

// Light L's contribution at the pixel, added to hdr (the same lines in both loops).
void addLight(GpuLight L, vec3 P, vec3 N, vec3 Nraw, vec3 V, vec3 albedo, vec2 material, bool receiver,
              inout vec3 hdr) {
    vec3 c = kSpecPbr != 0u ? shadeLightPbr(L, P, N, V, albedo, material.x, material.y)
                            : shadeLight(L, P, N, V, albedo);
    if (c != vec3(0.0)) hdr += receiver ? c * mlLightVisibility(L, P, Nraw) : c;
}

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= frame.size.x || px.y >= frame.size.y) return;
    float d = texelFetch(depthImage, ivec2(px), 0).r;
    vec3 hdr = frame.sky.rgb;
    if (hasSurface(d)) {
        vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
        vec4 normalTexel = texelFetch(normalImage, ivec2(px), 0);
        vec3 Nraw = normalTexel.xyz;
        vec3 N = normalize(Nraw);
        bool receiver = normalTexel.w >= 0.0; // ML_NOT_A_RECEIVER (-1): lit unshadowed
        vec2 material = kSpecPbr != 0u ? texelFetch(materialImage, ivec2(px), 0).rg : vec2(0.0);
        vec3 albedo = texelFetch(albedoImage, ivec2(px), 0).rgb;
        vec3 V = normalize(frame.cameraPosition.xyz - P);
        hdr = albedo * frame.ambient.rgb;
        uvec2 range = mlClusterRange(px, d);
        uint n = mlRangeCount(range);
#ifdef ML_WAVE_LOOP
        if (kUniformLoop != 0u) {
            const uint kDone = 0xFFFFFFFFu; // past every light index (ML_MAX_LIGHTS)
            uint i = 0;
            uint mine = n > 0u ? ML_CLUSTER_LIGHT(range, 0u) : kDone;
            for (;;) {
                uint next = subgroupMin(mine); // over the lanes with a surface (the others left)
                if (next == kDone) break;
                if (mine == next) {
                    addLight(lights[next], P, N, Nraw, V, albedo, material, receiver, hdr);
                    ++i;
                    mine = i < n ? ML_CLUSTER_LIGHT(range, i) : kDone;
                }
            }
        } else
#endif
        {
            // The host include's loop (a host forward pass writes the same lines).
            for (uint i = 0; i < n; ++i)
                addLight(mlRangeLight(range, i), P, N, Nraw, V, albedo, material, receiver, hdr);
        }
    }
    if (kSpecOutput != 2u) imageStore(hdrImage, ivec2(px), vec4(hdr, 1.0));
    if (kSpecOutput != 1u) imageStore(outputImage, ivec2(px), vec4(toneMap(hdr * frame.ambient.w), 1.0));
}
