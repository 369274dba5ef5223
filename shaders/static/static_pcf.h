// Static shadow visibility of one receiver for one light with a baked record, one source text for the
// shader (shaders/static/static_visibility.glsl) and the CPU twin (shadows/static/static_visibility.cpp),
// as shaders/static/dagmh_decode.h is for the DAG-MH decoder: the mapping from a world point to the
// light's texel and quantised depth, the bias, the choice of level and the PCF loops over the decoders,
// the same operations in the same order on both sides. The light view (a quaternion and a translation in
// the record) is applied by shaders/shared/shadow_record.h, likewise one text.
//
// Depth methods (SM, MH, MMH, DAG-MH): the receiver is offset along its normal by (1 + PCF radius)
// texels' world size (normal-offset bias: it grows with the texel footprint, so it holds at grazing
// angles where a constant depth bias fails, and with the kernel, whose outer taps would otherwise see
// the receiver's own surface) and then compared with a further half-texel depth bias. PCF averages the
// binary tests of (2r+1)^2 texels around it. DAG-MH's kernel (dagmhPcfLit) first tests the value bounds
// of the cells it covers, which decide a tap or a whole kernel when the receiver is nearer or farther
// than every value there, then walks the in-map taps only and shares reads between taps; each tap gets
// the answer its own dagmhLookup gives (tests/static/static_visibility_test.cpp compares the kernels with
// a per-tap loop).
// Filtering by level (MH, MMH, DAG-MH and CPVS records with shadowRecordByLevel, off by default):
// footprint2 is the receiver's pixel footprint squared (shadowFootprint2: FrameConstants.cameraPosition.w
// times the squared distance); shadowLevelStep picks the coarsest level whose texel is at most a quarter
// of it (ML_LEVEL_TEXELS_PER_PIXEL), by exact doubling so both sides pick the same one, and the taps,
// normal offset and depth bias are that level's texels.
// CPVS: the voxel lookup applies its own normal bias in integer voxel coordinates (cpvs_decode.h); by
// level, a level voxel answers with its block's centre voxel at the receiver's own slice.
//
// The languages differ only in how the code reaches the encoded words and in reference parameters. The
// includer defines, before including this file:
//   ML_SV_FN          `inline` in C++, nothing in GLSL
//   ML_SV_DATA_PARAM  the leading parameter: `const uint32_t* data,` in C++, nothing in GLSL
//   ML_SV_DATA_ARG    the leading argument of a decoder call: `data,` or nothing
//   ML_SV_WORD(i)     word i: `data[i]` or `ML_STATIC_DATA[i]`
//   ML_SV_INOUT(T)    an in-out parameter of type T: `T&` or `inout T`
// and makes callable, as GLSL names them: the decoders of mh_descent.h, dagmh_decode.h and
// cpvs_decode.h (with the same leading argument), cpvsVoxelNormal(vec3, float, float, float, float)
// returning an ivec3, shadow_record.h's functions, the vector types vec2, vec3, ivec2, ivec3 and the
// built-ins clamp, floor, min and max on the types used below. This file undefines the five macros at
// its end; its includers guard it.

// float version of quantizeDepth: 4294967040 is the largest float below 2^32.
ML_SV_FN uint staticQuantize(float z, float far) {
    float t = clamp(z / far, 0.0f, 1.0f);
    return t >= 1.0f ? 0xFFFFFFFEu : uint(t * 4294967040.0f);
}

ML_SV_FN uint staticDepthAt(ML_SV_DATA_PARAM uint method, uint base, uint x, uint y) {
    if (method == ML_STATIC_SM) {
        // Version 2 (a directional map fitted to its box) stores only its rows (word 5).
        uint rows = ML_SV_WORD(base + 1u) == 2u ? ML_SV_WORD(base + 5u) : ML_SV_WORD(base + 2u);
        if (y >= rows) return 0xFFFFFFFFu;
        return ML_SV_WORD(base + 6u + y * ML_SV_WORD(base + 2u) + x);
    }
    if (method == ML_STATIC_MH) return mhLookup(ML_SV_DATA_ARG base, x, y);
    if (method == ML_STATIC_MMH) return mmhLookup(ML_SV_DATA_ARG base, x, y);
    return dagmhLookup(ML_SV_DATA_ARG base, x, y);
}

