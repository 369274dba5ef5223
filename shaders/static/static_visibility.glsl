// Static shadow visibility of one receiver for one light with a baked record: the mapping from a world
// point to the light's texel and quantised depth, the bias, and the PCF loop over the decoders.
// CPU twin: shadows/static/static_visibility.cpp (same operations, same order; the tests compare), but
// for DAG-MH (dagmhPcfLit, the one tap): that first tests the value bounds of the cells it covers,
// which decide a tap or a whole kernel when the receiver is nearer or farther than every value there,
// then walks the in-map taps only and shares more reads between taps; each tap still gets the answer
// the CPU's per-tap loop gets, so the lit count is the same. The light view (a quaternion and a
// translation in the record) is applied by shaders/shared/shadow_record.h, the same text on both sides.
//
// Depth methods (SM, MH, MMH, DAG-MH): the receiver is offset along its normal by (1 + PCF radius)
// texels' world size (normal-offset bias: it grows with the texel footprint, so it holds at grazing
// angles where a constant depth bias fails, and with the kernel, whose outer taps would otherwise see
// the receiver's own surface) and then compared with a further half-texel depth bias. PCF averages the
// binary tests of (2r+1)^2 texels around it.
// Filtering by level (MH, MMH, DAG-MH and CPVS records with shadowRecordByLevel, off by default):
// footprint2 is the receiver's pixel footprint squared (shadowFootprint2: FrameConstants.cameraPosition.w times the squared
// distance); shadowLevelStep picks the coarsest level whose texel is at most a quarter of it
// (ML_LEVEL_TEXELS_PER_PIXEL), by exact doubling so the CPU twin picks the same one, and the taps, normal
// offset and depth bias are that level's texels.
// CPVS: the voxel lookup applies its own normal bias in integer voxel coordinates (cpvs_decode.h); by
// level, a level voxel answers with its block's centre voxel at the receiver's own slice.
#ifndef ML_STATIC_VISIBILITY_GLSL
#define ML_STATIC_VISIBILITY_GLSL

#include "shaders/shared/shadow_record.h"
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

// The depth of texel (x, y) of the level `step` above the finest (MH and MMH; step 0 is the map; DAG-MH
// levels: dagmhPcfLitLevel).
uint staticDepthAtLevel(uint method, uint base, uint x, uint y, uint step) {
    if (step == 0u) return staticDepthAt(method, base, x, y);
    uint steps = ML_STATIC_DATA[base + ML_MH_LEVELS] - step;
    return method == ML_STATIC_MH ? mhLookupLevel(base, x, y, steps) : mmhLookupLevel(base, x, y, steps);
}

// The value a kernel's tap located (st, at full-resolution texel (x, y)): a tap with the previous tap's
// value index reuses its value (same MH node), and one in the same chunk the chunk's 6 words (only its
// factor bits are read).
struct DagmhMemo {
    uint index, value, chunkIndex;
    DagmhChunk chunk;
};

DagmhMemo dagmhMemoNone() {
    DagmhMemo m;
    m.index = 0xFFFFFFFFu, m.value = 0u, m.chunkIndex = 0xFFFFFFFFu;
    return m;
}

uint dagmhMemoValue(DagmhHeader dh, inout DagmhMemo m, DagmhState st, uint x, uint y) {
    if (st.vlast == m.index) return m.value;
    m.index = st.vlast;
    if ((st.vlast >> 5u) != m.chunkIndex) {
        m.chunkIndex = st.vlast >> 5u;
        m.chunk = dagmhChunk(dh, m.chunkIndex);
    }
    uint s = dh.L - st.dlast;
    m.value = dagmhChunkValue(dh, m.chunk, st.vlast & 31u, (x >> s) << s, (y >> s) << s);
    return m.value;
}

