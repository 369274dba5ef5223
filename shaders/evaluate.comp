#version 460
#extension GL_GOOGLE_include_directive : require
// The one evaluation pass: per pixel, every light of its cluster: visibility (static x dynamic shadow
// hooks, 1 until the shadow methods attach) x shading, accumulated in HDR, tone-mapped to the output.
// With kSpecStats it also counts, per pixel, lights evaluated and lights whose cone and range really
// hold the point (a brute-force loop: diagnostic cost, off in benchmarks).
#include "shaders/shared/glsl_common.h"
#include "shaders/shared/shading.h"

layout(local_size_x = ML_EVAL_GROUP, local_size_y = ML_EVAL_GROUP) in;
layout(constant_id = 0) const uint kSpecCullingMode = ML_CULL_CLUSTERED;
layout(constant_id = 1) const bool kSpecStats = false;

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
layout(binding = 10, std430) buffer Counters { FrameCounters counters; };
layout(binding = 11, std430) readonly buffer StaticWords { uint staticWords[]; };
layout(binding = 12, std430) readonly buffer ShadowRecords { GpuShadowRecord shadowRecords[]; };
#define ML_STATIC_DATA staticWords
#define CPVS_DATA staticWords
#include "shaders/static/static_visibility.glsl"

shared uint sEvaluated, sReaching, sSurface;

// Visibility hook: static (baked SM / MH / MMH / DAG-MH / CPVS) times dynamic (virtual shadow map,
// not built yet) visibility of light `index` at P.
float lightVisibility(uint index, GpuLight L, vec3 P, vec3 N) {
    float v = 1.0;
    if (L.info.z != ML_NO_SHADOW) {
        // Point lights have six consecutive records, one per cube face (method 0 = face not baked).
        uint r = L.info.z;
        if (L.info.x == ML_LIGHT_POINT) r += pointLightFace(P - L.positionRange.xyz);
        GpuShadowRecord rec = shadowRecords[r];
        if (rec.info.x != 0u) v *= staticVisibility(rec, P, N);
    }
    return v;
}

vec3 shade(uint index, vec3 P, vec3 N, vec3 V, vec3 albedo) {
    GpuLight L = lights[index];
    vec3 c = shadeLight(L, P, N, V, albedo);
    if (c == vec3(0.0)) return c;
    return c * lightVisibility(index, L, P, N);
}

void main() {
    if (kSpecStats && gl_LocalInvocationIndex == 0) { sEvaluated = 0; sReaching = 0; sSurface = 0; }
    if (kSpecStats) barrier();

    uvec2 px = gl_GlobalInvocationID.xy;
    bool inside = px.x < frame.size.x && px.y < frame.size.y;
    if (inside) {
        float d = texelFetch(depthImage, ivec2(px), 0).r;
        vec3 hdr = frame.sky.rgb;
        if (d < 1.0) {
            vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
            vec3 N = normalize(texelFetch(normalImage, ivec2(px), 0).xyz);
            vec3 albedo = texelFetch(albedoImage, ivec2(px), 0).rgb;
            vec3 V = normalize(frame.cameraPosition.xyz - P);
            hdr = albedo * frame.ambient.rgb;
            uint evaluated = 0;
            bool all = kSpecCullingMode == ML_CULL_NONE;
            uvec2 range = uvec2(0);
            if (!all) {
                float z = linearDepth(d, frame.depth);
                uint slices = frame.cluster.x;
                uint s = 0;
                while (s + 1 < slices && z >= sliceFar[s]) ++s;
                uvec2 tile = px / frame.cluster.y;
                range = ranges[(tile.y * frame.size.z + tile.x) * slices + s];
                all = range.x == ML_CLUSTER_OVERFLOW;
            }
            if (all) {
                // No culling, or an overflowed cluster: every visible light, tested per pixel.
                for (uint l = 0; l < frame.cluster.z; ++l) hdr += shade(l, P, N, V, albedo);
                evaluated = frame.cluster.z;
            } else {
                for (uint i = 0; i < range.y; ++i) hdr += shade(pool[range.x + i], P, N, V, albedo);
                evaluated = range.y;
            }
            if (kSpecStats) {
                uint reaching = 0;
                for (uint l = 0; l < frame.cluster.z; ++l) reaching += lightReachesPoint(lights[l], P) ? 1u : 0u;
                atomicAdd(sEvaluated, evaluated);
                atomicAdd(sReaching, reaching);
                atomicAdd(sSurface, 1u);
            }
        }
        imageStore(hdrImage, ivec2(px), vec4(hdr, 1.0));
        imageStore(outputImage, ivec2(px), vec4(toneMap(hdr * frame.ambient.w), 1.0));
    }
    if (kSpecStats) {
        barrier();
        if (gl_LocalInvocationIndex == 0 && sSurface > 0) {
            atomicAdd(counters.evaluatedSum, uint64_t(sEvaluated));
            atomicAdd(counters.reachingSum, uint64_t(sReaching));
            atomicAdd(counters.surfacePixels, uint64_t(sSurface));
        }
    }
}
