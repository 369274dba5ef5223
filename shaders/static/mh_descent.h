// The MH and MMH lookups, one source text for the C++ decoders (shadows/static/mh.h, mmh.h) and the GLSL
// ones (shaders/static/mh_lookup.glsl, mmh_lookup.glsl), as shaders/shared/light_math.h is for the light
// tests: both run the same integer operations in the same order, so they decode every texel alike. The
// layout is in shadows/static/mh.h's header comment (version 1, and version 2 with far child groups).
//
// The languages differ only in how a decoder reaches its words: C++ passes the buffer, GLSL reads the
// SSBO array named ML_STATIC_DATA (shaders/static/common_static.glsl). The includer defines, before
// including this file:
//   ML_MH_FN          `inline` in C++, nothing in GLSL
//   ML_MH_DATA_PARAM  the leading parameter: `const uint32_t* data,` in C++, nothing in GLSL
//   ML_MH_DATA_ARG    the matching argument: `data,` or nothing
//   ML_MH_WORD(i)     word i: `data[i]` or `ML_STATIC_DATA[i]`
// and `uint` must name a 32-bit unsigned integer. This file undefines the four at its end. It has no
// include guard: its two includers guard it, and the tests compile both texts into one program (the GLSL
// one as C++ in a namespace of its own: tests/static/glsl_shims.h).

// Header word indices (mhfmt in shadows/static/mh.h, which asserts them equal).
const uint ML_MH_LEVELS = 3u;
const uint ML_MH_ROOT_TYPE = 4u;
const uint ML_MH_NODE_OFFSET = 5u;
const uint ML_MH_HEADER_WORDS = 12u; // version 1; version 2 (far groups) has 14
const uint ML_MH_FAR_SHIFT = 12u;
const uint ML_MH_FAR_BIT = 0x800000u;

// The descent from the root to the level `steps` below it (steps <= levels; a node of that level stands
// for 2^(levels - steps) texels a side), (x, y) a texel of that level. Returns the deepest valued node's
// value on the path: every level of the hierarchy is a complete map (the MMH paper's hierarchical
// filtering), exact at the finest (steps = levels) and an approximation above. MH stores absolute
// values; MMH (relative = true) stores each value relative to its nearest valued ancestor, and the
// descent adds them up, wrapping mod 2^32 (MH's 0 + value is the value itself, bit for bit).
ML_MH_FN uint mhDescend(ML_MH_DATA_PARAM uint base, uint x, uint y, uint steps, bool relative) {
    uint nodeOffset = ML_MH_WORD(base + ML_MH_NODE_OFFSET);
    uint p = base + nodeOffset;
    uint value = ML_MH_WORD(p);
    if (ML_MH_WORD(base + ML_MH_ROOT_TYPE) == 1u) return value;
    // Version 1 has no far groups: shift 0 and a far bit of 0 keep its 24-bit offsets.
    uint shift = nodeOffset > ML_MH_HEADER_WORDS ? ML_MH_WORD(base + ML_MH_FAR_SHIFT) : 0u;
    uint farBit = shift != 0u ? ML_MH_FAR_BIT : 0u;
    uint hp = p + 1u;
    uint hdr = ML_MH_WORD(hp);
    for (uint s = steps; s > 0u; --s) {
        uint c = (((y >> (s - 1u)) & 1u) << 1u) | ((x >> (s - 1u)) & 1u);
        uint t = (hdr >> (2u * c)) & 3u;
        if (t == 0u) return value;
        uint off = hdr >> 8u;
        uint q = (off & farBit) != 0u ? base + ((off & (ML_MH_FAR_BIT - 1u)) << shift) : hp + off;
        // Record sizes by type: absent 0, leaf 1, full 2, empty 1 (2-bit table 0x64).
        for (uint i = 0u; i < c; ++i) q += (0x64u >> (2u * ((hdr >> (2u * i)) & 3u))) & 3u;
        if (t != 3u) {
            value = (relative ? value : 0u) + ML_MH_WORD(q);
            q += 1u;
        }
        if (t == 1u) return value;
        hp = q;
        hdr = ML_MH_WORD(hp);
    }
    return value;
}

// The map at the level `steps` below the root (above), and the map itself (the finest level).
ML_MH_FN uint mhLookupLevel(ML_MH_DATA_PARAM uint base, uint x, uint y, uint steps) {
    return mhDescend(ML_MH_DATA_ARG base, x, y, steps, false);
}
ML_MH_FN uint mhLookup(ML_MH_DATA_PARAM uint base, uint x, uint y) {
    return mhDescend(ML_MH_DATA_ARG base, x, y, ML_MH_WORD(base + ML_MH_LEVELS), false);
}
ML_MH_FN uint mmhLookupLevel(ML_MH_DATA_PARAM uint base, uint x, uint y, uint steps) {
    return mhDescend(ML_MH_DATA_ARG base, x, y, steps, true);
}
ML_MH_FN uint mmhLookup(ML_MH_DATA_PARAM uint base, uint x, uint y) {
    return mhDescend(ML_MH_DATA_ARG base, x, y, ML_MH_WORD(base + ML_MH_LEVELS), true);
}

#undef ML_MH_FN
#undef ML_MH_DATA_PARAM
#undef ML_MH_DATA_ARG
#undef ML_MH_WORD
