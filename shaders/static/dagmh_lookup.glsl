// DAG-MH lookups: twins of dagmhValue / dagmhLookup / dagmhLookupLevel (a level above the finest, for
// filtering by level) in shadows/static/dagmh.h, the same steps except that
// the header words are read once into DagmhHeader (the CPU twin reads them where used; same values) (layout
// documented there and in docs/dagmh-encoding.md).
#ifndef ML_DAGMH_LOOKUP_GLSL
#define ML_DAGMH_LOOKUP_GLSL
#include "common_static.glsl"

// Header word indices and record sizes (dagfmt).
const uint ML_DAG_LEVELS = 3u;
const uint ML_DAG_SKIP_LEVEL = 4u;
const uint ML_DAG_ROOT_KIND = 5u;
const uint ML_DAG_ROOT_PTR = 6u;
const uint ML_DAG_SKIP_OFFSET = 9u;
const uint ML_DAG_NODE_OFFSET = 10u;
const uint ML_DAG_TREELET_OFFSET = 12u;
const uint ML_DAG_CHUNK_OFFSET = 14u;
const uint ML_DAG_FACTOR_OFFSET = 15u;
const uint ML_DAG_SLOPE_OFFSET = 20u;
const uint ML_DAG_CHUNK_WORDS = 6u;
const uint ML_DAG_SLOPE_WORDS = 2u;
const uint ML_DAG_TREELET_WORDS = 3u;
const uint ML_DAG_SKIP_WORDS = 4u;
const uint ML_DAG_HEADER_WORDS = 22u;

// The header words the lookup needs, read once per lookup (or once per PCF kernel): in the evaluation
// pass every buffer read is a gather across the lanes (lavapipe), and these were re-read by each step
// and each tap. Section offsets are absolute (base added).
struct DagmhHeader {
    uint L, S, B, base, skip, bounds, nodes, treelets, chunks, slopes, factors;
};

// In two steps, so that a lookup the value bounds decide reads one header word (S): the levels and the
// fixed-place sections first (L given: validate() makes it the resolution's ceil(log2), dagmhLevels),
// the three section offsets a descent needs only when it descends (dagmhSections).
uint dagmhLevels(uint res) {
    return res > 1u ? uint(findMSB(res - 1u)) + 1u : 0u;
}

DagmhHeader dagmhHeaderTop(uint base, uint L) {
    DagmhHeader h;
    h.L = L;
    uint levels = ML_STATIC_DATA[base + ML_DAG_SKIP_LEVEL]; // S | B << 8 (dagfmt::skipLevel, boundsLevel)
    h.S = levels & 255u;
    h.B = levels >> 8u;
    // validate() requires the sections to tile the buffer from the header on: the skip list at word 22,
    // the value bounds after its 4^S entries and the nodes after their 4^B words, so those offsets need
    // no read.
    h.skip = base + ML_DAG_HEADER_WORDS;
    h.bounds = h.skip + (ML_DAG_SKIP_WORDS << (2u * h.S));
    h.nodes = h.bounds + (1u << (2u * h.B));
    h.base = base;
    h.treelets = 0u, h.chunks = 0u, h.slopes = 0u, h.factors = 0u;
    return h;
}

DagmhHeader dagmhSections(DagmhHeader h) {
    h.treelets = h.base + ML_STATIC_DATA[h.base + ML_DAG_TREELET_OFFSET];
    h.chunks = h.base + ML_STATIC_DATA[h.base + ML_DAG_CHUNK_OFFSET];
    h.slopes = h.base + ML_STATIC_DATA[h.base + ML_DAG_SLOPE_OFFSET];
    h.factors = h.base + ML_STATIC_DATA[h.base + ML_DAG_FACTOR_OFFSET];
    return h;
}

DagmhHeader dagmhHeader(uint base) {
    return dagmhSections(dagmhHeaderTop(base, ML_STATIC_DATA[base + ML_DAG_LEVELS]));
}

// The b-bit field at bit `pos` of the factor stream (0 when b is 0); it may straddle two words.
uint dagmhField(DagmhHeader h, uint pos, uint b) {
    if (b == 0u) return 0u;
    uint w = h.factors + (pos >> 5u);
    uint sh = pos & 31u;
    uint f = ML_STATIC_DATA[w] >> sh;
    if (sh + b > 32u) f |= ML_STATIC_DATA[w + 1u] << (32u - sh);
    return f & mlLowMask(b);
}

