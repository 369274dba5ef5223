// `bake --shard I/N` of a tiled bake with one light: a tile part (bake/bake_tile_part.h), and the build
// id every part carries.
#pragma once
#include "bake/bake_tile_part.h"

#include <string>
#include <vector>

namespace ml {

// The build id of a part: a hash of this executable's bytes (another build's encoders may differ).
Result<uint64_t> executableHash();

// Bakes shard `id` of the one selected light's tiles into `out`; the exit status.
int bakeTileShard(const Scene& scene, const SceneSpec& spec, StaticMethod method, uint32_t res, uint32_t tile,
                  const std::vector<uint32_t>& selected, ShardId id, BakeRenderer renderer,
                  const std::string& out, bool quiet);

// `inspect` of a tile part: its shard, light, tiles and nodes (one line, or one JSON object); the exit
// status.
int inspectTilePart(const std::string& path, bool json);

// `merge` of tile parts (every path one): the bake file at `out`; the exit status.
int mergeTileShards(const std::vector<std::string>& paths, const std::string& out, bool quiet);

} // namespace ml
