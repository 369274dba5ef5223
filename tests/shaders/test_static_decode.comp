#version 460
#extension GL_GOOGLE_include_directive : require
// Test program: decodes every texel (depth methods) or every voxel (CPVS) of one encoded static shadow
// with the GLSL decoders, so tests/gpu can compare them bit for bit with the CPU twins.
#include "shaders/shared/glsl_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, std430) readonly buffer Words { uint words[]; };
layout(binding = 1, std430) writeonly buffer Out { uint outWords[]; };
layout(push_constant) uniform Push { uint method, base, res, pad; };

#define ML_STATIC_DATA words
#define CPVS_DATA words
#include "shaders/static/static_visibility.glsl"

void main() {
    uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
    if (x >= res || y >= res) return;
    if (method != ML_STATIC_CPVS) {
        outWords[y * res + x] = staticDepthAt(method, base, x, y);
        return;
    }
    // One bit per voxel of the column, 32 slices per word.
    uint wordsPerColumn = (res + 31u) / 32u;
    for (uint w = 0u; w < wordsPerColumn; ++w) {
        uint bits = 0u;
        for (uint b = 0u; b < 32u && w * 32u + b < res; ++b)
            if (cpvsShadowedVoxel(base, int(x), int(y), int(w * 32u + b))) bits |= 1u << b;
        outWords[(y * res + x) * wordsPerColumn + w] = bits;
    }
}