// A chunk's 6 words, read once (PCF: the taps of a kernel mostly fall in one or two chunks, so a kernel
// keeps the last chunk and reads only factor bits and a slope entry for the other taps).
struct DagmhChunk {
    uint bm, a0, a1, widths, off, slopes;
};

DagmhChunk dagmhChunk(DagmhHeader h, uint chunk) {
    uint ch = h.chunks + ML_DAG_CHUNK_WORDS * chunk;
    DagmhChunk c;
    c.bm = ML_STATIC_DATA[ch];
    c.a0 = ML_STATIC_DATA[ch + 1u];
    c.a1 = ML_STATIC_DATA[ch + 2u];
    c.widths = ML_STATIC_DATA[ch + 3u];
    c.off = ML_STATIC_DATA[ch + 4u];
    c.slopes = ML_STATIC_DATA[ch + 5u];
    return c;
}

// Slot j of a chunk (twin of dagmhChunkSlot): class = bit j of the bitmap, value = A + B_x px + B_y py +
// (factor << sh) with the class's plane, width and step; class 0's factors follow class 1's.
uint dagmhChunkValue(DagmhHeader h, DagmhChunk c, uint j, uint px, uint py) {
    uint cls = (c.bm >> j) & 1u;
    uint before1 = mlPopc(c.bm & mlLowMask(j));
    uint cw = cls != 0u ? c.widths >> 11u : c.widths;
    uint b = cw & 63u;
    uint pos = c.off + (cls != 0u ? before1 * b : mlPopc(c.bm) * ((c.widths >> 11u) & 63u) + (j - before1) * b);
    uint f = dagmhField(h, pos, b);
    if (b == 32u) return f; // raw 32-bit value
    uint e = h.slopes + ML_DAG_SLOPE_WORDS * (cls != 0u ? c.slopes >> 16u : c.slopes & 0xFFFFu);
    uint a = cls != 0u ? c.a1 : c.a0;
    return a + ML_STATIC_DATA[e] * px + ML_STATIC_DATA[e + 1u] * py + (f << ((cw >> 6u) & 31u));
}

// Value retrieval (paper Alg. 2, integer version, two plane classes a chunk). (px, py) is the texel at the
// top-left corner of the cell of the MH node that holds the value.
uint dagmhValue(DagmhHeader h, uint index, uint px, uint py) {
    return dagmhChunkValue(h, dagmhChunk(h, index >> 5u), index & 31u, px, py);
}

// The lookup in steps (twin of dagmhStart / dagmhDescend / dagmhLocate / dagmhLocatedValue / dagmhFinish /
// dagmhPcfPrefix).
struct DagmhState {
    uint kind, depth, dlast, ptr, vcount, vlast;
};

DagmhState dagmhStart(DagmhHeader h, uint x, uint y) {
    uint e = h.skip + ML_DAG_SKIP_WORDS * (((y >> (h.L - h.S)) << h.S) + (x >> (h.L - h.S)));
    uint w0 = ML_STATIC_DATA[e];
    DagmhState st;
    st.kind = w0 & 255u;
    st.depth = (w0 >> 8u) & 255u;
    st.dlast = w0 >> 16u; // depth of the node that holds value vlast
    st.ptr = ML_STATIC_DATA[e + 1u];
    st.vcount = ML_STATIC_DATA[e + 2u];
    st.vlast = ML_STATIC_DATA[e + 3u];
    return st;
}

DagmhState dagmhDescend(DagmhHeader h, uint x, uint y, DagmhState st, uint stop) {
    while (st.kind == 1u) {
        if (st.depth >= stop) break;
        uint flags = ML_STATIC_DATA[h.nodes + st.ptr];
        if ((flags & 256u) != 0u) {
            st.vlast = st.vcount;
            st.dlast = st.depth;
        }
        if (st.depth >= h.L) break;
        uint s = h.L - st.depth - 1u;
        uint c = (((y >> s) & 1u) << 1u) | ((x >> s) & 1u);
        uint t = (flags >> (2u * c)) & 3u;
        if (t == 0u) break;
        // Bit 2i of `present` is set when child i exists (type != 0): rank = present children before c,
        // n = present children (the CPU twin counts them in a loop; same numbers).
        uint present = (flags | (flags >> 1u)) & 0x55u;
        uint rank = mlPopc(present & mlLowMask(2u * c));
        uint n = mlPopc(present);
        uint child = ML_STATIC_DATA[h.nodes + st.ptr + 1u + rank];
        st.vcount += rank == 0u ? ((flags >> 8u) & 1u) : ML_STATIC_DATA[h.nodes + st.ptr + n + rank];
        st.ptr = child;
        st.depth += 1u;
        st.kind = t;
    }
    return st;
}

