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
//   - Values (format version 6): chunks of 32, each slot in one of two classes (a class bitmap); a class
//     decodes value = A + ((D_x px + D_y py + 32) >> 6) + (k << sh) (uint32 arithmetic), (px, py) the
//     texel at the top-left corner of the value's node cell, k a factor of the class's bit width b
//     (b = 32: raw values); the slopes (D_x, D_y) / 64 come from a table shared by all chunks
//     (dagmh_values.h). The plane is the directional rasteriser's depth rule (raster_dual.h), so an
//     open surface's texels decode with no factor bits.
//   - Plane values (version 6): a planar tree (mh.h) holds whole blocks of texels on one depth plane in
//     one node. Such a slot is marked in the chunk's planar bitmap; its index k (the chunk's width bp)
//     picks plane base + k of the plane table, evaluated at the looked-up texel itself
//     (dagmhChunkValue). The other slots split into the two classes as above.
// Layout (words):
//   header[24]: magic 'DGM1' | version 6 | resolution | levels L | skip level S | B << 8 | root kind (1
//     inner, 2 treelet) | root pointer | values | chunks | skip offset | node offset | node words |
//     treelet offset | treelets | chunk offset | factor offset | factor words | total words | checksum |
//     0 | slope offset | slopes | plane offset | planes
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
//   chunks: 8 words each (6 without a plane table, the last two then 0): class bitmap (bit j: slot j in class
//   1; 0 at plane slots) | A_0 | A_1 | b_0 |
//     sh_0 << 6 | b_1 << 11 | sh_1 << 17 | bit offset of the chunk's factors (the plane indices, class
//     1's, then class 0's) | slope entry of class 0 | slope entry of class 1 << 16 | planar bitmap (bit
//     j: slot j is a plane) | plane base | bp << 27.
//   slopes: 2 words each (D_x, D_y as int32 bits, 1/64 units a texel); entry 0 is (0, 0).
//   planes: 3 words each: A (its low 32 bits), D_x, D_y: depth = A + ((D_x x + D_y y + 32) >> 6) at
//     texel (x, y), in the order the values first use them.
//   factors: bit stream, little-endian within words.
// Empty texels decode to exactly kDepthEmpty.
#pragma once
#include "io/result.h"
#include "shadows/static/dual_depth.h"
#include "shadows/static/format_common.h"
#include "shadows/static/mh.h"

#include <algorithm>
#include <bit>
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
    kPlaneOffset,
    kPlanes,
};
constexpr uint32_t kHeaderWords = 24;
constexpr uint32_t kChunkValues = 32, kChunkWords = 6, kTreeletWords = 3, kSkipWords = 4, kSlopeWords = 2;
// With a plane table every chunk has 8 words (the planar bitmap and the plane base); without, 6.
constexpr uint32_t kPlanarChunkWords = 8;
inline uint32_t chunkWords(uint32_t planes) {
    return planes ? kPlanarChunkWords : kChunkWords;
}
constexpr uint32_t kPlaneWords = 3;
// A chunk's word 7: the first plane index (27 bits) | the plane indices' width << 27 (at most 27 bits).
constexpr uint32_t kPlanarWidthShift = 27;
constexpr uint32_t kMaxPlanes = 1u << kPlanarWidthShift;
// A chunk's factor offset is a bit position in a uint32, and a slope entry 16 bits.
constexpr uint64_t kMaxFactorBits = (uint64_t(1) << 32) - 64;
constexpr uint32_t kMaxSlopes = 1u << 16;

// Format version 6 (planar classes and the plane table, for planar trees). A reader takes only its own
// version and asks for a rebake otherwise.
constexpr uint32_t kVersionNumber = 6;
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
    uint64_t planarValues = 0, planes = 0;    // values that are planes (planar trees), plane table entries
    uint64_t treeInner = 0, treeTreelets = 0; // before deduplication
};

Result<std::vector<uint32_t>> encodeDAGMH(const MhTree& tree, DagMhStats* stats = nullptr);
Result<std::vector<uint32_t>> encodeDAGMH(const DualDepthMap& map);
Result<void> validateDAGMH(const uint32_t* data, size_t size);
stat::ByteBreakdown breakdownDAGMH(const uint32_t* data, size_t size);
// Encoder self-check: decodes every value of `tree` from `data` (an encoding of it) with the lookup's
// arithmetic and counts the values outside their node's interval.
uint64_t dagmhCheckValues(const MhTree& tree, const uint32_t* data);

