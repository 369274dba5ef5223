// The DAG-MH lookups, one source text for the C++ decoder (shadows/static/dagmh.h) and the GLSL one
// (shaders/static/dagmh_lookup.glsl), as shaders/static/mh_descent.h is for MH: both run the same integer
// operations in the same order, so they decode every texel alike. The layout is in shadows/static/dagmh.h's
// header comment and docs/dagmh-encoding.md.
//
// The languages differ only in how a decoder reaches its words: C++ passes the buffer, GLSL reads the
// SSBO array named ML_STATIC_DATA (shaders/static/common_static.glsl). The includer defines, before
// including this file:
//   ML_DAG_FN          `inline` in C++, nothing in GLSL
//   ML_DAG_DATA_PARAM  the leading parameter: `const uint32_t* data,` in C++, nothing in GLSL
//   ML_DAG_DATA_ARG    the matching argument: `data,` or nothing
//   ML_DAG_WORD(i)     word i: `data[i]` or `ML_STATIC_DATA[i]`
// and `uint` must name a 32-bit unsigned integer; mlPopc(uint) and mlLowMask(uint) (common_static.glsl),
// findMSB(uint), min(uint, uint) and max(uint, uint) (GLSL built-ins) must be callable. This file
// undefines the four macros at its end. It has no include guard: its two includers guard it, and the
// tests compile both texts into one program (the GLSL one as C++ in a namespace of its own:
// tests/static/glsl_shims.h).

// Header word indices and record sizes (dagfmt in shadows/static/dagmh.h, which asserts them equal).
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
const uint ML_DAG_PLANE_OFFSET = 22u;
const uint ML_DAG_PLANES = 23u;
const uint ML_DAG_CHUNK_WORDS = 6u;        // 8 with a plane table (ML_DAG_PLANAR_CHUNK_WORDS)
const uint ML_DAG_PLANAR_CHUNK_WORDS = 8u; // + the planar bitmap and the plane base
const uint ML_DAG_SLOPE_WORDS = 2u;
const uint ML_DAG_SLOPE_FRACTION = 6u; // kOrthoSlopeFractionBits (shadows/static/dual_depth.h)
const uint ML_DAG_TREELET_WORDS = 3u;
const uint ML_DAG_SKIP_WORDS = 4u;
const uint ML_DAG_PLANE_WORDS = 3u;
const uint ML_DAG_HEADER_WORDS = 24u;
const uint ML_DAG_PLANAR_WIDTH_SHIFT = 27u; // a chunk's word 7: plane base (bits 0-26) | index width << 27

// The header words the lookup needs, read once per lookup (or once per PCF kernel): in the evaluation
// pass every buffer read is a gather across the lanes (lavapipe), and these were re-read by each step
// and each tap. Section offsets are absolute (base added).
struct DagmhHeader {
    uint L, S, B, base, skip, bounds, nodes, treelets, chunks, slopes, planes, factors;
    uint chunkWords; // ML_DAG_CHUNK_WORDS, or ML_DAG_PLANAR_CHUNK_WORDS when the map has a plane table
};

// In two steps, so that a lookup the value bounds decide reads one header word (S): the levels and the
// fixed-place sections first (L given: validate() makes it the resolution's ceil(log2), dagmhLevels),
// the four section offsets a descent or a value needs only when it descends (dagmhSections).
ML_DAG_FN uint dagmhLevels(uint res) {
    return res > 1u ? uint(findMSB(res - 1u)) + 1u : 0u;
}

ML_DAG_FN DagmhHeader dagmhHeaderTop(ML_DAG_DATA_PARAM uint base, uint L) {
    DagmhHeader h;
    h.L = L;
    uint levels = ML_DAG_WORD(base + ML_DAG_SKIP_LEVEL); // S | B << 8 (dagfmt::skipLevel, boundsLevel)
    h.S = levels & 255u;
    h.B = levels >> 8u;
    // validate() requires the sections to tile the buffer from the header on: the skip list at word 22,
    // the value bounds after its 4^S entries and the nodes after their 4^B words, so those offsets need
    // no read.
    h.skip = base + ML_DAG_HEADER_WORDS;
    h.bounds = h.skip + (ML_DAG_SKIP_WORDS << (2u * h.S));
    h.nodes = h.bounds + (1u << (2u * h.B));
    h.base = base;
    h.treelets = 0u, h.chunks = 0u, h.slopes = 0u, h.planes = 0u, h.factors = 0u;
    h.chunkWords = ML_DAG_CHUNK_WORDS;
    return h;
}