// The treelet step of the lookup, from the treelet's 3 words (read once by the caller: then the level
// loop tests bits without further reads, and the taps of a PCF quad share them). Positions deeper than
// `limit` are not looked at (h.L for the map, less for a level above it: dagmhLookupLevel).
DagmhState dagmhTreelet(DagmhHeader h, uint x, uint y, DagmhState st, uint t0, uint t1, uint t2, uint limit) {
    for (uint i = 0u; i < 4u; ++i) {
        uint lvl = 3u - i;
        if (st.depth + lvl > limit) continue;
        uint idx = lvl;
        for (uint j = 1u; j <= lvl; ++j) {
            uint s = h.L - st.depth - j;
            uint c = (((y >> s) & 1u) << 1u) | ((x >> s) & 1u);
            idx += c * (j == 1u ? 21u : (j == 2u ? 5u : 1u));
        }
        uint wi = idx >> 5u;
        uint word = wi == 0u ? t0 : (wi == 1u ? t1 : t2);
        if (((word >> (idx & 31u)) & 1u) != 0u) {
            uint before = mlPopc(word & mlLowMask(idx & 31u));
            if (wi > 0u) before += mlPopc(t0);
            if (wi > 1u) before += mlPopc(t1);
            st.vlast = st.vcount + before;
            st.dlast = st.depth + lvl;
            break;
        }
    }
    return st;
}

DagmhState dagmhLocate(DagmhHeader h, uint x, uint y, DagmhState st) {
    st = dagmhDescend(h, x, y, st, h.L + 1u);
    if (st.kind == 2u) {
        uint tb = h.treelets + ML_DAG_TREELET_WORDS * st.ptr;
        st = dagmhTreelet(h, x, y, st, ML_STATIC_DATA[tb], ML_STATIC_DATA[tb + 1u], ML_STATIC_DATA[tb + 2u], h.L);
    }
    return st;
}

uint dagmhLocatedValue(DagmhHeader h, uint x, uint y, DagmhState st) {
    uint s = h.L - st.dlast;
    return dagmhValue(h, st.vlast, (x >> s) << s, (y >> s) << s);
}

uint dagmhFinish(DagmhHeader h, uint x, uint y, DagmhState st) {
    return dagmhLocatedValue(h, x, y, dagmhLocate(h, x, y, st));
}

uint dagmhLookupH(DagmhHeader h, uint x, uint y) {
    return dagmhFinish(h, x, y, dagmhStart(h, x, y));
}

uint dagmhLookup(uint base, uint x, uint y) {
    return dagmhLookupH(dagmhHeader(base), x, y);
}

// Level lookups (twin of dagmhLookupLevel in dagmh.h, which says why it starts at the root above the skip
// level and does not use the value bounds), in two steps so that the taps of a kernel can share the
// descent (dagmhPcfLitLevel): where the lookup of full-resolution texel (X, Y) at depth `steps` starts,
// and the rest of it from a state above that depth.
DagmhState dagmhLevelStart(DagmhHeader h, uint X, uint Y, uint steps) {
    if (steps >= h.S) return dagmhStart(h, X, Y);
    DagmhState st;
    st.kind = ML_STATIC_DATA[h.base + ML_DAG_ROOT_KIND];
    st.ptr = ML_STATIC_DATA[h.base + ML_DAG_ROOT_PTR];
    st.depth = 0u, st.dlast = 0u, st.vcount = 0u, st.vlast = 0u;
    return st;
}

DagmhState dagmhLevelLocate(DagmhHeader h, uint X, uint Y, DagmhState st, uint steps) {
    st = dagmhDescend(h, X, Y, st, steps);
    if (st.kind == 1u && st.depth == steps && (ML_STATIC_DATA[h.nodes + st.ptr] & 256u) != 0u) {
        st.vlast = st.vcount;
        st.dlast = steps;
    }
    if (st.kind == 2u) {
        uint tb = h.treelets + ML_DAG_TREELET_WORDS * st.ptr;
        st = dagmhTreelet(h, X, Y, st, ML_STATIC_DATA[tb], ML_STATIC_DATA[tb + 1u], ML_STATIC_DATA[tb + 2u], steps);
    }
    return st;
}

