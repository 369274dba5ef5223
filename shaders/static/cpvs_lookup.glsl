// CPVS lookup (paper section 5): GLSL twin of the CPU functions at the end of
// shadows/static/cpvs_layout.cpp. Same names, same integer operations in the same order; keep the two in
// step line by line. The data layout is in docs/cpvs-layout.md and shadows/static/cpvs_layout.cpp.
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

// header word indices (CpvsHeader in shadows/static/cpvs.h)
const uint CPVS_H_RESOLUTION = 2u;
const uint CPVS_H_LOG2_RESOLUTION = 3u;
const uint CPVS_H_GRID_LOG2 = 4u;
const uint CPVS_H_THRESHOLDS = 8u;
const uint CPVS_H_GRID = 9u;
const uint CPVS_LIT = 0u;
const uint CPVS_SHADOWED = 1u;

// Slice of a quantised depth: the number of s in [1, N-1] with T[s] < depth (binary search).
uint cpvsSliceOfDepth(uint base, uint depth) {
    uint n = CPVS_DATA[base + CPVS_H_RESOLUTION];
    uint t = base + CPVS_DATA[base + CPVS_H_THRESHOLDS];
    uint lo = 1u; // first s in [1, N) with T[s] >= depth, N if none
    uint count = n - 1u;
    while (count > 0u) {
        uint step = count >> 1u;
        uint mid = lo + step;
        if (CPVS_DATA[t + mid] < depth) {
            lo = mid + 1u;
            count -= step + 1u;
        } else {
            count = step;
        }
    }
    return lo - 1u;
}

// Voxel (x, y, s): x, y outside [0, N) are lit; s is clamped to [0, N-1].
bool cpvsShadowedVoxel(uint base, int x, int y, int s) {
    int n = int(CPVS_DATA[base + CPVS_H_RESOLUTION]);
    if (x < 0 || y < 0 || x >= n || y >= n) return false;
    s = s < 0 ? 0 : (s >= n ? n - 1 : s);
    uint ux = uint(x), uy = uint(y), us = uint(s);
    uint gridLog2 = CPVS_DATA[base + CPVS_H_GRID_LOG2];
    uint cellLog2 = CPVS_DATA[base + CPVS_H_LOG2_RESOLUTION] - gridLog2;
    uint cell = (((us >> cellLog2) << gridLog2 | (uy >> cellLog2)) << gridLog2) | (ux >> cellLog2);
    uint ptr = CPVS_DATA[base + CPVS_DATA[base + CPVS_H_GRID] + cell];
    if (ptr == CPVS_LIT) return false;
    if (ptr == CPVS_SHADOWED) return true;
    uint half_ = 1u << (cellLog2 - 1u);
    while (half_ >= 4u) {
        uint h = CPVS_DATA[base + ptr];
        uint c = ((ux & half_) != 0u ? 1u : 0u) | ((uy & half_) != 0u ? 2u : 0u) | ((us & half_) != 0u ? 4u : 0u);
        uint bit = 1u << c;
        if ((h & bit) == 0u) return ((h >> 8u) & bit) != 0u;
        ptr = CPVS_DATA[base + ptr + 1u + uint(bitCount(h & (bit - 1u)))];
        half_ >>= 1u;
    }
    uint b = (ux & 3u) + 4u * (uy & 3u) + 16u * (us & 3u);
    return ((CPVS_DATA[base + ptr + (b >> 5u)] >> (b & 31u)) & 1u) != 0u;
}

// Normal bias: move along nq until the largest component is radius + 1 voxels, rounding half away from 0.
ivec3 cpvsNormalOffset(ivec3 nq, int radius) {
    int ax = nq.x < 0 ? -nq.x : nq.x, ay = nq.y < 0 ? -nq.y : nq.y, az = nq.z < 0 ? -nq.z : nq.z;
    int m = ax > ay ? ax : ay;
    m = m > az ? m : az;
    int h = radius + 1;
    ivec3 a = ivec3(ax, ay, az);
    ivec3 outv;
    for (int i = 0; i < 3; ++i) {
        int o = m == 0 ? 0 : (2 * a[i] * h + m) / (2 * m); // non-negative: rounds half up
        outv[i] = nq[i] < 0 ? -o : o;
    }
    return outv;
}

// Lit taps of a (2 radius + 1)^2 PCF kernel (radius 0..4, up to 9x9) around the biased voxel.
// Visibility = float(count) / float((2 radius + 1)^2) on the caller's side.
uint cpvsPcfLitCount(uint base, int x, int y, int s, ivec3 nq, int radius) {
    ivec3 o = cpvsNormalOffset(nq, radius);
    uint lit = 0u;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx)
            if (!cpvsShadowedVoxel(base, x + o.x + dx, y + o.y + dy, s + o.z)) lit += 1u;
    return lit;
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