ML_DAG_FN DagmhHeader dagmhSections(ML_DAG_DATA_PARAM DagmhHeader h) {
    h.treelets = h.base + ML_DAG_WORD(h.base + ML_DAG_TREELET_OFFSET);
    h.chunks = h.base + ML_DAG_WORD(h.base + ML_DAG_CHUNK_OFFSET);
    h.slopes = h.base + ML_DAG_WORD(h.base + ML_DAG_SLOPE_OFFSET);
    h.planes = h.base + ML_DAG_WORD(h.base + ML_DAG_PLANE_OFFSET);
    h.chunkWords = ML_DAG_WORD(h.base + ML_DAG_PLANES) != 0u ? ML_DAG_PLANAR_CHUNK_WORDS : ML_DAG_CHUNK_WORDS;
    h.factors = h.base + ML_DAG_WORD(h.base + ML_DAG_FACTOR_OFFSET);
    return h;
}

// Every header word a lookup reads, for the buffer at word `base`.
ML_DAG_FN DagmhHeader dagmhHeader(ML_DAG_DATA_PARAM uint base) {
    return dagmhSections(
        ML_DAG_DATA_ARG dagmhHeaderTop(ML_DAG_DATA_ARG base, ML_DAG_WORD(base + ML_DAG_LEVELS)));
}

// The b-bit field at bit `pos` of the factor stream (0 when b is 0); it may straddle two words.
ML_DAG_FN uint dagmhField(ML_DAG_DATA_PARAM DagmhHeader h, uint pos, uint b) {
    if (b == 0u) return 0u;
    uint w = h.factors + (pos >> 5u);
    uint sh = pos & 31u;
    uint f = ML_DAG_WORD(w) >> sh;
    if (sh + b > 32u) f |= ML_DAG_WORD(w + 1u) << (32u - sh);
    return f & mlLowMask(b);
}

// A chunk's 6 or 8 words, read once (PCF: the taps of a kernel mostly fall in one or two chunks, so a kernel
// keeps the last chunk and reads only factor bits and a slope entry for the other taps).
struct DagmhChunk {
    uint bm, a0, a1, widths, off, slopes, planar, pbase;
};

ML_DAG_FN DagmhChunk dagmhChunk(ML_DAG_DATA_PARAM DagmhHeader h, uint chunk) {
    uint ch = h.chunks + h.chunkWords * chunk;
    DagmhChunk c;
    c.bm = ML_DAG_WORD(ch);
    c.a0 = ML_DAG_WORD(ch + 1u);
    c.a1 = ML_DAG_WORD(ch + 2u);
    c.widths = ML_DAG_WORD(ch + 3u);
    c.off = ML_DAG_WORD(ch + 4u);
    c.slopes = ML_DAG_WORD(ch + 5u);
    bool planar = h.chunkWords == ML_DAG_PLANAR_CHUNK_WORDS; // no plane slots in a 6-word chunk
    c.planar = planar ? ML_DAG_WORD(ch + 6u) : 0u;
    c.pbase = planar ? ML_DAG_WORD(ch + 7u) : 0u;
    return c;
}