// The depth of texel (x, y) of the level `step` above the finest (MH and MMH; step 0 is the map; DAG-MH
// levels: dagmhPcfLitLevel).
ML_SV_FN uint staticDepthAtLevel(ML_SV_DATA_PARAM uint method, uint base, uint x, uint y, uint step) {
    if (step == 0u) return staticDepthAt(ML_SV_DATA_ARG method, base, x, y);
    uint steps = ML_SV_WORD(base + ML_MH_LEVELS) - step;
    return method == ML_STATIC_MH ? mhLookupLevel(ML_SV_DATA_ARG base, x, y, steps)
                                  : mmhLookupLevel(ML_SV_DATA_ARG base, x, y, steps);
}

// The value a kernel's tap located (st, at full-resolution texel (x, y)): a tap with the previous tap's
// value index reuses its value (same MH node) unless the value is a plane (it differs per texel), and one
// in the same chunk the chunk's 8 words (only its factor bits are read).
struct DagmhMemo {
    uint index, value, chunkIndex;
    DagmhChunk chunk;
};

ML_SV_FN DagmhMemo dagmhMemoNone() {
    DagmhMemo m;
    m.index = 0xFFFFFFFFu, m.value = 0u, m.chunkIndex = 0xFFFFFFFFu;
    // Never read before dagmhMemoValue sets it (no chunk index matches the one above); set so that the
    // C++ build copies no indeterminate words.
    m.chunk.bm = 0u, m.chunk.a0 = 0u, m.chunk.a1 = 0u, m.chunk.widths = 0u, m.chunk.off = 0u,
    m.chunk.slopes = 0u, m.chunk.planar = 0u, m.chunk.pbase = 0u;
    return m;
}

ML_SV_FN uint dagmhMemoValue(ML_SV_DATA_PARAM DagmhHeader dh, ML_SV_INOUT(DagmhMemo) m, DagmhState st, uint x,
                             uint y) {
    if (st.vlast == m.index) return m.value;
    if ((st.vlast >> 5u) != m.chunkIndex) {
        m.chunkIndex = st.vlast >> 5u;
        m.chunk = dagmhChunk(ML_SV_DATA_ARG dh, m.chunkIndex);
    }
    uint s = dh.L - st.dlast;
    m.value = dagmhChunkValue(ML_SV_DATA_ARG dh, m.chunk, st.vlast & 31u, (x >> s) << s, (y >> s) << s, x, y);
    m.index = dagmhSlotPlanar(m.chunk, st.vlast & 31u) ? 0xFFFFFFFFu : st.vlast;
    return m.value;
}

