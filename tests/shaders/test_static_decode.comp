#version 460
#extension GL_GOOGLE_include_directive : require
// Test program: decodes every texel (depth methods) or every voxel (CPVS) of one encoded static shadow
// with the GLSL decoders, so tests/gpu can compare them bit for bit with the CPU twins.
#include "shaders/shared/glsl_common.glsl"
#include "tests/shaders/static_decode_push.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = ML_DECODE_WORDS, std430) readonly buffer Words { uint words[]; };
layout(binding = ML_DECODE_OUT, std430) writeonly buffer Out { uint outWords[]; };
layout(push_constant) uniform Push { StaticDecodePush push; };

#define ML_STATIC_DATA words
#define CPVS_DATA words
#include "shaders/static/static_visibility.glsl"

void main() {
    uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
    if (x >= push.res || y >= push.res) return;
    if (push.method != ML_STATIC_CPVS) {
        outWords[y * push.res + x] = staticDepthAt(push.method, push.base, x, y);
        return;
    }
    // One bit per voxel of the column, 32 slices per word.
    uint wordsPerColumn = (push.res + 31u) / 32u;
    for (uint w = 0u; w < wordsPerColumn; ++w) {
        uint bits = 0u;
        for (uint b = 0u; b < 32u && w * 32u + b < push.res; ++b)
            if (cpvsShadowedVoxel(push.base, int(x), int(y), int(w * 32u + b))) bits |= 1u << b;
        outWords[(y * push.res + x) * wordsPerColumn + w] = bits;
    }
}