// DAG-MH PCF: the number of lit taps of [t - r, t + r] (taps outside the map count as lit; a tap is lit
// when depth <= its decoded value). Hierarchical, and exact (each tap gets the value index and node depth
// that dagmhLookup finds, so the count equals the per-tap loop of the CPU twin):
// - the kernel's taps share the descent to the node that holds them all (dagmhPcfPrefix); when that
//   descent ends in a treelet, the taps share its 3 words too (read once, not once per tap);
// - a tap with the previous tap's value index reuses its value, and one in the same chunk the chunk's
//   words (dagmhMemoValue);
// - first of all, the value bounds of the cells the kernel covers (dagmhBoundsClass) decide it
//   whole when the receiver is nearer than every value there (all lit) or farther than every one.
uint dagmhPcfLit(DagmhHeader dh, ivec2 t, int radius, int res, uint depth) {
    uint taps = uint((2 * radius + 1) * (2 * radius + 1));
    ivec2 lo = max(t - radius, ivec2(0)), hi = min(t + radius, ivec2(res - 1));
    if (lo.x > hi.x || lo.y > hi.y) return taps;
    uint lit = taps - uint((hi.x - lo.x + 1) * (hi.y - lo.y + 1));
    // The value bounds decide most kernels whole: every in-map tap lit, or none.
    uint k = dagmhBoundsClass(dh, uint(lo.x), uint(lo.y), uint(hi.x), uint(hi.y), depth);
    if (k != 0u) return k == 1u ? taps : lit;
    dh = dagmhSections(dh);
    DagmhState prefix = dagmhPcfPrefix(dh, uint(lo.x), uint(lo.y), uint(hi.x), uint(hi.y));
    bool usePrefix = prefix.kind != ML_DAG_NO_PREFIX;
    bool sharedTreelet = prefix.kind == 2u;
    uint t0 = 0u, t1 = 0u, t2 = 0u;
    if (sharedTreelet) {
        uint tb = dh.treelets + ML_DAG_TREELET_WORDS * prefix.ptr;
        t0 = ML_STATIC_DATA[tb], t1 = ML_STATIC_DATA[tb + 1u], t2 = ML_STATIC_DATA[tb + 2u];
    }
    DagmhMemo memo = dagmhMemoNone();
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            DagmhState st;
            if (sharedTreelet) st = dagmhTreelet(dh, uint(x), uint(y), prefix, t0, t1, t2, dh.L);
            else st = dagmhLocate(dh, uint(x), uint(y), usePrefix ? prefix : dagmhStart(dh, uint(x), uint(y)));
            if (depth <= dagmhMemoValue(dh, memo, st, uint(x), uint(y))) lit += 1u;
        }
    return lit;
}

// DAG-MH PCF by level: the lit taps of [t - r, t + r] on the map `steps` levels below the root, t a texel of
// that map (levelRes a side). Each tap gets the value dagmhLookupLevel finds (the CPU twin's per-tap loop),
// with the taps sharing the descent above the level where they part and a tap with the previous tap's
// value index reusing its value. No value bounds here (dagmhLookupLevel says why).
uint dagmhPcfLitLevel(DagmhHeader dh, ivec2 t, int radius, int levelRes, uint depth, uint steps) {
    uint taps = uint((2 * radius + 1) * (2 * radius + 1));
    ivec2 lo = max(t - radius, ivec2(0)), hi = min(t + radius, ivec2(levelRes - 1));
    if (lo.x > hi.x || lo.y > hi.y) return taps;
    uint lit = taps - uint((hi.x - lo.x + 1) * (hi.y - lo.y + 1));
    dh = dagmhSections(dh);
    uint sh = dh.L - steps;
    // The taps' full-resolution texels (x << sh) take the same children down to depth L - (bits of the
    // widest difference), and never past `steps`.
    uint diff = (uint(lo.x ^ hi.x) | uint(lo.y ^ hi.y)) << sh;
    uint bits = 0u;
    while ((diff >> bits) != 0u) ++bits;
    uint sharedLevels = min(dh.L - bits, steps);
    uint X0 = uint(lo.x) << sh, Y0 = uint(lo.y) << sh;
    // Above the skip level each tap starts at the root (dagmhLevelStart), and so does a shared prefix.
    DagmhState prefix = dagmhDescend(dh, X0, Y0, dagmhLevelStart(dh, X0, Y0, sharedLevels), sharedLevels);
    DagmhMemo memo = dagmhMemoNone();
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            uint X = uint(x) << sh, Y = uint(y) << sh;
            if (depth <= dagmhMemoValue(dh, memo, dagmhLevelLocate(dh, X, Y, prefix, steps), X, Y)) lit += 1u;
        }
    return lit;
}