// DAG-MH PCF: the number of lit taps of [t - r, t + r] (taps outside the map count as lit; a tap is lit
// when depth <= its decoded value). Hierarchical, and exact (each tap gets the value index and node depth
// that dagmhLookup finds, so the count equals a per-tap loop's):
// - the kernel's taps share the descent to the node that holds them all (dagmhPcfPrefix); when that
//   descent ends in a treelet, the taps share its 3 words too (read once, not once per tap);
// - a tap with the previous tap's value index reuses its value, and one in the same chunk the chunk's
//   words (dagmhMemoValue);
// - first of all, the value bounds of the cells the kernel covers (dagmhBoundsClass) decide it
//   whole when the receiver is nearer than every value there (all lit) or farther than every one.
ML_SV_FN uint dagmhPcfLit(ML_SV_DATA_PARAM DagmhHeader dh, ivec2 t, int radius, int res, uint depth) {
    uint taps = uint((2 * radius + 1) * (2 * radius + 1));
    ivec2 lo = max(t - radius, ivec2(0)), hi = min(t + radius, ivec2(res - 1));
    if (lo.x > hi.x || lo.y > hi.y) return taps;
    uint lit = taps - uint((hi.x - lo.x + 1) * (hi.y - lo.y + 1));
    // The value bounds decide most kernels whole: every in-map tap lit, or none.
    uint k = dagmhBoundsClass(ML_SV_DATA_ARG dh, uint(lo.x), uint(lo.y), uint(hi.x), uint(hi.y), depth);
    if (k != 0u) return k == 1u ? taps : lit;
    dh = dagmhSections(ML_SV_DATA_ARG dh);
    DagmhState prefix = dagmhPcfPrefix(ML_SV_DATA_ARG dh, uint(lo.x), uint(lo.y), uint(hi.x), uint(hi.y));
    bool usePrefix = prefix.kind != ML_DAG_NO_PREFIX;
    bool sharedTreelet = prefix.kind == 2u;
    uint t0 = 0u, t1 = 0u, t2 = 0u;
    if (sharedTreelet) {
        uint tb = dh.treelets + ML_DAG_TREELET_WORDS * prefix.ptr;
        t0 = ML_SV_WORD(tb), t1 = ML_SV_WORD(tb + 1u), t2 = ML_SV_WORD(tb + 2u);
    }
    DagmhMemo memo = dagmhMemoNone();
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            DagmhState st;
            if (sharedTreelet)
                st = dagmhTreelet(dh, uint(x), uint(y), prefix, t0, t1, t2, dh.L);
            else
                st = dagmhLocate(ML_SV_DATA_ARG dh, uint(x), uint(y),
                                 usePrefix ? prefix : dagmhStart(ML_SV_DATA_ARG dh, uint(x), uint(y)));
            if (depth <= dagmhMemoValue(ML_SV_DATA_ARG dh, memo, st, uint(x), uint(y))) lit += 1u;
        }
    return lit;
}

// DAG-MH PCF by level: the lit taps of [t - r, t + r] on the map `steps` levels below the root, t a texel of
// that map (levelRes a side). Each tap gets the value dagmhLookupLevel finds, with the taps sharing the
// descent above the level where they part and a tap with the previous tap's value index reusing its value.
// No value bounds here (dagmhLookupLevel says why).
ML_SV_FN uint dagmhPcfLitLevel(ML_SV_DATA_PARAM DagmhHeader dh, ivec2 t, int radius, int levelRes, uint depth,
                               uint steps) {
    uint taps = uint((2 * radius + 1) * (2 * radius + 1));
    ivec2 lo = max(t - radius, ivec2(0)), hi = min(t + radius, ivec2(levelRes - 1));
    if (lo.x > hi.x || lo.y > hi.y) return taps;
    uint lit = taps - uint((hi.x - lo.x + 1) * (hi.y - lo.y + 1));
    dh = dagmhSections(ML_SV_DATA_ARG dh);
    uint sh = dh.L - steps;
    // The taps' full-resolution texels (x << sh) take the same children down to depth L - (bits of the
    // widest difference), and never past `steps`.
    uint diff = (uint(lo.x ^ hi.x) | uint(lo.y ^ hi.y)) << sh;
    uint bits = 0u;
    while ((diff >> bits) != 0u) ++bits;
    uint sharedLevels = min(dh.L - bits, steps);
    uint X0 = uint(lo.x) << sh, Y0 = uint(lo.y) << sh;
    // Above the skip level each tap starts at the root (dagmhLevelStart), and so does a shared prefix.
    DagmhState prefix = dagmhDescend(ML_SV_DATA_ARG dh, X0, Y0,
                                     dagmhLevelStart(ML_SV_DATA_ARG dh, X0, Y0, sharedLevels), sharedLevels);
    DagmhMemo memo = dagmhMemoNone();
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
            uint X = uint(x) << sh, Y = uint(y) << sh;
            if (depth <= dagmhMemoValue(ML_SV_DATA_ARG dh, memo,
                                        dagmhLevelLocate(ML_SV_DATA_ARG dh, X, Y, prefix, steps), X, Y))
                lit += 1u;
        }
    return lit;
}