// The plane a + ((D_x x + D_y y + 32) >> 6) at texel (x, y), in uint32 (dx, dy: D as int32 bits, 1/64
// units a texel: the rasteriser's depth planes of directional maps, shadows/static/raster_dual.h). D = 64 B
// + f with B = D >> 6 (arithmetic) and f < 64, so with x, y < 2^18 the plane is B_x x + B_y y + ((f_x x +
// f_y y + 32) >> 6), whose fraction sum stays below 2^25; the sum wraps exactly as the int64 rule does
// wherever the value lies in [0, 2^32).
ML_DAG_FN uint dagmhPlane(uint a, uint dx, uint dy, uint x, uint y) {
    uint fmask = (1u << ML_DAG_SLOPE_FRACTION) - 1u, fround = 1u << (ML_DAG_SLOPE_FRACTION - 1u);
    uint frac = ((dx & fmask) * x + (dy & fmask) * y + fround) >> ML_DAG_SLOPE_FRACTION;
    return a + uint(int(dx) >> ML_DAG_SLOPE_FRACTION) * x + uint(int(dy) >> ML_DAG_SLOPE_FRACTION) * y + frac;
}

// Whether slot j of a chunk is a plane (bit j of its planar bitmap): its value then differs from texel to
// texel of its node.
ML_DAG_FN bool dagmhSlotPlanar(DagmhChunk c, uint j) {
    return ((c.planar >> j) & 1u) != 0u;
}

// Slot j of a chunk (paper Alg. 2, integers; docs/dagmh-encoding.md), for texel (tx, ty) of the MH node
// that holds it, (px, py) the top-left texel of that node's cell. The chunk's factor stream holds the
// plane slots' indices (np of width bp), then class 1's factors, then class 0's.
// - A plane slot (bit j of `planar`): plane pbase + index of the plane table, evaluated at the texel
//   itself: a planar tree's node holds a block of texels on one plane (shadows/static/mh.h).
// - Otherwise class = bit j of the class bitmap; value = A + ((D_x px + D_y py + 32) >> 6) + (factor <<
//   sh) with the class's plane constant A, slopes from the table, width b (bits 0-5 of the class's half of
//   `widths`) and step sh (bits 6-10); b = 32: the raw value. The node's corner evaluates it, so every
//   texel of the node gets one value.
ML_DAG_FN uint dagmhChunkValue(ML_DAG_DATA_PARAM DagmhHeader h, DagmhChunk c, uint j, uint px, uint py,
                               uint tx, uint ty) {
    uint below = mlLowMask(j);
    uint bp = c.pbase >> ML_DAG_PLANAR_WIDTH_SHIFT;
    if (dagmhSlotPlanar(c, j)) {
        uint f = dagmhField(ML_DAG_DATA_ARG h, c.off + mlPopc(c.planar & below) * bp, bp);
        uint q = h.planes + ML_DAG_PLANE_WORDS * ((c.pbase & mlLowMask(ML_DAG_PLANAR_WIDTH_SHIFT)) + f);
        return dagmhPlane(ML_DAG_WORD(q), ML_DAG_WORD(q + 1u), ML_DAG_WORD(q + 2u), tx, ty);
    }
    uint cls = (c.bm >> j) & 1u;
    uint before1 = mlPopc(c.bm & below); // class-1 slots before j
    uint cw = cls != 0u ? c.widths >> 11u : c.widths;
    uint b = cw & 63u;
    uint pos =
        c.off + mlPopc(c.planar) * bp +
        (cls != 0u ? before1 * b
                   : mlPopc(c.bm) * ((c.widths >> 11u) & 63u) + (j - before1 - mlPopc(c.planar & below)) * b);
    uint f = dagmhField(ML_DAG_DATA_ARG h, pos, b);
    if (b == 32u) return f; // raw 32-bit value
    uint e = h.slopes + ML_DAG_SLOPE_WORDS * (cls != 0u ? c.slopes >> 16u : c.slopes & 0xFFFFu);
    uint a = cls != 0u ? c.a1 : c.a0;
    return dagmhPlane(a, ML_DAG_WORD(e), ML_DAG_WORD(e + 1u), px, py) + (f << ((cw >> 6u) & 31u));
}

