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
// Memory: per worker thread about 30 B a tile texel (43 B planar: the plane ids of the render, the tile and
// its pyramid) (the tile's enter/exit, its intervals and its pyramid; T = 512: 8 MiB) plus the source's own
// scratch, and the output tree: 16 B a node while the tiles are built (packed, children implicit in
// preorder), then 32 B a node assembled, each tile's packed nodes freed as it is spliced (at most 48 B a node
// at once). Never the map.
#pragma once
#include "shadows/static/mh.h"

#include <functional>

namespace ml {

// Fills a w x h block of the map at texel (x0, y0) with enter and exit depths (row-major, w words a
// row; dual_depth.h's meaning) and, when `plane` is not null (planar builds), the enter plane ids
// (DualRasterizer::renderRect's). Called from several threads at once, each with its own block.
using DualTileSource = std::function<Result<void>(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h,
                                                  uint32_t* enter, uint32_t* exit, uint32_t* plane)>;

struct MhTiledOptions {
    uint32_t tile = 2048;                 // tile side: a power of two; clamped to the padded map
    uint32_t threads = 0;                 // workers; 0: the machine's hardware threads
    uint64_t maxNodes = 0;                // 0: none; past it the build stops (the tree's memory bound)
    std::function<void(double)> progress; // fraction of tiles done, from one thread at a time
    // Optional: true when `source` would fill the block with kDepthEmpty only (DualRasterizer::blockEmpty).
    // Such a whole tile is not rendered: it gets a copy of the one empty tile's subtree (built once),
    // which is what rendering it would give. A fitted moon map at 262144^2 has about half its tiles empty.
    std::function<bool(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h)> emptyBlock;
    // Not empty: a planar tree (mh.h) over these planes, the source asked for plane ids (DAG-MH).
    std::vector<DepthPlane> planes;
};

struct MhTiledStats {
    uint32_t tiles = 0, tileSide = 0;
    uint32_t emptyTiles = 0;                      // of `tiles`, those emptyBlock skipped
    uint64_t coveredTexels = 0, closedTexels = 0; // enter != empty, and exit > enter
    uint64_t nodes = 0;
    double renderSeconds = 0, reduceSeconds = 0; // summed over the workers
    double assembleSeconds = 0;                  // the top pyramid and the splicing
};

// The tile grid of a resolution x resolution map (1..kMhMaxResolution) in tiles of `tile` (a power of two,
// clamped to the padded map): perAxis^2 tiles, row-major, whose roots are level `top` of the tree.
struct MhTileGrid {
    uint32_t resolution = 0, levels = 0, tile = 0, top = 0, perAxis = 0;
    uint32_t count() const { return perAxis * perAxis; }
};
Result<MhTileGrid> mhTileGrid(uint32_t resolution, uint32_t tile);

// A tile's subtree kept between its build and the assembly, 16 B a node: the interval, in `bits` the
// present children (bits 0-3), valued (bit 4) and depth (bits 8-15), and the plane id (planar trees; 0
// otherwise). Children are implicit in preorder: a node's first present child follows it, the next one
// follows the first one's subtree.
struct MhPackedNode {
    uint32_t lo = 0, hi = 0, bits = 0, plane = 0;
};
struct MhTile {
    uint32_t lo = 0, hi = 0, plane = 0; // the root's interval and plane id
    uint8_t flags = 0; // the root's: bit 0 keeps its value (the levels above may clear it), bit 1 has
                       // a present descendant
    bool built = false;
    std::vector<MhPackedNode> nodes; // preorder, nodes[0] the root
};

// Builds the tiles `select` accepts (every tile when empty) into tiles[k] (resized to grid.count(); the
// others stay unbuilt): a shard of one light's tiles. Same failures as buildMhTreeTiled.
Result<void> buildMhTiles(const MhTileGrid& grid, const DualTileSource& source, const MhTiledOptions& options,
                          const std::function<bool(uint32_t)>& select, std::vector<MhTile>& tiles,
                          MhTiledStats* stats = nullptr);
// The tree from every tile of the grid (fails naming a missing one); frees the tiles as it splices them.
// `planes` not empty: the tiles were built planar over them (MhTiledOptions::planes).
Result<MhTree> assembleMhTree(const MhTileGrid& grid, std::vector<MhTile>&& tiles,
                              MhTiledStats* stats = nullptr, const std::vector<DepthPlane>& planes = {});
// Checks a tile read from a file: its node count, root, depths, preorder and children (no child below
// the texels, no leaf without a value), plane ids up to `planes` (an empty interval only with a plane),
// so assembleMhTree can splice it without reading out of bounds.
Result<void> validateMhTile(const MhTileGrid& grid, const MhTile& tile, size_t planes = 0);

// The MH tree of a resolution x resolution map (1..kMhMaxResolution) read tile by tile from `source`: equal
// to buildMhTree of the whole map. Fails with the source's first error, on a tile that is not a power of two,
// or when the tiles' nodes pass options.maxNodes (with the count reached).
Result<MhTree> buildMhTreeTiled(uint32_t resolution, const DualTileSource& source,
                                const MhTiledOptions& options = {}, MhTiledStats* stats = nullptr);

// A tile source over a map already in memory (tests, and the whole-map path's twin).
DualTileSource dualTileSourceOf(const DualDepthMap& map);

} // namespace ml
