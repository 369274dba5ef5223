// Static shadow visibility of one receiver for one light with a baked record: the mapping from a world
// point to the light's texel and quantised depth, the bias, and the PCF loop over the decoders.
// CPU twin: shadows/static/static_visibility.cpp (same operations, same order; the tests compare).
//
// Depth methods (SM, MH, MMH, DAG-MH): the receiver is offset along its normal by (1 + PCF radius)
// texels' world size (normal-offset bias: it grows with the texel footprint, so it holds at grazing
// angles where a constant depth bias fails, and with the kernel, whose outer taps would otherwise see
// the receiver's own surface) and then compared with a further half-texel depth bias. PCF averages the
// binary tests of (2r+1)^2 texels around it.
// CPVS: the voxel lookup applies its own normal bias in integer voxel coordinates (cpvs_lookup.glsl).
#ifndef ML_STATIC_VISIBILITY_GLSL
#define ML_STATIC_VISIBILITY_GLSL

#include "shaders/static/common_static.glsl"
#include "shaders/static/mh_lookup.glsl"
#include "shaders/static/mmh_lookup.glsl"
#include "shaders/static/dagmh_lookup.glsl"
#include "shaders/static/cpvs_lookup.glsl"

uint staticQuantize(float z, float far) {
    // float version of quantizeDepth: 4294967040 is the largest float below 2^32.
    float t = clamp(z / far, 0.0, 1.0);
    return t >= 1.0 ? 0xFFFFFFFEu : uint(t * 4294967040.0);
}

uint staticDepthAt(uint method, uint base, uint x, uint y) {
    if (method == ML_STATIC_SM) {
        // Version 2 (a directional map fitted to its box) stores only its rows (word 5).
        uint rows = ML_STATIC_DATA[base + 1u] == 2u ? ML_STATIC_DATA[base + 5u] : ML_STATIC_DATA[base + 2u];
        if (y >= rows) return 0xFFFFFFFFu;
        return ML_STATIC_DATA[base + 6u + y * ML_STATIC_DATA[base + 2u] + x];
    }
    if (method == ML_STATIC_MH) return mhLookup(base, x, y);
    if (method == ML_STATIC_MMH) return mmhLookup(base, x, y);
    return dagmhLookup(base, x, y);
}

float staticVisibility(GpuShadowRecord rec, vec3 P, vec3 N) {
    uint method = rec.info.x, base = rec.info.y, res = rec.info.z;
    int radius = int(rec.info.w);
    float tanHalf = rec.frustum.x, far = rec.frustum.z;
    // frustum.x < 0: an orthographic map (directional light) of half side -frustum.x.
    bool ortho = tanHalf < 0.0;
    float orthoHalf = -tanHalf;
    vec3 vp = (rec.view * vec4(P, 1.0)).xyz;
    vec3 vn = mat3(rec.view) * N;
    float z = -vp.z;
    if (z <= rec.frustum.y) return 1.0;
    if (method == ML_STATIC_CPVS) {
        vec2 ndc = ortho ? vp.xy / orthoHalf : vp.xy / (z * tanHalf);
        ivec2 t = ivec2(floor((ndc * 0.5 + 0.5) * float(res)));
        uint s = cpvsSliceOfDepth(base, staticQuantize(z, far));
        // Orthographic maps slice depth linearly: frustum.w is far - near there (log(far / near) else).
        ivec3 nq = ortho ? cpvsVoxelNormal(vn, 0.0, 0.0, orthoHalf, rec.frustum.w)
                         : cpvsVoxelNormal(vn, ndc.x, ndc.y, tanHalf, rec.frustum.w);
        uint lit = cpvsPcfLitCount(base, t.x, t.y, int(s), nq, radius);
        return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
    }
    float texelWorld = ortho ? 2.0 * orthoHalf / float(res) : 2.0 * z * tanHalf / float(res);
    // Normal offset of (1 + radius) texels: the PCF taps reach `radius` texels to the side, and on a
    // surface at a grazing angle to the light (flat ground under a low point light's side faces) the taps
    // on the light's side of the receiver see the same surface nearer than the receiver unless it is
    // lifted past them (GpuPointShadow.NoAcneOnFlatGroundOrBoxFaces: stripes of self-shadow with PCF).
    // Per light (GpuShadowRecord.bias): a scale on that offset and the depth bias (defaults 1 and 0.5).
    vec3 q = vp + vn * (texelWorld * float(1 + radius) * rec.bias.y);
    float zq = -q.z;
    if (zq <= rec.frustum.y) return 1.0;
    vec2 ndc = ortho ? q.xy / orthoHalf : q.xy / (zq * tanHalf);
    ivec2 t = ivec2(floor((ndc * 0.5 + 0.5) * float(res)));
    uint depth = staticQuantize(max(zq - rec.bias.x * texelWorld, 0.0), far);
    // Hierarchical PCF for DAG-MH: the taps share the traversal down to the node that holds them all.
    ivec2 lo = clamp(t - radius, ivec2(0), ivec2(int(res) - 1));
    ivec2 hi = clamp(t + radius, ivec2(0), ivec2(int(res) - 1));
    bool usePrefix = false;
    DagmhState prefix;
    DagmhHeader dh;
    if (method == ML_STATIC_DAGMH) dh = dagmhHeader(base); // once for all taps
    if (method == ML_STATIC_DAGMH && radius > 0) {
        prefix = dagmhPcfPrefix(dh, uint(lo.x), uint(lo.y), uint(hi.x), uint(hi.y));
        usePrefix = prefix.kind != ML_DAG_NO_PREFIX;
    }
    // DAG-MH taps that land in the node of the previous tap's value (same value index) reuse its decoded
    // value: MH nodes cover many texels, so a 3x3 kernel mostly decodes one or two values.
    uint memoIndex = 0xFFFFFFFFu, memoDepth = 0u;
    uint lit = 0u;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            int x = t.x + dx, y = t.y + dy;
            // Outside the map the light's cone does not reach: count as lit.
            if (x < 0 || y < 0 || x >= int(res) || y >= int(res)) { lit += 1u; continue; }
            uint d;
            if (method == ML_STATIC_DAGMH) {
                DagmhState st = dagmhLocate(dh, uint(x), uint(y), usePrefix ? prefix : dagmhStart(dh, uint(x), uint(y)));
                if (st.vlast != memoIndex) {
                    memoIndex = st.vlast;
                    memoDepth = dagmhLocatedValue(dh, uint(x), uint(y), st);
                }
                d = memoDepth;
            } else {
                d = staticDepthAt(method, base, uint(x), uint(y));
            }
            if (depth <= d) lit += 1u;
        }
    return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
}

#endif
