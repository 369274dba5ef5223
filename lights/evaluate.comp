#version 460
#extension GL_GOOGLE_include_directive : require
// The one evaluation pass: per pixel, every light of its cluster: visibility (static bake x dynamic
// virtual shadow map) x shading, accumulated in HDR, tone-mapped to the output. Per-pixel light counts
// are a pass of their own (statistics.comp), so this pass times only the frame's work.
#include "shaders/shared/glsl_common.glsl"
#include "shadows/virtual/vsm_types.h"
#include "shaders/shared/brdf.h"

layout(local_size_x = ML_EVAL_GROUP, local_size_y = ML_EVAL_GROUP) in;
// 0: HDR and the tone-mapped sRGB output; 1: HDR only (the host tone-maps); 2: tone-mapped only
// (lights/evaluate_pass.h, EvaluateOutputs).
layout(constant_id = 0) const uint kSpecOutput = 0;
// 1: GGX from the material target (binding 17, shaders/shared/brdf.h); 0: Lambert + Blinn-Phong
// (shading.h), binding 17 unread.
layout(constant_id = 1) const uint kSpecPbr = 0;

layout(binding = 0) uniform Frame { FrameConstants frame; };
layout(binding = 1, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = 2, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = 3, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = 4, std430) readonly buffer Pool { uint pool[]; };
layout(binding = 5) uniform texture2D depthImage;
layout(binding = 6) uniform texture2D normalImage;
layout(binding = 7) uniform texture2D albedoImage;
layout(binding = 8, rgba16f) uniform writeonly image2D hdrImage;
layout(binding = 9, rgba8) uniform writeonly image2D outputImage;
layout(binding = 10, std430) readonly buffer StaticWords { uint staticWords[]; };
layout(binding = 11, std430) readonly buffer ShadowRecords { GpuShadowRecord shadowRecords[]; };
layout(binding = 12) uniform VsmConst { VsmConstants vsm; };
layout(binding = 13, std430) readonly buffer VsmMaps { GpuVsmMap vsmMaps[]; };
layout(binding = 14, std430) readonly buffer VsmCoverage { uint vsmCoverage[]; };
layout(binding = 15, std430) readonly buffer VsmTable { uint vsmTable[]; };
layout(binding = 16, std430) readonly buffer VsmPool { uint vsmPool[]; };
layout(binding = 17) uniform texture2D materialImage; // r perceptual roughness, g metalness
#define ML_STATIC_DATA staticWords
#define CPVS_DATA staticWords
#include "shaders/static/static_visibility.glsl"
#define VSM_CONST vsm
#define VSM_MAPS vsmMaps
#define VSM_COVER vsmCoverage
#define VSM_TABLE vsmTable
#define VSM_POOL vsmPool
#include "shaders/shared/cluster_list.glsl"
#include "shadows/virtual/vsm_common.glsl"

// Static (baked SM / MH / MMH / DAG-MH / CPVS) times dynamic (virtual shadow map) visibility of light
// L at P. Nraw is the G-buffer normal as stored (the VSM lookup normalises it like its CPU twin).
float lightVisibility(GpuLight L, vec3 P, vec3 N, vec3 Nraw) {
    float v = 1.0;
    if (L.info.z != ML_NO_SHADOW) {
        // Point lights have six consecutive records, one per cube face (method 0 = face not baked).
        uint r = L.info.z;
        if (L.info.x == ML_LIGHT_POINT) r += pointLightFace(P - L.positionRange.xyz);
        GpuShadowRecord rec = shadowRecords[r];
        if (rec.info.x != 0u) v *= staticVisibility(rec, P, N);
    }
    if (L.info.y != ML_VSM_NO_MAP && v > 0.0) {
        VsmChoice c;
        uint status, depth;
        v *= vsmVisibility(L, L.info.y, P, Nraw, c, status, depth);
    }
    return v;
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
        uvec2 range = clusterLights(px, d);
        for (uint i = 0; i < range.y; ++i) {
            GpuLight L = lights[ML_CLUSTER_LIGHT(range, i)];
            vec3 c = kSpecPbr != 0u ? shadeLightPbr(L, P, N, V, albedo, material.x, material.y)
                                    : shadeLight(L, P, N, V, albedo);
            if (c != vec3(0.0)) hdr += receiver ? c * lightVisibility(L, P, N, Nraw) : c;
        }
    }
    if (kSpecOutput != 2u) imageStore(hdrImage, ivec2(px), vec4(hdr, 1.0));
    if (kSpecOutput != 1u) imageStore(outputImage, ivec2(px), vec4(toneMap(hdr * frame.ambient.w), 1.0));
}
