// DAG-MH: the MH quadtree stored as a DAG with separately compressed depth values (Scandolo, Eisemann
// 2021, ../shared/papers/dagmh-scandolo-eisemann-2021.txt). The value encoding (paper sections 3.3/3.4
// are missing from the text) is designed in docs/dagmh-encoding.md.
//
// Structure (sec. 3.1, 3.2, 3.5, 3.7):
//   - The MH tree's values are numbered in depth-first (preorder) order. The structure keeps only the
//     topology, deduplicated bottom-up as a DAG; each inner node carries value counts so a traversal can
//     track v_count (index of the first value of the current subtree) and v_last (index of the deepest
//     value seen so far).
//   - Subtrees of height <= 3 (4 levels: 1 + 4 + 16 + 64 = 85 nodes) are treelets: an 85-bit bitmap of
//     valued positions in depth-first order, bit index n + 21 l0 + 5 l1 + l2 (n = level in the treelet,
//     l_i = child index on the path). A value's index is v_count + set bits before its bit. Lookup
//     checks the deepest level first (paper Alg. 1).
//   - A dense skip list at level S stores the traversal state for every node position at that level
//     (paper: level 6 for large maps). S is the deepest level <= min(L, 8) whose list stays within an
//     eighth of the other sections (the night city's 1024^2 bake: skip lists 0.25 -> 2.48 MB of
//     44.9 MB, dense lights deeper, near-empty ones unchanged), so a lookup starts that deep; older
//     bakes used clamp(L - 7, 0, 6) and still read (S is in the header).
//   - Value bounds (format version 3): per cell of level B (chooseBoundsLevel), the smallest and largest
//     value any of its texels decodes to, 16 bits each (rounded outwards). A lookup whose receiver depth is
//     at or below the cell's smallest value is lit, one above its largest is shadowed, without the descent or
//     the value decode (dagmhBoundsClass; a PCF kernel tests the cells it covers at once). Exact: the bounds
//     hold every texel's decoded value (validate() recomputes them, the tests check every texel); 1 word per
//     cell.
//   - Values (format version 4): chunks of 32, each slot in one of two classes (a class bitmap); a class
//     decodes value = A + B_x px + B_y py + (k << sh) (uint32 arithmetic), (px, py) the texel at the
//     top-left corner of the value's node cell, k a factor of the class's bit width b (b = 32: raw
//     values); the slopes (B_x, B_y) come from a table shared by all chunks (dagmh_values.h).
// Layout (words):
//   header[22]: magic 'DGM1' | version 4 | resolution | levels L | skip level S | B << 8 | root kind (1
//     inner, 2 treelet) | root pointer | values | chunks | skip offset | node offset | node words |
//     treelet offset | treelets | chunk offset | factor offset | factor words | total words | checksum |
//     0 | slope offset | slopes
//   skip list: 4^S entries of 4 words: kind (0 resolved, 1 inner, 2 treelet) | depth << 8 | d_last << 16
//     (depth of the node holding v_last), pointer, v_count, v_last; entry index = Y * 2^S + X.
//   bounds: 4^B words (B in bits 8-15 of the skip level word), index Y * 2^B + X: lo >> 16 | (hi >> 16) <<
//     16 (lo, hi: the cell's smallest and largest decoded value; the node offset is skip offset + 4 * 4^S +
//     4^B).
//   nodes: inner node = flags (2 bits per child c: 0 absent, 1 inner, 2 treelet; bit 8: the node has a
//     value) | n child pointers (inner: word index into nodes, always smaller than the node's own;
//     treelet: treelet index) | n - 1 prefix counts (values before child rank r >= 1 in the subtree,
//     the node's own value included). Size 2n words.
//   treelets: 3 words each (85 bits used).
//   chunks: 6 words each: class bitmap (bit j: slot j in class 1) | A_0 | A_1 | b_0 | sh_0 << 6 | b_1 << 11
//     | sh_1 << 17 | bit offset of the chunk's factors (class 1's, then class 0's) | slope entry of class
//     0 | slope entry of class 1 << 16.
//   slopes: 2 words each (B_x, B_y as int32 bits); entry 0 is (0, 0).
//   factors: bit stream, little-endian within words.
// Empty texels decode to exactly kDepthEmpty.
#pragma once
#include "io/result.h"
#include "shadows/static/dual_depth.h"
#include "shadows/static/format_common.h"
#include "shadows/static/mh.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace ml {