// The depth methods' mapping (SM, MH, MMH, DAG-MH): the receiver at view position vp (in front of the
// near plane) with view normal vn, offset along the normal, to its centre tap t and its quantised, biased
// depth. With filtering by level (MH, MMH, DAG-MH), step is the level above the finest and t a texel of
// that level. lit: the offset receiver lies before the near plane (t and depth are then not set).
struct StaticDepthTap {
    ivec2 t;
    uint depth, step;
    bool lit;
};

ML_SV_FN StaticDepthTap staticDepthTap(ML_SV_DATA_PARAM GpuShadowRecord rec, vec3 vp, vec3 vn,
                                       float footprint2) {
    uint method = shadowRecordMethod(rec), base = rec.info.y, res = shadowRecordResolution(rec);
    int radius = int(shadowRecordRadius(rec));
    float tanHalf = rec.frustum.x, far = rec.frustum.z;
    // frustum.x < 0: an orthographic map (directional light) of half side -frustum.x.
    bool ortho = tanHalf < 0.0f;
    float orthoHalf = -tanHalf;
    float z = -vp.z;
    StaticDepthTap tap;
    tap.t = ivec2(0), tap.depth = 0u;
    float texelWorld = ortho ? 2.0f * orthoHalf / float(res) : 2.0f * z * tanHalf / float(res);
    // Filtering by level (MH, MMH, DAG-MH): the taps, the normal offset and the depth bias are those of the
    // level shadowLevelStep picks, so a distant receiver does not walk the whole hierarchy.
    tap.step = 0u;
    if (shadowRecordByLevel(rec) &&
        (method == ML_STATIC_MH || method == ML_STATIC_MMH || method == ML_STATIC_DAGMH))
        tap.step = shadowLevelStep(texelWorld, footprint2,
                                   ML_SV_WORD(base + ML_MH_LEVELS)); // L: word 3 of all three
    texelWorld = texelWorld * float(1u << tap.step);
    // Normal offset of (1 + radius) texels: the PCF taps reach `radius` texels to the side, and on a
    // surface at a grazing angle to the light (flat ground under a low point light's side faces) the taps
    // on the light's side of the receiver see the same surface nearer than the receiver unless it is
    // lifted past them (GpuPointShadow.NoAcneOnFlatGroundOrBoxFaces: stripes of self-shadow with PCF).
    // Per light (GpuShadowRecord.bias): a scale on that offset and the depth bias (defaults 1 and 0.5).
    vec3 q = vp + vn * (texelWorld * float(1 + radius) * rec.bias.y);
    float zq = -q.z;
    tap.lit = zq <= rec.frustum.y;
    if (tap.lit) return tap;
    vec2 ndc = ortho ? vec2(q.x, q.y) / orthoHalf : vec2(q.x, q.y) / (zq * tanHalf);
    tap.t = ivec2(floor((ndc * 0.5f + 0.5f) * float(res))) >> int(tap.step);
    tap.depth = staticQuantize(max(zq - rec.bias.x * texelWorld, 0.0f), far);
    return tap;
}

