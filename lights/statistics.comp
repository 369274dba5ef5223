#version 460
#extension GL_GOOGLE_include_directive : require
// Frame statistics (off by default in the API, on in the demo): per pixel with geometry, the lights
// evaluated (its cluster's list, or every visible light in an overflowed cluster / without culling) and
// the lights whose cone and range really hold the point (a brute-force loop over every visible light:
// diagnostic cost, which is why it is a pass of its own with its own profile entry).
#include "shaders/shared/glsl_common.glsl"
#include "lights/evaluate_bindings.h"

layout(local_size_x = ML_EVAL_GROUP, local_size_y = ML_EVAL_GROUP) in;

layout(binding = ML_STATS_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_STATS_SLICES, std430) readonly buffer Slices { float sliceFar[]; };
layout(binding = ML_STATS_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_STATS_RANGES, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_STATS_POOL, std430) readonly buffer Pool { uint pool[]; };
layout(binding = ML_STATS_DEPTH) uniform texture2D depthImage;
layout(binding = ML_STATS_COUNTERS, std430) buffer Counters { FrameCounters counters; };

#include "shaders/shared/cluster_list.glsl"

shared uint sEvaluated, sReaching, sSurface;

void main() {
    if (gl_LocalInvocationIndex == 0) { sEvaluated = 0; sReaching = 0; sSurface = 0; }
    barrier();
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x < frame.size.x && px.y < frame.size.y) {
        float d = texelFetch(depthImage, ivec2(px), 0).r;
        if (hasSurface(d)) {
            vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
            uint reaching = 0;
            for (uint l = 0; l < frame.cluster.z; ++l) reaching += lightReachesPoint(lights[l], P) ? 1u : 0u;
            atomicAdd(sEvaluated, clusterLights(px, d).y);
            atomicAdd(sReaching, reaching);
            atomicAdd(sSurface, 1u);
        }
    }
    barrier();
    if (gl_LocalInvocationIndex == 0 && sSurface > 0) {
        atomicAdd(counters.evaluatedSum, uint64_t(sEvaluated));
        atomicAdd(counters.reachingSum, uint64_t(sReaching));
        atomicAdd(counters.surfacePixels, uint64_t(sSurface));
    }
}