// The value with index `index` at texel (tx, ty), (px, py) the top-left texel of the cell of the MH node
// that holds it (paper Alg. 2, integer version).
ML_DAG_FN uint dagmhValue(ML_DAG_DATA_PARAM DagmhHeader h, uint index, uint px, uint py, uint tx, uint ty) {
    return dagmhChunkValue(ML_DAG_DATA_ARG h, dagmhChunk(ML_DAG_DATA_ARG h, index >> 5u), index & 31u, px, py,
                           tx, ty);
}

// The lookup in steps, so that the taps of a PCF kernel can share the traversal above the level where
// they part (dagmhPcfPrefix, hierarchical PCF): the skip-list entry of (x, y) (dagmhStart); the descent
// towards (x, y) while depth < stop (dagmhDescend); the rest of the descent and the treelet
// (dagmhLocate); the value (dagmhLocatedValue). dlast is the depth of the node that holds value vlast.
struct DagmhState {
    uint kind, depth, dlast, ptr, vcount, vlast;
};

ML_DAG_FN DagmhState dagmhStart(ML_DAG_DATA_PARAM DagmhHeader h, uint x, uint y) {
    uint e = h.skip + ML_DAG_SKIP_WORDS * (((y >> (h.L - h.S)) << h.S) + (x >> (h.L - h.S)));
    uint w0 = ML_DAG_WORD(e);
    DagmhState st;
    st.kind = w0 & 255u;
    st.depth = (w0 >> 8u) & 255u;
    st.dlast = w0 >> 16u;
    st.ptr = ML_DAG_WORD(e + 1u);
    st.vcount = ML_DAG_WORD(e + 2u);
    st.vlast = ML_DAG_WORD(e + 3u);
    return st;
}

ML_DAG_FN DagmhState dagmhDescend(ML_DAG_DATA_PARAM DagmhHeader h, uint x, uint y, DagmhState st, uint stop) {
    while (st.kind == 1u) {
        if (st.depth >= stop) break;
        uint flags = ML_DAG_WORD(h.nodes + st.ptr);
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
        // n = present children.
        uint present = (flags | (flags >> 1u)) & 0x55u;
        uint rank = mlPopc(present & mlLowMask(2u * c));
        uint n = mlPopc(present);
        uint child = ML_DAG_WORD(h.nodes + st.ptr + 1u + rank);
        st.vcount += rank == 0u ? ((flags >> 8u) & 1u) : ML_DAG_WORD(h.nodes + st.ptr + n + rank);
        st.ptr = child;
        st.depth += 1u;
        st.kind = t;
    }
    return st;
}