namespace dagfmt {
constexpr uint32_t kMagic = stat::fourcc('D', 'G', 'M', '1');
enum : uint32_t {
    kMagicWord,
    kVersion,
    kResolution,
    kLevels,
    kSkipLevel,
    kRootKind,
    kRootPtr,
    kValues,
    kChunks,
    kSkipOffset,
    kNodeOffset,
    kNodeWords,
    kTreeletOffset,
    kTreelets,
    kChunkOffset,
    kFactorOffset,
    kFactorWords,
    kTotalWords,
    kChecksum,
    kReserved,
    kSlopeOffset,
    kSlopes,
};
constexpr uint32_t kHeaderWords = 22;
constexpr uint32_t kChunkValues = 32, kChunkWords = 6, kTreeletWords = 3, kSkipWords = 4, kSlopeWords = 2;
// A chunk's factor offset is a bit position in a uint32, and a slope entry 16 bits.
constexpr uint64_t kMaxFactorBits = (uint64_t(1) << 32) - 64;
constexpr uint32_t kMaxSlopes = 1u << 16;

// Format version 4 (two plane classes a value chunk, the slope table). A reader takes only its own
// version and asks for a rebake otherwise.
constexpr uint32_t kVersionNumber = 4;
// Traversal state at depth S for the skip-list cell (X, Y): the 4 words of a skip entry.
void descendToSkipLevel(const uint32_t* data, uint32_t base, uint32_t X, uint32_t Y, uint32_t out[4]);
// The bounds word of bounds cell (X, Y) (level B below), computed from its skip entry down (every node and
// treelet position under the cell, each region's value decoded once): the smallest and largest value a texel
// of the cell decodes to, packed as in the bounds section. Needs the skip entries and value sections
// in place (the encoder fills the bounds last; validate() compares).
uint32_t cellBounds(const uint32_t* data, uint32_t X, uint32_t Y);
// Word kSkipLevel holds the skip level S (bits 0-7) and the bounds' level B (bits 8-15, S <= B <= min(L,
// 9)); the rest is 0.
inline uint32_t skipLevel(const uint32_t* data, uint32_t base = 0) {
    return data[base + kSkipLevel] & 255u;
}
inline uint32_t boundsLevel(const uint32_t* data, uint32_t base = 0) {
    return (data[base + kSkipLevel] >> 8u) & 255u;
}
// The encoder's choice of B: the deepest level <= min(L, S + 4, 9) whose bounds (4 B a cell) stay within
// a sixteenth of the other sections or 64 KiB, whichever is more, and never below S. The floor serves
// the many small maps (a lamp over flat ground: 8-32 KiB), whose bounds it makes 8x8-texel cells at
// 1024^2: a tap the bounds leave undecided lies in a cell that an occluder's edge crosses, so halving
// the cell's side about halves those taps (7.1 -> 4.0 % of the one taps at 1024^2, bench static; the
// night city's bake: 49.3 -> 59.7 MB against a 16 KiB floor and S + 3; 3x3 PCF ~12 % cheaper, the one
// tap within the noise; docs/culling.md). The sixteenth keeps dense maps near B = S.
uint32_t chooseBoundsLevel(uint32_t L, uint32_t S, uint64_t restWords);
inline uint32_t packBounds(uint32_t lo, uint32_t hi) {
    return (lo >> 16u) | (hi & 0xFFFF0000u);
}
} // namespace dagfmt

struct DagMhStats {
    uint64_t innerNodes = 0, treelets = 0, values = 0, chunks = 0, rawChunks = 0, factors = 0, factorBits = 0;
    uint64_t slopes = 0;                      // slope table entries; rawChunks counts raw classes
    uint64_t treeInner = 0, treeTreelets = 0; // before deduplication
};

