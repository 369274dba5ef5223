// One light's tiles over several processes: `bake --shard I/N` of a tiled bake (bake_tiled.h) with one
// light builds the tiles k with k mod N = I into a tile part; `merge` checks the N parts together and
// assembles the bake file a single process would have written, byte for byte (the same tree, then the
// same encoder: shadows/static/mh_tiled.h).
//
// The tile part file ('MLTP'), little-endian 32-bit words:
//   0 magic 'MLTP'        6 resolution      12 seed                  18, 19 build id (lo, hi)
//   1 version (2)         7 tile side       13 scene string bytes S  20..41 frustum: view (16), fov,
//   2 header words H      8 light           14 tiles in this part K          near, far, orthoHalf,
//   3 shard index I       9 face            15 depth planes P                orthoHalfY, fitMargin
//   4 shard count N      10 renderer (0/1)  16, 17 scene fingerprint
//   5 method             11 scene lights    42.. the scene string (SceneSpec::scene), zero-padded
//   then P planes of 4 words (a lo, a hi, dx, dy: DAG-MH's planar tree, mh.h; P = 0 otherwise)
//   then K tiles: index, lo, hi, flags, plane, node count C, then C nodes of 4 words (MhPackedNode)
//   last word: checksum, word-wise FNV-1a over every other word
// The merge compares everything but I (scene by name, lights, seed and fingerprint; the build, because
// another build's rasteriser or reduction may differ) and needs every tile of the grid exactly once.
#pragma once
#include "bake/bake_shard.h"
#include "shadows/static/mh_tiled.h"

namespace ml {

struct TilePart {
    ShardId shard;
    StaticMethod method = StaticMethod::None;
    uint32_t resolution = 0, tile = 0, light = 0, face = 0;
    BakeRenderer renderer = BakeRenderer::Cpu;
    SceneSpec scene;
    LightFrustum frustum;
    uint64_t build = 0, fingerprint = 0;
    std::vector<std::pair<uint32_t, MhTile>> tiles; // (tile index, tile), increasing index
    std::vector<DepthPlane> planes;                 // DAG-MH: the planar tree's planes (mh.h)
};

Result<std::vector<uint32_t>> serializeTilePart(const TilePart& part);
// Checks the header, the checksum, every tile (validateMhTile) and that the tiles are shard I's.
Result<TilePart> parseTilePart(const std::string& name, const uint32_t* words, size_t count);
Result<void> writeTilePart(const std::string& path, const TilePart& part);
Result<TilePart> readTilePart(const std::string& path);
// Whether the file starts with the tile part magic (merge picks the reader by it).
bool isTilePartFile(const std::string& path);

// Builds shard `id` of light `light`'s tiles (face 0: a spot or directional map) on the CPU rasteriser.
Result<TilePart> bakeTilePart(const Scene& scene, const SceneSpec& spec, StaticMethod method,
                              uint32_t resolution, uint32_t tile, uint32_t light, ShardId id,
                              BakeRenderer renderer, uint64_t build,
                              const std::function<void(double)>& progress = {});
// The bake file of one process from the N parts (`names` name them in errors).
Result<BakeFile> mergeTileParts(std::vector<TilePart>&& parts, const std::vector<std::string>& names);

} // namespace ml
