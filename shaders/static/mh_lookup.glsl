// MH lookup: line-by-line twin of mhLookup in shadows/static/mh.h (layout documented there).
#ifndef ML_MH_LOOKUP_GLSL
#define ML_MH_LOOKUP_GLSL
#include "common_static.glsl"

// Header word indices (mhfmt).
const uint ML_MH_LEVELS = 3u;
const uint ML_MH_ROOT_TYPE = 4u;
const uint ML_MH_NODE_OFFSET = 5u;

uint mhLookup(uint base, uint x, uint y) {
    uint levels = ML_STATIC_DATA[base + ML_MH_LEVELS];
    uint p = base + ML_STATIC_DATA[base + ML_MH_NODE_OFFSET];
    uint value = ML_STATIC_DATA[p];
    if (ML_STATIC_DATA[base + ML_MH_ROOT_TYPE] == 1u) return value;
    uint hp = p + 1u;
    uint hdr = ML_STATIC_DATA[hp];
    for (uint s = levels; s > 0u; --s) {
        uint c = (((y >> (s - 1u)) & 1u) << 1u) | ((x >> (s - 1u)) & 1u);
        uint t = (hdr >> (2u * c)) & 3u;
        if (t == 0u) return value;
        uint q = hp + (hdr >> 8u);
        // Record sizes by type: absent 0, leaf 1, full 2, empty 1 (2-bit table 0x64).
        for (uint i = 0u; i < c; ++i) q += (0x64u >> (2u * ((hdr >> (2u * i)) & 3u))) & 3u;
        if (t != 3u) {
            value = ML_STATIC_DATA[q];
            q += 1u;
        }
        if (t == 1u) return value;
        hp = q;
        hdr = ML_STATIC_DATA[hp];
    }
    return value;
}

#endif
