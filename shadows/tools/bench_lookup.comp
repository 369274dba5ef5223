#version 460
#extension GL_GOOGLE_include_directive : require
// Lookup timing (bench static, shadows/tools/lookup_timer.cpp): each invocation takes one (receiver, light)
// pair and calls the static lookup `lookups` times with the pass's PCF radius. Each call's receiver
// depends on the previous result (offset by acc * 1e-30 m, which rounds to nothing but cannot be
// folded), so the calls are neither merged nor hoisted. Timing the pass at 1 and at 1 + K lookups
// and dividing the difference by K * pairs leaves the cost of one lookup, free of the pass's fixed
// cost (launch, item loads, record fetch). The sum is written out so that nothing is dead code; the
// host checks it against the CPU twin (static_visibility.cpp).
#include "shaders/shared/glsl_common.glsl"
#include "shadows/tools/lookup_push.h"
#include "shadows/tools/bench_lookup_bindings.h"

layout(local_size_x = 64) in;
layout(binding = ML_LOOKUP_ITEMS, std430) readonly buffer Items { vec4 items[]; }; // per pair: P (w unused), N (w = record bits)
layout(binding = ML_LOOKUP_RECORDS, std430) readonly buffer Records { GpuShadowRecord records[]; };
layout(binding = ML_LOOKUP_WORDS, std430) readonly buffer Words { uint words[]; };
layout(binding = ML_LOOKUP_OUT, std430) writeonly buffer Out { float sums[]; };
layout(push_constant) uniform Push { LookupPush push; };

#define ML_STATIC_DATA words
#define CPVS_DATA words
#include "shaders/static/static_visibility.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    vec4 p = items[2u * i], n = items[2u * i + 1u];
    GpuShadowRecord rec = records[floatBitsToUint(n.w)];
    rec.info.x = shadowRecordWithRadius(rec.info.x, push.radius);
    float acc = 0.0;
    for (uint k = 0u; k < push.lookups; ++k) acc += staticVisibility(rec, p.xyz + n.xyz * (acc * 1e-30), n.xyz, 0.0);
    sums[i] = acc;
}