Result<std::vector<uint32_t>> encodeDAGMH(const MhTree& tree, DagMhStats* stats = nullptr);
Result<std::vector<uint32_t>> encodeDAGMH(const DualDepthMap& map);
Result<void> validateDAGMH(const uint32_t* data, size_t size);
stat::ByteBreakdown breakdownDAGMH(const uint32_t* data, size_t size);
// Encoder self-check: decodes every value of `tree` from `data` (an encoding of it) with the lookup's
// arithmetic and counts the values outside their node's interval.
uint64_t dagmhCheckValues(const MhTree& tree, const uint32_t* data);

// The b-bit field at bit `pos` of the factor stream starting at word `factors` (0 when b == 0); it may
// straddle two words.
inline uint32_t dagmhField(const uint32_t* data, uint32_t factors, uint32_t pos, uint32_t b) {
    if (b == 0u) return 0u;
    const uint32_t w = factors + (pos >> 5u), sh = pos & 31u;
    uint32_t f = data[w] >> sh;
    if (sh + b > 32u) f |= data[w + 1u] << (32u - sh);
    return f & stat::lowMask(b);
}

// Slot j of the chunk whose words are c[0..5] (paper Alg. 2, integers, two plane classes; see
// docs/dagmh-encoding.md). Class c = bit j of the bitmap; its factors follow class 1's when c = 0.
inline uint32_t dagmhChunkSlot(const uint32_t* data, uint32_t base, const uint32_t* c, uint32_t j,
                               uint32_t px, uint32_t py) {
    const uint32_t cls = (c[0] >> j) & 1u;
    const uint32_t before1 = stat::popc(c[0] & stat::lowMask(j)); // class-1 slots before j
    const uint32_t cw = cls != 0u ? c[3] >> 11u : c[3];           // this class's b (bits 0-5), sh (6-10)
    const uint32_t b = cw & 63u;
    const uint32_t pos =
        c[4] + (cls != 0u ? before1 * b : stat::popc(c[0]) * ((c[3] >> 11u) & 63u) + (j - before1) * b);
    const uint32_t f = dagmhField(data, base + data[base + dagfmt::kFactorOffset], pos, b);
    if (b == 32u) return f; // raw 32-bit value
    const uint32_t e = base + data[base + dagfmt::kSlopeOffset] +
                       dagfmt::kSlopeWords * (cls != 0u ? c[5] >> 16u : c[5] & 0xFFFFu);
    return c[1u + cls] + data[e] * px + data[e + 1u] * py + (f << ((cw >> 6u) & 31u));
}

// The value with index `index`, (px, py) the full-resolution texel at the top-left corner of the cell of
// the MH node that holds it. GLSL twin in shaders/static/dagmh_lookup.glsl.
inline uint32_t dagmhValue(const uint32_t* data, uint32_t base, uint32_t index, uint32_t px, uint32_t py) {
    const uint32_t ch = base + data[base + dagfmt::kChunkOffset] + dagfmt::kChunkWords * (index >> 5u);
    return dagmhChunkSlot(data, base, data + ch, index & 31u, px, py);
}

// Only valid on a buffer validateDAGMH accepted; x, y < resolution.
// The lookup in three steps, so that the taps of a PCF kernel can share the traversal above the level
// where they part (dagmhPcfPrefix, hierarchical PCF): the skip-list entry of (x, y); the descent towards
// (x, y) while depth < stop; the rest of the descent, the treelet and the value.
struct DagmhState {
    uint32_t kind, depth, dlast, ptr, vcount, vlast;
};

inline DagmhState dagmhStart(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y) {
    uint32_t L = data[base + dagfmt::kLevels];
    uint32_t S = dagfmt::skipLevel(data, base);
    uint32_t e = base + data[base + dagfmt::kSkipOffset] +
                 dagfmt::kSkipWords * (((y >> (L - S)) << S) + (x >> (L - S)));
    DagmhState st;
    st.kind = data[e] & 255u;
    st.depth = (data[e] >> 8u) & 255u;
    st.dlast = data[e] >> 16u; // depth of the node that holds value vlast
    st.ptr = data[e + 1u];
    st.vcount = data[e + 2u];
    st.vlast = data[e + 3u];
    return st;
}

