// CPVS lookup (paper section 5). The decoder (a depth's slice, a voxel's bit, the normal bias and the PCF
// kernel by level) is one source text with the C++ one: shaders/static/cpvs_decode.h. cpvsVoxelNormal below
// is the GLSL twin of the CPU function at the end of shadows/static/cpvs_layout.cpp: same operations in
// the same order; keep the two in step line by line. The data layout is in docs/cpvs-layout.md and shadows/static/cpvs_layout.cpp.
//
// Usage: bind the CPVS words of all lights as one `uint` array and define CPVS_DATA before including:
//     layout(std430, set = 0, binding = 3) readonly buffer CpvsWords { uint words[]; } cpvsBuf;
//     #define CPVS_DATA cpvsBuf.words
//     #include "static/cpvs_lookup.glsl"
// `base` is the word index of a light's CPVS header in that array.
//
// Inputs are integers: the receiver's texel (x, y) in the light's N x N map, its quantised linear depth
// (quantizeDepth in shadows/static/dual_depth.h; the caller computes it like for every other static
// method) mapped to a slice by cpvsSliceOfDepth, and a quantised voxel-space normal. From there every
// result is bit-identical to the CPU. Only cpvsVoxelNormal uses floats; Vulkan does not round float
// division exactly, so its +-1024 quantised output may differ from the CPU by one unit in rare cases
// (the normal bias built from it then shifts by at most one voxel).
#ifndef CPVS_LOOKUP_GLSL
#define CPVS_LOOKUP_GLSL

#ifndef CPVS_DATA
#error "define CPVS_DATA as the uint[] array that holds the CPVS words"
#endif

// The decoder proper, cpvsSliceOfDepth, cpvsShadowedVoxel and cpvsPcfLitLevel: one text with the C++ one.
#define CPVS_FN
#define CPVS_DATA_PARAM
#define CPVS_DATA_ARG
#define CPVS_WORD(i) CPVS_DATA[i]
#include "shaders/static/cpvs_decode.h"

// Lit taps of a (2 radius + 1)^2 PCF kernel at the finest level (cpvsPcfLitLevel, step 0).
uint cpvsPcfLitCount(uint base, int x, int y, int s, ivec3 nq, int radius) {
    return cpvsPcfLitLevel(base, x, y, s, nq.x, nq.y, nq.z, radius, 0u);
}

// Voxel-space direction of a light-view normal (light looks down -Z), quantised to +-1024.
ivec3 cpvsVoxelNormal(vec3 nView, float ndcX, float ndcY, float tanHalfFov, float logFarOverNear) {
    // precise: no fused multiply-add, so the operations round like the CPU's (-ffp-contract=off)
    precise float nd = -nView.z;
    precise vec3 v;
    v.x = (nView.x - ndcX * tanHalfFov * nd) / (2.0 * tanHalfFov);
    v.y = (nView.y - ndcY * tanHalfFov * nd) / (2.0 * tanHalfFov);
    v.z = nd / logFarOverNear;
    float m = max(abs(v.x), max(abs(v.y), abs(v.z)));
    ivec3 outv;
    for (int i = 0; i < 3; ++i) {
        precise float q = v[i] / m * 1024.0 + 0.5;
        outv[i] = m > 0.0 ? int(floor(q)) : 0;
    }
    return outv;
}

#endif // CPVS_LOOKUP_GLSL