// The treelet step (st.kind == 2): the deepest valued position of the treelet on the path to (x, y) at
// depth <= limit (h.L for the map, less for a level above it: dagmhLookupLevel), else st unchanged. It
// takes the treelet's 3 words, read once by the caller: then the level loop tests bits without further
// reads, and the taps of a PCF kernel share them.
ML_DAG_FN DagmhState dagmhTreelet(DagmhHeader h, uint x, uint y, DagmhState st, uint t0, uint t1, uint t2,
                                  uint limit) {
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

// The rest of the descent and the treelet: st.vlast is then the index of (x, y)'s value and st.dlast the
// depth of the node holding it (one node: texels with the same vlast have the same value).
ML_DAG_FN DagmhState dagmhLocate(ML_DAG_DATA_PARAM DagmhHeader h, uint x, uint y, DagmhState st) {
    st = dagmhDescend(ML_DAG_DATA_ARG h, x, y, st, h.L + 1u);
    if (st.kind == 2u) {
        uint tb = h.treelets + ML_DAG_TREELET_WORDS * st.ptr;
        st = dagmhTreelet(h, x, y, st, ML_DAG_WORD(tb), ML_DAG_WORD(tb + 1u), ML_DAG_WORD(tb + 2u), h.L);
    }
    return st;
}

// The value dagmhLocate found for (x, y).
ML_DAG_FN uint dagmhLocatedValue(ML_DAG_DATA_PARAM DagmhHeader h, uint x, uint y, DagmhState st) {
    uint s = h.L - st.dlast;
    return dagmhValue(ML_DAG_DATA_ARG h, st.vlast, (x >> s) << s, (y >> s) << s, x, y);
}

ML_DAG_FN uint dagmhFinish(ML_DAG_DATA_PARAM DagmhHeader h, uint x, uint y, DagmhState st) {
    return dagmhLocatedValue(ML_DAG_DATA_ARG h, x, y, dagmhLocate(ML_DAG_DATA_ARG h, x, y, st));
}

ML_DAG_FN uint dagmhLookupH(ML_DAG_DATA_PARAM DagmhHeader h, uint x, uint y) {
    return dagmhFinish(ML_DAG_DATA_ARG h, x, y, dagmhStart(ML_DAG_DATA_ARG h, x, y));
}

// The map: the value of texel (x, y), x, y < resolution. Only valid on a buffer validate() accepted.
ML_DAG_FN uint dagmhLookup(ML_DAG_DATA_PARAM uint base, uint x, uint y) {
    return dagmhLookupH(ML_DAG_DATA_ARG dagmhHeader(ML_DAG_DATA_ARG base), x, y);
}

// Level lookups (filtering by level), in two steps so that the taps of a kernel can share the descent
// (dagmhPcfLitLevel, shaders/static/static_pcf.h): where the lookup of full-resolution texel
// (X, Y) at depth `steps` starts, and the rest of it from a state above that depth. The descent starts at
// the skip entry when steps >= S (the entry holds the state above depth S), at the root otherwise, reads
// the flags of the node at depth `steps` itself and looks in a treelet only down to `steps`.
ML_DAG_FN DagmhState dagmhLevelStart(ML_DAG_DATA_PARAM DagmhHeader h, uint X, uint Y, uint steps) {
    if (steps >= h.S) return dagmhStart(ML_DAG_DATA_ARG h, X, Y);
    DagmhState st;
    st.kind = ML_DAG_WORD(h.base + ML_DAG_ROOT_KIND);
    st.ptr = ML_DAG_WORD(h.base + ML_DAG_ROOT_PTR);
    st.depth = 0u, st.dlast = 0u, st.vcount = 0u, st.vlast = 0u;
    return st;
}

ML_DAG_FN DagmhState dagmhLevelLocate(ML_DAG_DATA_PARAM DagmhHeader h, uint X, uint Y, DagmhState st,
                                      uint steps) {
    st = dagmhDescend(ML_DAG_DATA_ARG h, X, Y, st, steps);
    if (st.kind == 1u && st.depth == steps && (ML_DAG_WORD(h.nodes + st.ptr) & 256u) != 0u) {
        st.vlast = st.vcount;
        st.dlast = steps;
    }
    if (st.kind == 2u) {
        uint tb = h.treelets + ML_DAG_TREELET_WORDS * st.ptr;
        st = dagmhTreelet(h, X, Y, st, ML_DAG_WORD(tb), ML_DAG_WORD(tb + 1u), ML_DAG_WORD(tb + 2u), steps);
    }
    return st;
}

// The map at the level `steps` below the root (steps <= L), (x, y) a texel of that level: the value of
// the deepest valued node on the path down to that level, as mhLookupLevel (every level a complete map,
// exact at steps = L). The value bounds are not used: a cell's bounds hold the values its texels decode
// at the finest level, and an ancestor's value need not be one of them.
ML_DAG_FN uint dagmhLookupLevel(ML_DAG_DATA_PARAM uint base, uint x, uint y, uint steps) {
    DagmhHeader h = dagmhHeader(ML_DAG_DATA_ARG base);
    uint X = x << (h.L - steps), Y = y << (h.L - steps); // the level texel's top-left full texel
    return dagmhLocatedValue(
        ML_DAG_DATA_ARG h, X, Y,
        dagmhLevelLocate(ML_DAG_DATA_ARG h, X, Y, dagmhLevelStart(ML_DAG_DATA_ARG h, X, Y, steps), steps));
}

// The bounds test: 1 when every texel of [x0, x1] x [y0, y1] (in the map) is lit at receiver depth
// `depth` (depth <= its value), 2 when none is, 0 when the value bounds of the cells of level B it covers
// do not decide. A lit or shadowed answer skips the descent and the value decode: one word per cell (a
// 3x3 kernel covers 1-4 cells of 3x3 texels or more, up to 9 of smaller ones). A kernel within 2x2 cells
// (every 3x3 kernel on cells of 8x8 texels) reads four words without a loop, a cell twice when it covers
// one row or column of cells: the same minimum and maximum, without the loop's per-lane masks (lavapipe:
// 3x3 PCF ~7 % faster).
ML_DAG_FN uint dagmhBoundsClass(ML_DAG_DATA_PARAM DagmhHeader h, uint x0, uint y0, uint x1, uint y1,
                                uint depth) {
    uint sh = h.L - h.B;
    uint lo = 0xFFFFFFFFu, hi = 0u;
    uint X0 = x0 >> sh, X1 = x1 >> sh, Y0 = y0 >> sh, Y1 = y1 >> sh;
    if (X1 - X0 <= 1u && Y1 - Y0 <= 1u) {
        uint r0 = h.bounds + (Y0 << h.B), r1 = h.bounds + (Y1 << h.B);
        uint a = ML_DAG_WORD(r0 + X0), b = ML_DAG_WORD(r0 + X1);
        uint c = ML_DAG_WORD(r1 + X0), d = ML_DAG_WORD(r1 + X1);
        lo = min(min(a << 16u, b << 16u), min(c << 16u, d << 16u));
        hi = max(max(a | 0xFFFFu, b | 0xFFFFu), max(c | 0xFFFFu, d | 0xFFFFu));
        return depth <= lo ? 1u : (depth > hi ? 2u : 0u);
    }
    for (uint Y = y0 >> sh; Y <= (y1 >> sh); ++Y)
        for (uint X = x0 >> sh; X <= (x1 >> sh); ++X) {
            uint w = ML_DAG_WORD(h.bounds + (Y << h.B) + X);
            uint wl = w << 16u, wh = w | 0xFFFFu;
            lo = wl < lo ? wl : lo;
            hi = wh > hi ? wh : hi;
        }
    return depth <= lo ? 1u : (depth > hi ? 2u : 0u);
}

// The same test for one texel (the one-tap lookup): its cell's word alone, without the loops (lavapipe:
// the one tap ~4 % faster).
ML_DAG_FN uint dagmhBoundsClass1(ML_DAG_DATA_PARAM DagmhHeader h, uint x, uint y, uint depth) {
    uint sh = h.L - h.B;
    uint w = ML_DAG_WORD(h.bounds + ((y >> sh) << h.B) + (x >> sh));
    return depth <= (w << 16u) ? 1u : (depth > (w | 0xFFFFu) ? 2u : 0u);
}

// Hierarchical PCF: the state shared by every texel of the block [x0, x1] x [y0, y1] (in the map),
// descended once to the deepest level where all of them lie in one node. kind = ML_DAG_NO_PREFIX when
// the block straddles skip-list entries (each tap then starts from its own entry).
const uint ML_DAG_NO_PREFIX = 255u;
ML_DAG_FN DagmhState dagmhPcfPrefix(ML_DAG_DATA_PARAM DagmhHeader h, uint x0, uint y0, uint x1, uint y1) {
    uint diff = (x0 ^ x1) | (y0 ^ y1);
    uint bits = 0u;
    while ((diff >> bits) != 0u) ++bits;
    uint sharedLevels = h.L - bits; // levels above which every tap takes the same children
    DagmhState st = dagmhStart(ML_DAG_DATA_ARG h, x0, y0);
    if (sharedLevels < h.S) {
        st.kind = ML_DAG_NO_PREFIX;
        return st;
    }
    return dagmhDescend(ML_DAG_DATA_ARG h, x0, y0, st, sharedLevels);
}

#undef ML_DAG_FN
#undef ML_DAG_DATA_PARAM
#undef ML_DAG_DATA_ARG
#undef ML_DAG_WORD
