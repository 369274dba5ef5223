// Out-of-core CPVS construction: the dual depth map is never held whole, so CPVS bakes past the whole-map
// limit (kCpvsWholeMapMax, 16384^2) up to kCpvsMaxResolution. The unit is the region of the section 4.3
// build (cpvs_regions.cpp), a square block of grid cells through every slice, of side R = max(tile, C)
// texels (C = N >> g, the grid cell). Per region, in Z order:
//   render     strips of R x h texels (h a multiple of 8, R h <= max(tile^2, 8 R)) on every worker; a strip
//              emptyBlock proves empty is not rendered (its 8x8 tiles have no visibility step);
//   precompute each strip's 8x8 tiles (section 3.4) from its own texels only, the strips' lists appended in
//              row order, then the region's min-max hierarchy up to C;
//   insert     the region's cells from that precompute alone (insertion shares nodes only along z within
//              one footprint, so a region's nodes are what the whole-map insertion makes there);
//   merge      sort-compress the region's sub-DAG and merge it into the others bottom-up with full-content
//              comparison (mergeRegions), binary-counter order.
// Why the words equal bakeCpvs of the whole map, byte for byte: the merged levels are the sorted lists of
// all distinct subtrees, which depend on the voxels alone, and each 8x8 tile's steps depend on its 64
// texels alone; the layout is the same function of the same DAG. CpvsTiled.* check it at 256^2-1024^2.
//
// Memory: a strip per worker (8 B a texel plus the source's scratch), the region's precompute (about
// 12 B a 8x8 tile plus 12 B a step) and its inserted nodes (36 B each), the compressed sub-DAGs alive in
// the binary counter (at most log2(regions) + 1, together about the output's nodes at 36 B), then the
// layout's words beside the merged DAG. Never N^2.
#pragma once
#include "shadows/static/cpvs.h"
#include "shadows/static/mh_tiled.h"

#include <functional>

namespace ml {

struct CpvsTiledOptions {
    uint32_t tile = 512;  // a power of two >= 8; clamped to N. Strips hold at most max(tile^2, 8 R) texels
    uint32_t threads = 0; // strip workers; 0: the machine's hardware threads
    uint64_t maxLiveBytes = 0; // 0: none; past it (sub-DAGs alive at once) the bake stops with the size
    std::function<void(double)> progress; // fraction of regions done, from the calling thread
    // Optional: true when the source would fill the block with kDepthEmpty only (DualRasterizer::blockEmpty).
    std::function<bool(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h)> emptyBlock;
};

struct CpvsTiledStats {
    uint32_t regions = 0, regionSide = 0, emptyRegions = 0; // regions emptyBlock skipped whole
    uint64_t strips = 0, emptyStrips = 0;                   // strips of the other regions, and skipped ones
    uint64_t coveredTexels = 0, closedTexels = 0;           // enter != empty, and exit > enter
    double renderSeconds = 0; // rendering and the 8x8 precompute, summed over the workers
};

// The CPVS of a params.resolution^2 map read strip by strip from `source` (same params as bakeCpvs;
// compression is always the region build). Equal to bakeCpvs of the whole map where that exists. Fails
// on a resolution that is not a power of two in [64, kCpvsMaxResolution], a tile that is not a power of
// two >= 8 (so it cannot divide N), the source's first error, the live bound, or a layout past 2^32 words.
Result<CpvsBake> bakeCpvsTiled(const DualTileSource& source, const CpvsParams& params,
                               const CpvsTiledOptions& options, CpvsTiledStats* stats = nullptr);

} // namespace ml
