// CPVS internals shared by cpvs_build.cpp (insertion, compression) and cpvs_layout.cpp (flat words).
// Not part of the public API; see cpvs.h for the algorithm overview.
#pragma once
#include "shadows/static/cpvs.h"

#include <vector>

namespace ml::cpvs_detail {

using Node = CpvsOctree::Node;

// A DAG in construction: levels[k] holds nodes of size 8 << k (k = 0 .. top, the grid cell size). A
// node's child c (bit 0 x, bit 1 y, bit 2 z: near slices first) is homogeneous when its childMask bit is
// clear (value in shadowMask), else child[c] indexes levels[k - 1] (or leaves when k = 0). Unused child
// slots are 0 so nodes compare by plain memberwise comparison.
struct Dag {
    uint32_t resolution = 0, log2Resolution = 0, gridLog2 = 0, cellLog2 = 0;
    std::vector<std::vector<Node>> levels;
    std::vector<uint64_t> leaves; // 4^3 voxels, bit x + 4 y + 16 z
    // (2^g)^3 grid cells, index x + G (y + G z): 0 lit, 1 shadowed, else 2 + node index in levels.back()
    std::vector<uint32_t> grid;
};

// A block of grid cells: columns [x0, x0 + w) x [y0, y0 + w) of cells, every z. grid has w * w * G
// entries, index (x - x0) + w ((y - y0) + w z), coded like Dag::grid.
struct CellBlock {
    uint32_t x0 = 0, y0 = 0, w = 0;
    std::vector<uint32_t> grid;
};

// The precompute (cpvsPrecompute) in pieces, so that a map is never needed whole: precomputeBlock appends
// the 8x8 tiles of a width x height block (multiples of 8; texel (x, y) at enter[y * stride + x]) in
// row-major tile order to stepFirst / stepStart / stepMask / minT[0] / maxT[0]; precomputeEmpty appends
// `tiles` tiles of empty texels (no step: lit everywhere) without reading any; precomputeAppend appends
// another such partial precompute; precomputeFinish adds stepFirst's end and the hierarchy up to topSize.
// pre.tiles must be the per-axis tile count of the whole block appended (row-major), minT/maxT one level.
void precomputeBlock(const CpvsSpace& space, const uint32_t* enter, const uint32_t* exit, uint32_t width,
                     uint32_t height, size_t stride, CpvsPrecompute& pre);
void precomputeEmpty(const CpvsSpace& space, size_t tiles, CpvsPrecompute& pre);
void precomputeAppend(CpvsPrecompute& pre, const CpvsPrecompute& part);
void precomputeFinish(CpvsPrecompute& pre, uint32_t topSize);

// Section 3.2 insertion. progress(f) with f in [0, 1] after each grid layer.
Dag insert(const CpvsPrecompute& pre, uint32_t log2Resolution, uint32_t gridLog2,
           const std::function<void(float)>& progress);

// The same for one block of cells only (a region of the section 4.3 build; block.grid is not used): the
// returned Dag's grid has the block's layout (w * w * G entries). Insertion never shares nodes between
// x, y footprints, so the nodes of the blocks of a partition are exactly the nodes of insert(), split.
Dag insertBlock(const CpvsPrecompute& pre, uint32_t log2Resolution, uint32_t gridLog2,
                const CellBlock& block);

// Section 4.3: the region build. Splits the grid's x, y into (2^regionLog2)^2 blocks, inserts and
// bottom-up compresses each block's sub-DAG alone, and merges the sub-DAGs pairwise (binary-counter order,
// so at most log2(regions) + 1 sub-DAGs are alive) with sorted-layer merges: equal nodes are found by full
// content comparison, never by a hash. The result equals insert() + compressBottomUp() node for node.
struct RegionStats {
    uint32_t regions = 0;
    double insertMs = 0, compressMs = 0, mergeMs = 0;
    uint64_t nodesInserted = 0, leavesInserted = 0;
    uint64_t regionNodesPeak = 0, regionLeavesPeak = 0; // the largest region's insertion
    uint64_t liveBytesPeak = 0;                         // nodes + leaves held at once
};
Dag buildRegions(const CpvsPrecompute& pre, uint32_t log2Resolution, uint32_t gridLog2, uint32_t regionLog2,
                 RegionStats& stats, const std::function<void(float)>& progress);

// The same merge over sub-DAGs from any source: source(block) returns the block's inserted, uncompressed
// sub-DAG (the block's grid layout, log2Resolution - gridLog2 - 2 levels), as insertBlock does; each is
// compressed bottom-up and merged in the same binary-counter order. The result depends only on the voxels,
// not on where the sub-DAGs came from (the levels are the sorted lists of distinct subtrees). Fails with
// the source's error, or once the live sub-DAGs pass maxLiveBytes (0: no bound).
using RegionSource = std::function<Result<Dag>(const CellBlock& block)>;
Result<Dag> mergeRegions(uint32_t log2Resolution, uint32_t gridLog2, uint32_t regionLog2, RegionStats& stats,
                         const std::function<void(float)>& progress, const RegionSource& source,
                         uint64_t maxLiveBytes);

// Section 4.1: sort and merge every level from the leaves up; equality on full node content.
void compressBottomUp(Dag& dag);

// Section 4.2: 64-bit hashes bottom-up from contents, then top-down: per level, nodes with equal hash
// are merged only after a full structural comparison confirms them; children of merged-away nodes are
// never visited. Returns the number of hash collisions met (kept apart). hashBits < 64 truncates the
// hash (tests force collisions with it).
uint64_t compressTopDown(Dag& dag, uint32_t hashBits);

// Fails when the words would pass 2^32 - 1 (offsets are uint32 word indices).
Result<std::vector<uint32_t>> writeLayout(const CpvsSpace& space, const Dag& dag);

inline bool operator<(const Node& a, const Node& b) {
    if (a.childMask != b.childMask) return a.childMask < b.childMask;
    if (a.shadowMask != b.shadowMask) return a.shadowMask < b.shadowMask;
    for (int i = 0; i < 8; ++i)
        if (a.child[i] != b.child[i]) return a.child[i] < b.child[i];
    return false;
}
inline bool operator==(const Node& a, const Node& b) {
    return !(a < b) && !(b < a);
}

} // namespace ml::cpvs_detail
