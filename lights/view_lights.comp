#version 460
#extension GL_GOOGLE_include_directive : require
// Light-complexity view (demo --view lights | lights-reaching), run after the evaluation pass: per
// pixel, the lights the evaluation pass evaluated there (its cluster's list length; every visible
// light in mode none or for an overflowed cluster) and the lights whose cone and range hold the
// point (a brute-force loop over the visible lights), written to `viewCounts` (evaluated | reaching
// << 16) and, as heatColor of the chosen count, over the output image. Pixels without geometry stay
// as shaded (the sky). Diagnostic: its cost is not part of the frame's passes.
#include "shaders/shared/glsl_common.glsl"
#include "shaders/shared/heat.h"
#include "culling/culling_bindings.h"

layout(local_size_x = ML_EVAL_GROUP, local_size_y = ML_EVAL_GROUP) in;
layout(constant_id = 0) const bool kSpecReaching = false;

layout(binding = ML_VIEW_FRAME) uniform Frame { FrameConstants frame; };
layout(binding = ML_VIEW_SLICES, std430) readonly buffer Slices { float sliceFar[]; };
#include "shaders/shared/cluster_slice.glsl"
layout(binding = ML_VIEW_LIGHTS, std430) readonly buffer Lights { GpuLight lights[]; };
layout(binding = ML_VIEW_RANGES, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = ML_VIEW_DEPTH) uniform texture2D depthImage;
layout(binding = ML_VIEW_OUTPUT, rgba8) uniform writeonly image2D outputImage;
layout(binding = ML_VIEW_COUNTS, std430) writeonly buffer ViewCounts { uint viewCounts[]; };

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= frame.size.x || px.y >= frame.size.y) return;
    float d = texelFetch(depthImage, ivec2(px), 0).r;
    uint evaluated = 0, reaching = 0;
    if (hasSurface(d)) {
        vec3 P = worldFromPixel(px.x, px.y, d, frame.invViewProj, frame.size);
        evaluated = frame.cluster.z;
        if (frame.cluster.w != ML_CULL_NONE) {
            float z = linearDepth(d, frame.depth);
            uint slices = frame.cluster.x;
            uint s = clusterSlice(z);
            uvec2 tile = px / frame.cluster.y;
            uvec2 range = ranges[(tile.y * frame.size.z + tile.x) * slices + s];
            if (range.x != ML_CLUSTER_OVERFLOW) evaluated = range.y;
        }
        for (uint l = 0; l < frame.cluster.z; ++l) reaching += lightReachesPoint(lights[l], P) ? 1u : 0u;
        imageStore(outputImage, ivec2(px), vec4(heatColor(kSpecReaching ? reaching : evaluated), 1.0));
    }
    viewCounts[px.y * frame.size.x + px.x] = min(evaluated, 0xFFFFu) | (min(reaching, 0xFFFFu) << 16);
}