// footprint2: the squared world size of the receiver's pixel (shadowFootprint2), read only when the record
// filters by level.
ML_SV_FN float staticVisibility(ML_SV_DATA_PARAM GpuShadowRecord rec, vec3 P, vec3 N, float footprint2) {
    uint method = shadowRecordMethod(rec), base = rec.info.y, res = shadowRecordResolution(rec);
    int radius = int(shadowRecordRadius(rec));
    float tanHalf = rec.frustum.x, far = rec.frustum.z;
    bool ortho = tanHalf < 0.0f;
    float orthoHalf = -tanHalf;
    vec3 vp = shadowViewPoint(rec, P);
    vec3 vn = shadowViewVector(rec, N);
    float z = -vp.z;
    if (z <= rec.frustum.y) return 1.0f;
    if (method == ML_STATIC_CPVS) {
        vec2 ndc = ortho ? vec2(vp.x, vp.y) / orthoHalf : vec2(vp.x, vp.y) / (z * tanHalf);
        ivec2 t = ivec2(floor((ndc * 0.5f + 0.5f) * float(res)));
        uint s = cpvsSliceOfDepth(ML_SV_DATA_ARG base, staticQuantize(z, far));
        // Orthographic maps slice depth linearly: frustum.w is far - near there (log(far / near) else), and
        // du = N dx / (2 h), dw = N dz / (far - near) is the perspective formula with ndc = 0, tan = h.
        ivec3 nq = ortho ? cpvsVoxelNormal(vn, 0.0f, 0.0f, orthoHalf, rec.frustum.w)
                         : cpvsVoxelNormal(vn, ndc.x, ndc.y, tanHalf, rec.frustum.w);
        // Filtering by level: the level whose texel is at most a quarter of the pixel, as for the depth
        // methods (at most log2 N levels up: one texel for the map).
        uint step = 0u;
        if (shadowRecordByLevel(rec)) {
            float texelWorld = ortho ? 2.0f * orthoHalf / float(res) : 2.0f * z * tanHalf / float(res);
            step = shadowLevelStep(texelWorld, footprint2, ML_SV_WORD(base + CPVS_H_LOG2_RESOLUTION));
        }
        uint lit = cpvsPcfLitLevel(ML_SV_DATA_ARG base, t.x, t.y, int(s), nq.x, nq.y, nq.z, radius, step);
        return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
    }
    StaticDepthTap tap = staticDepthTap(ML_SV_DATA_ARG rec, vp, vn, footprint2);
    if (tap.lit) return 1.0f;
    ivec2 t = tap.t;
    uint depth = tap.depth, step = tap.step;
    // With filtering by level (step > 0), the taps are texels of that level's map.
    int levelRes = int((res + (1u << step) - 1u) >> step);
    if (method == ML_STATIC_DAGMH) {
        DagmhHeader dh = dagmhHeaderTop(ML_SV_DATA_ARG base, dagmhLevels(res)); // once for all taps
        uint lit = 0u;
        if (step > 0u) {
            lit = dagmhPcfLitLevel(ML_SV_DATA_ARG dh, t, radius, levelRes, depth, dh.L - step);
        } else if (radius == 0) {
            bool inside = t.x >= 0 && t.y >= 0 && t.x < int(res) && t.y < int(res);
            uint k = inside ? dagmhBoundsClass1(ML_SV_DATA_ARG dh, uint(t.x), uint(t.y), depth) : 1u;
            if (k == 0u)
                k = depth <= dagmhLookupH(ML_SV_DATA_ARG dagmhSections(ML_SV_DATA_ARG dh), uint(t.x),
                                          uint(t.y))
                        ? 1u
                        : 2u;
            lit = k == 1u ? 1u : 0u;
        } else {
            lit = dagmhPcfLit(ML_SV_DATA_ARG dh, t, radius, int(res), depth);
        }
        return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
    }
    uint lit = 0u;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            int x = t.x + dx, y = t.y + dy;
            // Outside the map the light's cone does not reach: count as lit.
            if (x < 0 || y < 0 || x >= levelRes || y >= levelRes) {
                lit += 1u;
                continue;
            }
            if (depth <= staticDepthAtLevel(ML_SV_DATA_ARG method, base, uint(x), uint(y), step)) lit += 1u;
        }
    return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
}

#undef ML_SV_FN
#undef ML_SV_DATA_PARAM
#undef ML_SV_DATA_ARG
#undef ML_SV_WORD
#undef ML_SV_INOUT
