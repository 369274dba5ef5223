// Sharded bakes: one bake split over N processes (or farm tasks) by light, and the merge of the parts
// back into the bake file a single process would have written, byte for byte.
//
// The split. Every selected light gets a cost estimate, maps * resolution^2 (a spot bakes 1 map, a
// point light 6 cube faces, a skipped light 0), and the lights are dealt greedily, costliest first
// (ties: lower light index first), each to the shard with the least cost so far (ties: lower shard).
// It depends only on the scene, the selection and N, so every task computes the same split on its own,
// with no coordinator; shards may be empty when N exceeds the lights (an empty part is valid).
//
// The part file ('MLBP'), little-endian 32-bit words; it wraps a complete bake file of the shard's own
// records (bake_file.h, with all its checks and checksums) behind a header that says which shard it is:
//
//   header [0, H)   H = 16 + S + K + ceil(D / 4)
//     0 magic 'MLBP'   4 shard count N        8, 9 scene fingerprint (lo, hi)   12, 13 inner words (lo, hi)
//     1 version (1)    5 selected lights S    10, 11 build id (lo, hi)          14 reserved (0)
//     2 header words H 6 own lights K                                           15 header checksum
//     3 shard index I  7 device string bytes D
//     16..     the selected lights (S words, increasing): the whole bake's --lights, skipped ones too
//     16+S..   this shard's lights (K words, increasing, a subset of the selection)
//     16+S+K.. the device string (UTF-8, zero-padded to a word): "cpu", or the GPU's name and driver
//   inner [H, H + inner words): a bake file (bake_file.h) holding the records of the shard's own lights
//
// The header checksum is word-wise FNV-1a over [0, H) with its own slot counted as 0; the inner file
// carries its own checksums. What the merge compares, and why:
//   - scene fingerprint: FNV-1a 64 over the caster triangles (positions' bits, closed flags) and every
//     light's type, dynamic flag and baked frustums, as bakeScene sees them: catches a scene file or
//     generator that changed between tasks even when its name did not;
//   - inner header: scene name / light count / seed, method, resolution, renderer: all that shapes bytes;
//   - build id: a hash of the manylights executable that baked the part: encoders of another build may
//     produce other bytes;
//   - device: GPU renderers of different vendors or drivers round depth differently;
//   - selection and N: the parts must be shards of one split.
// A light is "covered" by the part whose own list holds it; own lights without records are the lights
// bakeScene skipped (dynamic, directional), exactly as a single bake skips them.
#pragma once
#include "io/result.h"
#include "scenes/scene.h"
#include "shadows/static/bake_file.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ml {

namespace partfmt {
constexpr uint32_t kMagic = bakefmt::kPartMagic;
constexpr uint32_t kVersion = 1;
constexpr uint32_t kFixedHeaderWords = 16;
constexpr uint32_t kMaxShards = 65536;
constexpr uint32_t kMaxDeviceBytes = 512;
constexpr uint32_t kMaxLights = 65536;
enum : uint32_t {
    kHMagic,
    kHVersion,
    kHHeaderWords,
    kHShard,
    kHShards,
    kHSelected,
    kHOwn,
    kHDeviceBytes,
    kHFingerprintLo,
    kHFingerprintHi,
    kHBuildLo,
    kHBuildHi,
    kHInnerLo,
    kHInnerHi,
    kHReserved,
    kHChecksum,
};
} // namespace partfmt

// "I/N" with 0 <= I < N <= partfmt::kMaxShards.
struct ShardId {
    uint32_t index = 0, count = 1;
};
Result<ShardId> parseShard(const std::string& text);

// The cost estimate of baking one light: maps (1 spot, 6 point faces, 0 when bakeScene would skip it)
// times resolution^2.
uint64_t bakeCostEstimate(const Scene& scene, const Light& light, uint32_t resolution);
// Splits (light, cost) pairs into `count` shards as described above; shard s's lights come back sorted.
std::vector<std::vector<uint32_t>> splitShards(const std::vector<std::pair<uint32_t, uint64_t>>& costs,
                                               uint32_t count);
// The lights of shard `id` among `selected` (sorted, unique scene light indices).
std::vector<uint32_t> shardLights(const Scene& scene, const std::vector<uint32_t>& selected,
                                  uint32_t resolution, ShardId id);

// FNV-1a 64 of the scene as the bake sees it (see above).
uint64_t sceneFingerprint(const Scene& scene);
// FNV-1a 64 of a byte range, for the build id (the executable's bytes) and the fingerprint.
uint64_t fnv1a64(const void* data, size_t bytes, uint64_t h = 0xcbf29ce484222325ull);

struct BakePart {
    ShardId shard;
    uint64_t fingerprint = 0, build = 0;
    std::string device;             // "cpu", or the GPU's name and driver version
    std::vector<uint32_t> selected; // the whole bake's selection, sorted, unique
    std::vector<uint32_t> own;      // this shard's lights, sorted, unique, a subset of `selected`
    BakeFile file;                  // the records of the own lights that were baked
};

Result<std::vector<uint32_t>> serializeBakePart(const BakePart& part);
Result<BakePart> parseBakePart(const std::string& name, const uint32_t* words, size_t count);
Result<void> writeBakePart(const std::string& path, const BakePart& part);
Result<BakePart> readBakePart(const std::string& path);

// Checks that the parts are the N shards of one bake (same fingerprint, build, device, scene, method,
// resolution, renderer, selection and N; every selected light in exactly one part) and returns the bake
// file a single process would have written for the selection. Errors are one line naming the parts
// (by `names`, parallel to `parts`) and the lights at fault.
Result<BakeFile> mergeBakeParts(const std::vector<BakePart>& parts, const std::vector<std::string>& names);

} // namespace ml
