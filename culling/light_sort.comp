#version 460
#extension GL_GOOGLE_include_directive : require
// Light assignment, last pass (every culling mode with lists): orders each cluster's list by light
// index. The assignment passes append with atomics, so a list's order depends on thread timing;
// sorted lists make the frame deterministic (the evaluation sums lights in list order) and equal to
// the CPU reference in order, and give lanes of a wave that share lights the same sequence.
// One thread per cluster, insertion sort in place: lists are short (1-2 lights per pixel on average at
// 4096 lights in the night city, rarely past 64), and an empty or overflowed cluster returns at once.
#include "shaders/shared/glsl_common.glsl"

layout(local_size_x = ML_SORT_GROUP) in;

layout(binding = 0) uniform Frame { FrameConstants frame; };
layout(binding = 1, std430) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = 2, std430) buffer Pool { uint pool[]; };

void main() {
    uint c = gl_GlobalInvocationID.x;
    if (c >= frame.limits.y) return; // the grid's cluster count
    uvec2 r = ranges[c];
    if (r.x == ML_CLUSTER_OVERFLOW || r.y < 2u) return;
    for (uint i = 1u; i < r.y; ++i) {
        uint v = pool[r.x + i];
        uint j = i;
        while (j > 0u && pool[r.x + j - 1u] > v) {
            pool[r.x + j] = pool[r.x + j - 1u];
            --j;
        }
        pool[r.x + j] = v;
    }
}
