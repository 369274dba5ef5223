// MMH lookup: line-by-line twin of mmhLookup in shadows/static/mmh.h (MH layout, relative values).
#ifndef ML_MMH_LOOKUP_GLSL
#define ML_MMH_LOOKUP_GLSL
#include "mh_lookup.glsl" // the header word indices (ML_MH_*): MMH has MH's layout

uint mmhLookupLevel(uint base, uint x, uint y, uint steps) {
    uint nodeOffset = ML_STATIC_DATA[base + ML_MH_NODE_OFFSET];
    uint p = base + nodeOffset;
    uint value = ML_STATIC_DATA[p];
    if (ML_STATIC_DATA[base + ML_MH_ROOT_TYPE] == 1u) return value;
    uint shift = nodeOffset > ML_MH_HEADER_WORDS ? ML_STATIC_DATA[base + ML_MH_FAR_SHIFT] : 0u;
    uint farBit = shift != 0u ? ML_MH_FAR_BIT : 0u;
    uint hp = p + 1u;
    uint hdr = ML_STATIC_DATA[hp];
    for (uint s = steps; s > 0u; --s) {
        uint c = (((y >> (s - 1u)) & 1u) << 1u) | ((x >> (s - 1u)) & 1u);
        uint t = (hdr >> (2u * c)) & 3u;
        if (t == 0u) return value;
        uint off = hdr >> 8u;
        uint q = (off & farBit) != 0u ? base + ((off & (ML_MH_FAR_BIT - 1u)) << shift) : hp + off;
        // Record sizes by type: absent 0, leaf 1, full 2, empty 1 (2-bit table 0x64).
        for (uint i = 0u; i < c; ++i) q += (0x64u >> (2u * ((hdr >> (2u * i)) & 3u))) & 3u;
        if (t != 3u) {
            value += ML_STATIC_DATA[q]; // relative to the nearest valued ancestor, wrapping mod 2^32
            q += 1u;
        }
        if (t == 1u) return value;
        hp = q;
        hdr = ML_STATIC_DATA[hp];
    }
    return value;
}

uint mmhLookup(uint base, uint x, uint y) { return mmhLookupLevel(base, x, y, ML_STATIC_DATA[base + ML_MH_LEVELS]); }

#endif
