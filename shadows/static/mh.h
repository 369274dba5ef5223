// MH: multiresolution hierarchy of depth intervals (Scandolo, Bauszat, Eisemann 2016, "Compressed
// multiresolution hierarchies", summarised in ../shared/papers/mmh-*.txt section 2.2 and
// dagmh-*.txt section 3).
//
// Construction (buildMhTree): level L = the texels, each an interval [enter, exit] (empty texels
// [kDepthEmpty, kDepthEmpty]; texels past a non-power-of-two resolution are "don't care" [0, 2^32-1]).
// Bottom-up, every 2x2 group picks the point covered by the most child intervals (ties: the widest
// intersection, then the lowest child); the parent gets the intersection of those children, which are
// removed (represented implicitly by the parent). The others stay. Repeat up to the 1x1 root.
// Invariant: a node's interval lies inside the interval of every texel it represents implicitly, so
// the deepest value on a texel's path is lossless. The sparse result is a quadtree with leaf, full
// inner (value + children) and empty inner (children only) nodes.
//
// Serialized layout (words; the same node layout is used by MMH, with relative values):
//   header[12]: magic 'MH01' | version 1 | resolution | levels L | root type (1 leaf, 2 full) |
//               node offset (12) | node words | total words | valued nodes | inner records |
//               checksum (word-wise FNV-1a over all other words) | 0
//   nodes: root record, then child groups. A record is: leaf [value]; full inner [value][header];
//          empty inner [header]. header = child types (2 bits per child c = 2*ybit + xbit, bits 2c..2c+1:
//          0 absent, 1 leaf, 2 full, 3 empty) | offset << 8, offset = words from the header word to its
//          child group (> 0, < 2^24). A group holds the present children's records in child order, so a
//          child's position is the group start plus the record sizes of the present children before it.
//   Groups are laid out in depth-first (preorder) order of their parent, so offsets are positive.
// Version 2 (far groups): a node array past 2^24 words (MH from about 65,536^2 on a city) has child
//   groups more than 2^24 words after their header: a sibling's group follows the whole subtree of the
//   siblings before it. The header grows to 14 words: word 12 = far shift S (1..9), word 13 = padding
//   words; the node offset is 14. Offsets then hold 23 bits; bit 23 of the offset field marks a far group,
//   whose position is (offset & (2^23 - 1)) << S words from the record's first word, the group aligned to
//   2^S words by zero padding words before it. S is the smallest shift whose positions reach the whole
//   record (2^23 << S words: 2^32 at S = 9). Only groups that some header reaches from afar are
//   aligned, so padding stays small (the moon's MH at 65,536^2: 55.3 M node words, S = 3, 28 padding
//   words). A layout that fits 24-bit offsets is written as version 1, byte for byte as before; a
//   reader of version 1 refuses version 2 by its number.
// Lookup: the value of the deepest valued node on the texel's path (absent child -> current value).
// Empty texels decode to exactly kDepthEmpty (their interval is the single point).
#pragma once
#include "io/result.h"
#include "shadows/static/dual_depth.h"
#include "shadows/static/format_common.h"

#include <cstdint>
#include <vector>

