// Out-of-core bakes and verifies of one record, tile by tile (shadows/static/mh_tiled.h): the dual depth
// map is never held whole, so MH, MMH and DAG-MH bake past the whole-map limit (kBakeWholeMapMax) up to
// kMhMaxResolution (262144^2). Tiles are rendered by the CPU rasteriser (DualRasterizer::renderRect) on every
// hardware thread; a bake and its verify render the same texels whatever the tile size. SM takes tiles
// too, up to kBakeWholeMapMax: each tile's midpoints go straight into the output words.
#pragma once
#include "bake/bake.h"

namespace ml {

// The MH family's, SM's or CPVS's words for one map, built from tiles. `maxNodes` (0: none) bounds the tree:
// past it the bake stops with the count and the memory it would need. progress gets 0..1 over the tiles.
struct TiledBakeOptions {
    uint32_t tile = kBakeDefaultTile;
    uint64_t maxNodes = 0;
    std::function<void(double)> progress;
};
Result<std::vector<uint32_t>> bakeRecordTiled(StaticMethod method, const CasterTriangles& casters,
                                              const LightFrustum& frustum, uint32_t resolution,
                                              const TiledBakeOptions& options, LightBakeStats& stats);

// Every texel of a depth-method record against the re-rendered tiles: enter <= decoded <= exit, empty
// texels exactly empty. Mismatch examples (at most `maxExamples` in all) are appended to `examples`.
Result<void> verifyRecordTiled(const BakeRecord& record, const CasterTriangles& casters, uint32_t tile,
                               const std::function<void(double)>& progress, VerifyLight& out,
                               std::vector<std::string>& examples, size_t maxExamples);

// A tiled bake's working memory beside its output: per hardware thread a tile's enter, exit, intervals
// and pyramid (about 30 B a texel) and the rasteriser's hits (8 B each; allowed 2 a texel).
uint64_t tiledWorkingBytes(uint32_t tile);

// This process's peak resident memory so far (getrusage), bytes; 0 where unknown.
uint64_t peakResidentBytes();

} // namespace ml