inline DagmhState dagmhDescend(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y, DagmhState st,
                               uint32_t stop) {
    uint32_t L = data[base + dagfmt::kLevels];
    uint32_t nodes = base + data[base + dagfmt::kNodeOffset];
    while (st.kind == 1u) {
        if (st.depth >= stop) break;
        uint32_t flags = data[nodes + st.ptr];
        if ((flags & 256u) != 0u) {
            st.vlast = st.vcount;
            st.dlast = st.depth;
        }
        if (st.depth >= L) break;
        uint32_t s = L - st.depth - 1u;
        uint32_t c = (((y >> s) & 1u) << 1u) | ((x >> s) & 1u);
        uint32_t t = (flags >> (2u * c)) & 3u;
        if (t == 0u) break;
        uint32_t rank = 0u, n = 0u;
        for (uint32_t i = 0u; i < 4u; ++i) {
            uint32_t present = ((flags >> (2u * i)) & 3u) != 0u ? 1u : 0u;
            if (i < c) rank += present;
            n += present;
        }
        uint32_t child = data[nodes + st.ptr + 1u + rank];
        st.vcount += rank == 0u ? ((flags >> 8u) & 1u) : data[nodes + st.ptr + n + rank];
        st.ptr = child;
        st.depth += 1u;
        st.kind = t;
    }
    return st;
}

// The treelet step (st.kind == 2): the deepest valued position of the treelet on the path to (x, y) at
// depth <= limit (L for the map itself, less for a level above it: dagmhLookupLevel), else st unchanged.
inline DagmhState dagmhTreeletStep(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y, DagmhState st,
                                   uint32_t limit) {
    uint32_t L = data[base + dagfmt::kLevels];
    uint32_t tb = base + data[base + dagfmt::kTreeletOffset] + dagfmt::kTreeletWords * st.ptr;
    for (uint32_t i = 0u; i < 4u; ++i) {
        uint32_t lvl = 3u - i;
        if (st.depth + lvl > limit) continue;
        uint32_t idx = lvl;
        for (uint32_t j = 1u; j <= lvl; ++j) {
            uint32_t s = L - st.depth - j;
            uint32_t c = (((y >> s) & 1u) << 1u) | ((x >> s) & 1u);
            idx += c * (j == 1u ? 21u : (j == 2u ? 5u : 1u));
        }
        uint32_t wi = idx >> 5u;
        if (((data[tb + wi] >> (idx & 31u)) & 1u) != 0u) {
            uint32_t before = stat::popc(data[tb + wi] & stat::lowMask(idx & 31u));
            if (wi > 0u) before += stat::popc(data[tb]);
            if (wi > 1u) before += stat::popc(data[tb + 1u]);
            st.vlast = st.vcount + before;
            st.dlast = st.depth + lvl;
            break;
        }
    }
    return st;
}
// The rest of the descent and the treelet: st.vlast is then the index of (x, y)'s value and st.dlast the
// depth of the node holding it (one node: texels with the same vlast have the same value).
inline DagmhState dagmhLocate(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y, DagmhState st) {
    uint32_t L = data[base + dagfmt::kLevels];
    st = dagmhDescend(data, base, x, y, st, L + 1u);
    if (st.kind == 2u) st = dagmhTreeletStep(data, base, x, y, st, L);
    return st;
}
// The value dagmhLocate found for (x, y).
inline uint32_t dagmhLocatedValue(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y,
                                  const DagmhState& st) {
    uint32_t s = data[base + dagfmt::kLevels] - st.dlast;
    return dagmhValue(data, base, st.vlast, (x >> s) << s, (y >> s) << s);
}

inline uint32_t dagmhFinish(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y, DagmhState st) {
    return dagmhLocatedValue(data, base, x, y, dagmhLocate(data, base, x, y, st));
}

inline uint32_t dagmhLookup(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y) {
    return dagmhFinish(data, base, x, y, dagmhStart(data, base, x, y));
}

