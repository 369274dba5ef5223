// Out-of-core construction of the MH tree (mh.h), the input of MH, MMH and DAG-MH: the dual depth map is
// never held whole. The padded 2^L x 2^L map is cut into T x T tiles (T a power of two); each tile is
// rendered, reduced bottom-up into its subtree (mhbuild::buildSubtree) and dropped; the tile roots then
// form the finest level of a small top pyramid, reduced the same way (mhbuild::reduceLevel), and the
// tree is assembled in preorder with each tile's nodes spliced in at its root.
//
// Why this is the whole-map tree, node for node: the bottom-up pass decides a node's interval and its
// "has a present descendant" bit from its four children only, so everything at or below a tile's root
// depends on the tile's texels alone. The one bit that comes from above is whether the tile root keeps
// its own value (its parent may represent it): the top pyramid decides it, exactly as the whole-map pass
// would. Tiles visited in quadtree order make the preorder a concatenation. TiledMh.* check the trees
// and the MH, MMH and DAG-MH words equal the whole-map build's at 256^2-1024^2 with 64^2 tiles.
//
// Memory: per worker thread about 30 B a tile texel (the tile's enter/exit, its intervals and its
// pyramid; T = 512: 8 MiB) plus the source's own scratch, and the output tree: 12 B a node while the
// tiles are built (packed, children implicit in preorder), then 28 B a node assembled, each tile's
// packed nodes freed as it is spliced (at most 40 B a node at once). Never the map.
#pragma once
#include "shadows/static/mh.h"

#include <functional>

namespace ml {

// Fills a w x h block of the map at texel (x0, y0) with enter and exit depths (row-major, w words a
// row; dual_depth.h's meaning). Called from several threads at once, each with its own block.
using DualTileSource = std::function<Result<void>(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h,
                                                  uint32_t* enter, uint32_t* exit)>;

struct MhTiledOptions {
    uint32_t tile = 2048;                 // tile side: a power of two; clamped to the padded map
    uint32_t threads = 0;                 // workers; 0: the machine's hardware threads
    uint64_t maxNodes = 0;                // 0: none; past it the build stops (the tree's memory bound)
    std::function<void(double)> progress; // fraction of tiles done, from one thread at a time
};

struct MhTiledStats {
    uint32_t tiles = 0, tileSide = 0;
    uint64_t coveredTexels = 0, closedTexels = 0; // enter != empty, and exit > enter
    uint64_t nodes = 0;
    double renderSeconds = 0, reduceSeconds = 0; // summed over the workers
    double assembleSeconds = 0;                  // the top pyramid and the splicing
};

// The MH tree of a resolution x resolution map (1..65536) read tile by tile from `source`: equal to
// buildMhTree of the whole map. Fails with the source's first error, on a tile that is not a power of
// two, or when the tiles' nodes pass options.maxNodes (with the count reached).
Result<MhTree> buildMhTreeTiled(uint32_t resolution, const DualTileSource& source,
                                const MhTiledOptions& options = {}, MhTiledStats* stats = nullptr);

// A tile source over a map already in memory (tests, and the whole-map path's twin).
DualTileSource dualTileSourceOf(const DualDepthMap& map);

} // namespace ml
