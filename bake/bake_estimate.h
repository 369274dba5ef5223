// The bake's peak memory, estimated from its arguments before any work: `bake` prints it, refuses a
// whole-map bake whose estimate passes --max-memory and bounds a tiled bake's tree by what the limit
// leaves; at the end it prints the measured peak (peakResidentBytes, bake/bake_tiled.h). Two formulas:
//
// Whole maps and the MH family's tiles (bakePeakBytes), from the method and resolutions only:
//   base     400 MiB: scene, casters, Vulkan device and renderer;
//   words    every record's words are held until the file is written, then serialised beside them
//            (x2). A whole map: 4 B a texel for every method (sm stores one depth per texel: 8 lights at
//            2048^2 are 134,219,020 bytes; the compressed methods are far below it on the night city,
//            mh 1.2 MB, dagmh 0.6 MB, cpvs 0.8 MB, but have no proven bound, so they count as sm);
//   working  one map at a time is rendered (enter and exit, 8 B a texel) and encoded (scratch allowed
//            16 B a texel). Measured peak RSS (/usr/bin/time -v manylights bake --method M --res 2048
//            --lights 0-7): sm 516 MB, mh 310, dagmh 310, cpvs 257, estimate 752 MiB;
//   tiles    a tiled map holds no map: a tile per hardware thread (tiledWorkingBytes) and the MH tree,
//            which follows the map's detail, not its size. It is counted at one node per 64 texels (the
//            night city's moon has 1 per 32 at 4096^2, 1 per 52 at 8192^2, 1 per 75 at 16384^2), each
//            held twice while tiles are spliced (32 B) plus its output words (8 B). A tile shard (one of
//            `shards` > 1) holds only its tiles' packed nodes (16 B), written once more. SM in tiles
//            holds no tree: its words (4 B a texel) are filled tile by tile, so it is words and tiles,
//            without the whole map's 24 B a texel of map and scratch.
//
// CPVS in tiles (cpvsTiledPeakBytes, when every map of the bake is tiled), from what the region build
// (shadows/static/cpvs_tiled.h) holds, per map of side N, tile T, P hardware threads, region side
// R = max(T, N / 16):
//   base     the process's resident bytes when the estimate is made (the scene is loaded; the estimate
//            is never below the peak so far, which the measured peak includes), the Vulkan
//            device when the renderer is gpu (lavapipe: 74-76 MiB measured, 128 MiB allowed), and per
//            caster triangle the rasteriser's projected triangle (88 B) and the caster soup (37 B),
//            both allowed twice for vector growth (256 B);
//   strips   a strip of R x h texels per thread (R h <= max(T^2, 8 R)): enter and exit (8 B a texel) and
//            the rasteriser's hit slots (8 slots of 8 B and a 4 B count: 68 B a texel);
//   region   the region's precompute (per 8x8 tile 4 B of step index and 8 B of min-max hierarchy, x4/3
//            for its levels; 12 B a visibility step, one per 16 texels allowed: the closed city's moon
//            has one per 64 at 4096^2, one per 110 at 16384^2, one per 136 at 65536^2, the large one
//            per 35 at 8192^2), held
//            twice while the strips' parts are appended, and its inserted, uncompressed nodes and leaves
//            (36 B each, one per 8 region texels allowed: 2.4 B a texel measured at 4096^2, 2.8 B at
//            16384^2, 1.8 B at 65536^2, 3.4 B for the large city at 8192^2);
//   DAG      the distinct nodes and leaves grow with the map's side, not its area (the closed city's
//            moon: 27.6 N at 4096^2, 30.3 N at 16384^2, 27.0 N at 65536^2; the large city's 88 N at
//            4096^2, 113 N at 16384^2), counted at kCpvsNodesPerSide N nodes of 36 B, held three times
//            while the last two halves merge (both inputs and the result; the live sub-DAGs measured
//            2.1x the final DAG's bytes at 4096^2 to 65536^2), then the layout's words (below the DAG's
//            bytes) beside it.
// A CPVS map has no proven node bound either; the counts are the measured ones with a margin, and the
// live sub-DAGs are held to what --max-memory leaves (bakeTilesOf, apps/bake.cpp).
#pragma once
#include "bake/bake.h"
#include "scenes/scene.h"

#include <vector>

namespace ml {

// What a bake holds before its first map: measured where the bake runs (bakeBaseOf).
struct BakeBase {
    uint64_t residentBytes = 0;   // this process's resident memory when the estimate is made
    uint64_t peakBytes = 0;       // its peak so far (loading the scene may have passed what it keeps)
    uint64_t casterTriangles = 0; // the scene's static caster triangles (castersFromScene)
    bool gpuDevice = true;        // the Vulkan device will be created (--renderer gpu)
};

// The base of a bake of `scene` made by this process now.
BakeBase bakeBaseOf(const Scene& scene, bool gpuDevice);

// Nodes and leaves of a tiled CPVS map allowed per texel of its side: 3.2x the closed city's moon. The
// large city's moon (night-city-large-closed, 40 x 40 blocks) has 100 N at 8192^2 and 113 N at 16384^2,
// but its live sub-DAGs (130 MB at 16384^2) stay below the three copies counted (170 MB), and its bake
// measured 470 MiB against an estimate of 735 MiB.
constexpr uint64_t kCpvsNodesPerSide = 96;

// Peak bytes of a bake of maps of the given sides (a point light has six), `tile` from --tile (0: none).
// CPVS bakes whose maps are all tiled use cpvsTiledPeakBytes; the rest the whole-map / MH formula.
uint64_t bakePeakBytes(const std::vector<uint32_t>& faceResolutions, StaticMethod method, uint32_t tile,
                       uint32_t shards, const BakeBase& base);

// The CPVS region build's peak for these maps, built one after another (see above); `threads` 0: the
// machine's hardware threads.
uint64_t cpvsTiledPeakBytes(const std::vector<uint32_t>& faceResolutions, uint32_t tile, const BakeBase& base,
                            uint32_t threads = 0);

// This process's resident memory now (/proc/self/statm), bytes; 0 where unknown.
uint64_t currentResidentBytes();

} // namespace ml