// The lookups are one source text with the GLSL decoder, shaders/static/dagmh_decode.h, compiled here with
// the buffer as an argument: dagmhLookup(data, base, x, y), the map; dagmhLookupLevel(data, base, x, y,
// steps), the level `steps` below the root (filtering by level); with the header read once
// (dagmhHeader(data, base)), dagmhValue (a value by index), dagmhBoundsClass (the value bounds of a block
// of texels), and the steps the taps of a PCF kernel share (dagmhPcfPrefix, dagmhStart, dagmhLocate,
// dagmhLocatedValue, dagmhFinish). Only valid on a buffer validateDAGMH accepted; x, y below the
// resolution of the level looked up.
namespace dagtwin {
using uint = uint32_t;
inline uint mlPopc(uint x) {
    return stat::popc(x);
}
inline uint mlLowMask(uint bits) {
    return stat::lowMask(bits);
}
inline int findMSB(uint x) {
    return x == 0u ? -1 : 31 - std::countl_zero(x);
}
inline uint min(uint a, uint b) {
    return a < b ? a : b;
}
inline uint max(uint a, uint b) {
    return a > b ? a : b;
}
#define ML_DAG_FN inline
#define ML_DAG_DATA_PARAM const uint32_t *data,
#define ML_DAG_DATA_ARG data,
#define ML_DAG_WORD(i) data[i]
#include "shaders/static/dagmh_decode.h"
static_assert(ML_DAG_LEVELS == dagfmt::kLevels && ML_DAG_SKIP_LEVEL == dagfmt::kSkipLevel &&
              ML_DAG_ROOT_KIND == dagfmt::kRootKind && ML_DAG_ROOT_PTR == dagfmt::kRootPtr &&
              ML_DAG_SKIP_OFFSET == dagfmt::kSkipOffset && ML_DAG_NODE_OFFSET == dagfmt::kNodeOffset &&
              ML_DAG_TREELET_OFFSET == dagfmt::kTreeletOffset &&
              ML_DAG_CHUNK_OFFSET == dagfmt::kChunkOffset && ML_DAG_FACTOR_OFFSET == dagfmt::kFactorOffset &&
              ML_DAG_SLOPE_OFFSET == dagfmt::kSlopeOffset && ML_DAG_CHUNK_WORDS == dagfmt::kChunkWords &&
              ML_DAG_PLANAR_CHUNK_WORDS == dagfmt::kPlanarChunkWords && ML_DAG_PLANES == dagfmt::kPlanes &&
              ML_DAG_SLOPE_WORDS == dagfmt::kSlopeWords && ML_DAG_TREELET_WORDS == dagfmt::kTreeletWords &&
              ML_DAG_SKIP_WORDS == dagfmt::kSkipWords && ML_DAG_HEADER_WORDS == dagfmt::kHeaderWords &&
              ML_DAG_SLOPE_FRACTION == kOrthoSlopeFractionBits &&
              ML_DAG_PLANE_OFFSET == dagfmt::kPlaneOffset && ML_DAG_PLANE_WORDS == dagfmt::kPlaneWords &&
              ML_DAG_PLANAR_WIDTH_SHIFT == dagfmt::kPlanarWidthShift);
} // namespace dagtwin
using dagtwin::dagmhBoundsClass;
using dagtwin::dagmhFinish;
using dagtwin::DagmhHeader;
using dagtwin::dagmhHeader;
using dagtwin::dagmhLocate;
using dagtwin::dagmhLocatedValue;
using dagtwin::dagmhLookup;
using dagtwin::dagmhLookupLevel;
using dagtwin::dagmhPcfPrefix;
using dagtwin::dagmhSlotPlanar;
using dagtwin::dagmhStart;
using dagtwin::DagmhState;
using dagtwin::dagmhValue;
constexpr uint32_t kDagNoPrefix = dagtwin::ML_DAG_NO_PREFIX;

inline uint32_t dagmhLookup(const uint32_t* data, uint32_t x, uint32_t y) {
    return dagmhLookup(data, 0u, x, y);
}

} // namespace ml