// footprint2: the squared world size of the receiver's pixel (shadowFootprint2), read only when the record
// filters by level.
float staticVisibility(GpuShadowRecord rec, vec3 P, vec3 N, float footprint2) {
    uint method = shadowRecordMethod(rec), base = rec.info.y, res = shadowRecordResolution(rec);
    int radius = int(shadowRecordRadius(rec));
    float tanHalf = rec.frustum.x, far = rec.frustum.z;
    // frustum.x < 0: an orthographic map (directional light) of half side -frustum.x.
    bool ortho = tanHalf < 0.0;
    float orthoHalf = -tanHalf;
    vec3 vp = shadowViewPoint(rec, P);
    vec3 vn = shadowViewVector(rec, N);
    float z = -vp.z;
    if (z <= rec.frustum.y) return 1.0;
    if (method == ML_STATIC_CPVS) {
        vec2 ndc = ortho ? vp.xy / orthoHalf : vp.xy / (z * tanHalf);
        ivec2 t = ivec2(floor((ndc * 0.5 + 0.5) * float(res)));
        uint s = cpvsSliceOfDepth(base, staticQuantize(z, far));
        // Orthographic maps slice depth linearly: frustum.w is far - near there (log(far / near) else).
        ivec3 nq = ortho ? cpvsVoxelNormal(vn, 0.0, 0.0, orthoHalf, rec.frustum.w)
                         : cpvsVoxelNormal(vn, ndc.x, ndc.y, tanHalf, rec.frustum.w);
        // Filtering by level: the level whose texel is at most a quarter of the pixel, as for the depth
        // methods (at most log2 N levels up: one texel for the map).
        uint step = 0u;
        if (shadowRecordByLevel(rec)) {
            float texelWorld = ortho ? 2.0 * orthoHalf / float(res) : 2.0 * z * tanHalf / float(res);
            step = shadowLevelStep(texelWorld, footprint2, ML_STATIC_DATA[base + CPVS_H_LOG2_RESOLUTION]);
        }
        uint lit = cpvsPcfLitLevel(base, t.x, t.y, int(s), nq.x, nq.y, nq.z, radius, step);
        return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
    }
    float texelWorld = ortho ? 2.0 * orthoHalf / float(res) : 2.0 * z * tanHalf / float(res);
    // Filtering by level (MH, MMH, DAG-MH): the taps, the normal offset and the depth bias are those of the
    // level shadowLevelStep picks, so a distant receiver does not walk the whole hierarchy.
    uint step = 0u;
    if (shadowRecordByLevel(rec) && (method == ML_STATIC_MH || method == ML_STATIC_MMH || method == ML_STATIC_DAGMH))
        step = shadowLevelStep(texelWorld, footprint2, ML_STATIC_DATA[base + ML_MH_LEVELS]); // L: word 3 of all three
    texelWorld = texelWorld * float(1u << step);
    // Normal offset of (1 + radius) texels: the PCF taps reach `radius` texels to the side, and on a
    // surface at a grazing angle to the light (flat ground under a low point light's side faces) the taps
    // on the light's side of the receiver see the same surface nearer than the receiver unless it is
    // lifted past them (GpuPointShadow.NoAcneOnFlatGroundOrBoxFaces: stripes of self-shadow with PCF).
    // Per light (GpuShadowRecord.bias): a scale on that offset and the depth bias (defaults 1 and 0.5).
    vec3 q = vp + vn * (texelWorld * float(1 + radius) * rec.bias.y);
    float zq = -q.z;
    if (zq <= rec.frustum.y) return 1.0;
    vec2 ndc = ortho ? q.xy / orthoHalf : q.xy / (zq * tanHalf);
    ivec2 t = ivec2(floor((ndc * 0.5 + 0.5) * float(res))) >> int(step);
    uint depth = staticQuantize(max(zq - rec.bias.x * texelWorld, 0.0), far);
    int levelRes = int((res + (1u << step) - 1u) >> step);
    if (method == ML_STATIC_DAGMH) {
        DagmhHeader dh = dagmhHeaderTop(base, dagmhLevels(res)); // once for all taps
        uint lit = 0u;
        if (step > 0u) {
            lit = dagmhPcfLitLevel(dh, t, radius, levelRes, depth, dh.L - step);
        } else if (radius == 0) {
            bool inside = t.x >= 0 && t.y >= 0 && t.x < int(res) && t.y < int(res);
            uint k = inside ? dagmhBoundsClass1(dh, uint(t.x), uint(t.y), depth) : 1u;
            if (k == 0u) k = depth <= dagmhLookupH(dagmhSections(dh), uint(t.x), uint(t.y)) ? 1u : 2u;
            lit = k == 1u ? 1u : 0u;
        } else {
            lit = dagmhPcfLit(dh, t, radius, int(res), depth);
        }
        return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
    }
    uint lit = 0u;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            int x = t.x + dx, y = t.y + dy;
            // Outside the map the light's cone does not reach: count as lit.
            if (x < 0 || y < 0 || x >= levelRes || y >= levelRes) { lit += 1u; continue; }
            if (depth <= staticDepthAtLevel(method, base, uint(x), uint(y), step)) lit += 1u;
        }
    return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
}

#endif