namespace ml {

// The largest map the MH family (MH, MMH, DAG-MH) builds and reads: 2^18 texels a side, the seeds'
// 256K^2 tables. Coordinates, levels, node and word counts fit 32 bits there; the texel count (2^36)
// is counted in 64 bits. Only tiled builds (mh_tiled.h) reach it: a whole map past 16384^2 is not held.
constexpr uint32_t kMhMaxLevels = 18;
constexpr uint32_t kMhMaxResolution = 1u << kMhMaxLevels;

// Construction-side sparse quadtree shared by the MH, MMH and DAG-MH encoders.
struct MhTree {
    struct Node {
        uint32_t lo = 0, hi = 0; // interval (meaningful when valued)
        int32_t child[4] = {-1, -1, -1, -1};
        uint8_t valued = 0;
        uint8_t depth = 0; // 0 = root, levels = texels
        uint32_t plane =
            0; // planar trees: a plane id (1-based in MhTree::planes) every texel it holds lies on
        // Planar trees: a valued node whose interval is empty holds its texels by its plane alone.
        bool planarOnly() const { return lo > hi; }
        bool inner() const { return child[0] >= 0 || child[1] >= 0 || child[2] >= 0 || child[3] >= 0; }
        // Type as seen from the parent: 1 leaf, 2 full inner, 3 empty inner.
        uint32_t type() const { return inner() ? (valued ? 2u : 3u) : 1u; }
    };
    uint32_t resolution = 0, levels = 0;
    std::vector<Node> nodes;        // preorder; nodes[0] is the root (always valued)
    std::vector<DepthPlane> planes; // planar trees only (empty otherwise)
    size_t valuedCount() const;
    bool planar() const { return !planes.empty(); }
};

// Planar trees (DAG-MH only, whose values can be planes evaluated per texel, dagmh.h): with the map's
// enter planes (DualDepthMap::enterPlane), a node also keeps the plane id that every texel it holds lies
// on, and a parent may take a plane instead of a constant: the plane shared by the most children when
// it covers more of them than any constant (mhbuild::reduceLevel). A tilted open or closed surface then
// needs one node for a whole block instead of a value a texel: the night city's moon at 16384^2 holds
// 0.18x the values of the plain tree. Its chosen children's intervals may not meet: the parent's interval
// is then empty (lo > hi, Node::planarOnly) and only the plane holds them. MH and MMH refuse such trees.
Result<MhTree> buildMhTree(const DualDepthMap& map, bool planar = false);

// The construction's steps, shared with the tiled build (mh_tiled.h), so both run the same code.
namespace mhbuild {
// One level of the bottom-up pass: n x n children (lo, hi, flags; bit 0 keeps its value, bit 1 has a
// present descendant) -> n/2 x n/2 parents. Clears bit 0 of the children the parent represents. With
// plane ids (cpl, ppl: planar trees) empty intervals are lo > hi and planes compete with constants.
void reduceLevel(uint32_t n, const uint32_t* clo, const uint32_t* chi, uint8_t* cfl, uint32_t* plo,
                 uint32_t* phi, uint8_t* pfl, const uint32_t* cpl = nullptr, uint32_t* ppl = nullptr);
// The subtree of a size x size block of texel intervals (size a power of two), as a tile of a larger
// map: its root's interval and flags (the root's bit 0 is decided by the levels above the block), and
// its nodes in preorder, child indices local (nodes[0] is the root), depths from depthOffset.
struct Subtree {
    uint32_t lo = 0, hi = 0, plane = 0;
    uint8_t flags = 0;
    std::vector<MhTree::Node> nodes;
};
// `plane` (optional): the texels' enter plane ids, for a planar tree.
Result<Subtree> buildSubtree(uint32_t size, const uint32_t* lo, const uint32_t* hi, uint32_t depthOffset,
                             const uint32_t* plane = nullptr);
} // namespace mhbuild

namespace mhfmt {
constexpr uint32_t kMagicMH = stat::fourcc('M', 'H', '0', '1');
constexpr uint32_t kMagicMMH = stat::fourcc('M', 'M', 'H', '1');
constexpr uint32_t kHeaderWords = 12;
enum : uint32_t {
    kMagic,
    kVersion,
    kResolution,
    kLevels,
    kRootType,
    kNodeOffset,
    kNodeWords,
    kTotalWords,
    kValued,
    kInnerRecords,
    kChecksum,
    kReserved,
    kFarShift,    // version 2 only
    kPaddingWords // version 2 only
};
constexpr uint32_t kHeaderWordsFar = 14;
constexpr uint32_t kMaxOffset = (1u << 24) - 1u;     // version 1: 24-bit offsets
constexpr uint32_t kMaxNearOffset = (1u << 23) - 1u; // version 2: bit 23 marks a far group
constexpr uint32_t kFarBit = 1u << 23;
constexpr uint32_t kMaxFarShift = 9; // (2^23 - 1) << 9 still fits a 32-bit word position

// How the serializer places child groups. The defaults give the smallest file; tests lower maxNear to
// send small trees through the far-group path and raise minFarShift to exercise wider alignments.
struct Layout {
    uint32_t maxNear = kMaxOffset; // a larger offset makes the layout version 2 (then kMaxNearOffset)
    uint32_t minFarShift = 1;
};

// Shared serializer for MH and MMH. value[n] is the word stored for node n (absolute for MH, relative
// for MMH). redirect[n] >= 0 makes inner node n point at node redirect[n]'s child group (MMH merge);
// nodes with skip[n] are not written (inside a redirected subtree). headerPos/groupPos (optional)
// receive each node's header word and child group position in the node array.
Result<std::vector<uint32_t>> serialize(const MhTree& tree, const std::vector<uint32_t>& value,
                                        const std::vector<int32_t>* redirect,
                                        const std::vector<uint8_t>* skip, uint32_t magic,
                                        std::vector<uint32_t>* headerPos = nullptr,
                                        std::vector<uint32_t>* groupPos = nullptr, const Layout& layout = {});
// Node-array positions of every inner node's header word and child group in the version 1 layout
// without redirects (serialize's order, no padding), counted without writing the words: 8 B a node.
void layoutPositions(const MhTree& tree, std::vector<uint32_t>& headerPos, std::vector<uint32_t>& groupPos);
// Checks the header, checksum and every reachable record and group against the buffer's bounds.
Result<void> validate(const uint32_t* data, size_t size, uint32_t magic);
stat::ByteBreakdown breakdown(const uint32_t* data, size_t size);
} // namespace mhfmt

Result<std::vector<uint32_t>> encodeMH(const DualDepthMap& map, const mhfmt::Layout& layout = {});
Result<std::vector<uint32_t>> encodeMH(const MhTree& tree, const mhfmt::Layout& layout = {});
Result<void> validateMH(const uint32_t* data, size_t size);
// Bytes per part: header, nodes (header words of inner records), values (value words).
stat::ByteBreakdown breakdownMH(const uint32_t* data, size_t size);

// The lookups: mhLookup, mhLookupLevel (and mmhLookup, mmhLookupLevel, which mmh.h declares) are one
// source text with the GLSL decoders, shaders/static/mh_descent.h, compiled here with the buffer as an
// argument. Only valid on a buffer validateMH (validateMMH) accepted; x, y below the resolution of the
// level looked up. mhLookupLevel(data, base, x, y, steps): the map at the level `steps` below the root.
namespace mhtwin {
using uint = uint32_t;
#define ML_MH_FN inline
#define ML_MH_DATA_PARAM const uint32_t *data,
#define ML_MH_DATA_ARG data,
#define ML_MH_WORD(i) data[i]
#include "shaders/static/mh_descent.h"
static_assert(ML_MH_LEVELS == mhfmt::kLevels && ML_MH_ROOT_TYPE == mhfmt::kRootType &&
              ML_MH_NODE_OFFSET == mhfmt::kNodeOffset && ML_MH_HEADER_WORDS == mhfmt::kHeaderWords &&
              ML_MH_FAR_SHIFT == mhfmt::kFarShift && ML_MH_FAR_BIT == mhfmt::kFarBit);
} // namespace mhtwin
using mhtwin::mhLookup;
using mhtwin::mhLookupLevel;
inline uint32_t mhLookup(const uint32_t* data, uint32_t x, uint32_t y) {
    return mhLookup(data, 0u, x, y);
}

} // namespace ml