// The map at the level `steps` below the root, (x, y) a texel of that level.
uint dagmhLookupLevel(uint base, uint x, uint y, uint steps) {
    DagmhHeader h = dagmhHeader(base);
    uint X = x << (h.L - steps), Y = y << (h.L - steps); // the level texel's top-left full texel
    return dagmhLocatedValue(h, X, Y, dagmhLevelLocate(h, X, Y, dagmhLevelStart(h, X, Y, steps), steps));
}

// The bounds test (twin of dagmhBoundsClass in dagmh.h): 1 when every texel of [x0, x1] x [y0, y1] is lit
// at receiver depth `depth` (depth <= its value), 2 when none is, 0 when the value bounds of the cells
// of level B it covers do not decide. A lit or shadowed answer skips the descent and the value decode:
// one word per cell (a 3x3 kernel covers 1-4 cells of 3x3 texels or more, up to 9 of smaller ones).
// A kernel within 2x2 cells (every 3x3 kernel on cells of 8x8 texels) reads four words without a loop,
// a cell twice when it covers one row or column of cells: the same minimum and maximum, without the
// loop's per-lane masks (lavapipe: 3x3 PCF ~7 % faster).
uint dagmhBoundsClass(DagmhHeader h, uint x0, uint y0, uint x1, uint y1, uint depth) {
    uint sh = h.L - h.B;
    uint lo = 0xFFFFFFFFu, hi = 0u;
    uint X0 = x0 >> sh, X1 = x1 >> sh, Y0 = y0 >> sh, Y1 = y1 >> sh;
    if (X1 - X0 <= 1u && Y1 - Y0 <= 1u) {
        uint r0 = h.bounds + (Y0 << h.B), r1 = h.bounds + (Y1 << h.B);
        uint a = ML_STATIC_DATA[r0 + X0], b = ML_STATIC_DATA[r0 + X1];
        uint c = ML_STATIC_DATA[r1 + X0], d = ML_STATIC_DATA[r1 + X1];
        lo = min(min(a << 16u, b << 16u), min(c << 16u, d << 16u));
        hi = max(max(a | 0xFFFFu, b | 0xFFFFu), max(c | 0xFFFFu, d | 0xFFFFu));
        return depth <= lo ? 1u : (depth > hi ? 2u : 0u);
    }
    for (uint Y = y0 >> sh; Y <= (y1 >> sh); ++Y)
        for (uint X = x0 >> sh; X <= (x1 >> sh); ++X) {
            uint w = ML_STATIC_DATA[h.bounds + (Y << h.B) + X];
            uint wl = w << 16u, wh = w | 0xFFFFu;
            lo = wl < lo ? wl : lo;
            hi = wh > hi ? wh : hi;
        }
    return depth <= lo ? 1u : (depth > hi ? 2u : 0u);
}

// The same test for one texel (the one-tap lookup): its cell's word alone, without the loops (lavapipe:
// the one tap ~4 % faster).
uint dagmhBoundsClass1(DagmhHeader h, uint x, uint y, uint depth) {
    uint sh = h.L - h.B;
    uint w = ML_STATIC_DATA[h.bounds + ((y >> sh) << h.B) + (x >> sh)];
    return depth <= (w << 16u) ? 1u : (depth > (w | 0xFFFFu) ? 2u : 0u);
}

// kind = ML_DAG_NO_PREFIX when the block straddles skip-list entries (each tap then starts alone).
const uint ML_DAG_NO_PREFIX = 255u;
DagmhState dagmhPcfPrefix(DagmhHeader h, uint x0, uint y0, uint x1, uint y1) {
    uint diff = (x0 ^ x1) | (y0 ^ y1);
    uint bits = 0u;
    while ((diff >> bits) != 0u) ++bits;
    uint sharedLevels = h.L - bits; // levels above which every tap takes the same children
    DagmhState st = dagmhStart(h, x0, y0);
    if (sharedLevels < h.S) {
        st.kind = ML_DAG_NO_PREFIX;
        return st;
    }
    return dagmhDescend(h, x0, y0, st, sharedLevels);
}

#endif