// The map at the level `steps` below the root (steps <= L; filtering by level), (x, y) a texel of that
// level: the value of the deepest valued node on the path down to that level, as mhLookupLevel (every level
// a complete map, exact at steps = L). The descent starts at the skip entry when steps >= S (the entry
// holds the state above depth S), at the root otherwise, reads the flags of the node at depth `steps`
// itself and looks in a treelet only down to `steps`. The value bounds are not used: a cell's bounds hold
// the values its texels decode at the finest level, and an ancestor's value need not be one of them.
// GLSL twin dagmhLookupLevel (shaders/static/dagmh_lookup.glsl).
inline uint32_t dagmhLookupLevel(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y,
                                 uint32_t steps) {
    const uint32_t L = data[base + dagfmt::kLevels];
    const uint32_t X = x << (L - steps), Y = y << (L - steps); // the level texel's top-left full texel
    DagmhState st{data[base + dagfmt::kRootKind], 0u, 0u, data[base + dagfmt::kRootPtr], 0u, 0u};
    if (steps >= dagfmt::skipLevel(data, base)) st = dagmhStart(data, base, X, Y);
    st = dagmhDescend(data, base, X, Y, st, steps);
    if (st.kind == 1u && st.depth == steps &&
        (data[base + data[base + dagfmt::kNodeOffset] + st.ptr] & 256u) != 0u) {
        st.vlast = st.vcount;
        st.dlast = steps;
    }
    if (st.kind == 2u) st = dagmhTreeletStep(data, base, X, Y, st, steps);
    return dagmhLocatedValue(data, base, X, Y, st);
}
// The bounds test of the texels [x0, x1] x [y0, y1] (in the map) at receiver depth `depth`: 1 when
// every one of them is lit (depth <= value), 2 when none is, 0 when the cells' bounds do not decide.
// GLSL twin dagmhBoundsClass (shaders/static/dagmh_lookup.glsl).
inline uint32_t dagmhBoundsClass(const uint32_t* data, uint32_t base, uint32_t x0, uint32_t y0, uint32_t x1,
                                 uint32_t y1, uint32_t depth) {
    const uint32_t L = data[base + dagfmt::kLevels], S = dagfmt::skipLevel(data, base);
    const uint32_t B = dagfmt::boundsLevel(data, base);
    const uint32_t bounds = base + data[base + dagfmt::kSkipOffset] + (dagfmt::kSkipWords << (2u * S));
    const uint32_t sh = L - B;
    uint32_t lo = 0xFFFFFFFFu, hi = 0u;
    for (uint32_t Y = y0 >> sh; Y <= y1 >> sh; ++Y)
        for (uint32_t X = x0 >> sh; X <= x1 >> sh; ++X) {
            uint32_t w = data[bounds + (Y << B) + X];
            lo = std::min(lo, w << 16u);
            hi = std::max(hi, w | 0xFFFFu);
        }
    return depth <= lo ? 1u : (depth > hi ? 2u : 0u);
}

// Hierarchical PCF: the state shared by every texel of the block [x0, x1] x [y0, y1] (in the map),
// descended once to the deepest level where all of them lie in one node. kind = kNoPrefix when the
// block straddles skip-list entries (then each tap starts from its own entry).
constexpr uint32_t kDagNoPrefix = 255u;
inline DagmhState dagmhPcfPrefix(const uint32_t* data, uint32_t base, uint32_t x0, uint32_t y0, uint32_t x1,
                                 uint32_t y1) {
    uint32_t L = data[base + dagfmt::kLevels];
    uint32_t S = dagfmt::skipLevel(data, base);
    uint32_t diff = (x0 ^ x1) | (y0 ^ y1);
    uint32_t bits = 0u;
    while ((diff >> bits) != 0u) ++bits;
    uint32_t sharedLevels = L - bits; // levels above which every tap takes the same children
    DagmhState st = dagmhStart(data, base, x0, y0);
    if (sharedLevels < S) {
        st.kind = kDagNoPrefix;
        return st;
    }
    return dagmhDescend(data, base, x0, y0, st, sharedLevels);
}

inline uint32_t dagmhLookup(const uint32_t* data, uint32_t x, uint32_t y) {
    return dagmhLookup(data, 0u, x, y);
}

} // namespace ml
