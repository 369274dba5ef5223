// The bake driver: static lights of a scene -> dual depth maps -> a static method's words -> BakeFile,
// and its inverse check, verify: re-render every baked light and compare every texel (or voxel).
//
// Rendering goes through a DualRenderFn: the Vulkan renderer (shadows/gpu/dual_depth_gpu.h) or the CPU
// rasteriser, which must produce the same maps (raster_dual.h defines them). Spot lights bake one map,
// point lights six cube faces; MH-family maps past kBakeWholeMapMax are built tile by tile
// (bake_tiled.h). Lights that cannot be baked (dynamic and directional lights) are never
// dropped silently: they come back in BakeResult::skipped with the reason.
#pragma once
#include "io/result.h"
#include "scenes/scenes.h"
#include "shadows/static/bake_file.h"
#include "shadows/static/raster_dual.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ml {

using DualRenderFn =
    std::function<Result<DualDepthMap>(const CasterTriangles&, const LightFrustum&, uint32_t resolution)>;

// Row tiles of at most this many texels (4096 x 1024): a tile's hit lists are what the rasteriser holds
// in memory at once, so the tile bounds the bake's memory beside the map itself.
constexpr uint64_t kBakeTileTexels = uint64_t(4096) * 1024;
// Whole-map bakes hold the dual depth map (8 B a texel) and the encoder's scratch: 16384^2 is 2 GiB of
// map. MH, MMH and DAG-MH bake past it in tiles (bake_tiled.h) up to the bake file's kMaxResolution, CPVS
// (bake_tiled_cpvs.h) up to kCpvsMaxResolution, holding a tile per worker and the output. SM stops here
// even in tiles: its output is itself 4 B a texel (1 GiB at 16384^2; 4 GiB at 32768^2, past any storage
// buffer a device binds: Vulkan's maxStorageBufferRange is a 32-bit byte count, below 4 GiB).
constexpr uint32_t kBakeWholeMapMax = 16384;
constexpr uint32_t kBakeMaxResolution = 262144; // kMhMaxResolution (shadows/static/mh.h)
// Tiled bakes' tile side: a 512^2 tile's hit lists and counting-sort table (8 B a hit, 4 B a texel)
// stay small, once per hardware thread; a 2048^2 tile holds 16x as much (`bake --tile` to choose).
constexpr uint32_t kBakeDefaultTile = 512;
// Whether a bake at `resolution` (with `tile` from --tile, 0: none asked) goes tile by tile: the MH
// family (bake_tiled.h) and CPVS (bake_tiled_cpvs.h, regions of max(tile, its grid cell) texels), and SM
// when --tile asks, up to kBakeWholeMapMax (its output, not a tree: no larger map tiles).
inline bool bakeTiled(StaticMethod method, uint32_t resolution, uint32_t tile) {
    if (method == StaticMethod::SM) return tile != 0 && resolution <= kBakeWholeMapMax;
    const bool tiles = method == StaticMethod::MH || method == StaticMethod::MMH ||
                       method == StaticMethod::DAGMH || method == StaticMethod::CPVS;
    return tiles && (tile != 0 || resolution > kBakeWholeMapMax);
}

// Why SM refuses `resolution` past kBakeWholeMapMax, whole or in tiles: its output's size.
inline std::string smPastLimitReason(uint32_t resolution) {
    const uint64_t mib = uint64_t(resolution) * resolution * 4 >> 20;
    return "sm stores 4 B a texel: " + std::to_string(resolution) + "^2 is " + std::to_string(mib) +
           " MiB, past any storage buffer a device binds (under 4096 MiB); sm bakes up to " +
           std::to_string(kBakeWholeMapMax) +
           "^2, whole or in tiles (mh, mmh, dagmh and cpvs bake "
           "larger maps in tiles)";
}

// The CPU rasteriser (DualRasterizer::render in row tiles).
DualRenderFn cpuDualRenderer(uint64_t tileTexels = kBakeTileTexels);

struct BakeProgress {
    uint32_t light = 0;              // scene light index
    uint32_t ordinal = 0, count = 0; // this is light `ordinal` (0-based) of `count` being processed
    const char* phase = "";          // "render", "encode", "check", "done"
    double fraction = 0;             // of the whole bake or verify, 0..1
    double elapsedSeconds = 0;       // since the bake or verify started
};
using BakeProgressFn = std::function<void(const BakeProgress&)>;

struct SkippedLight {
    uint32_t light = 0;
    std::string reason;
};

struct LightBakeStats {
    uint32_t light = 0;
    uint32_t resolution = 0; // of this light's map(s)
    double renderSeconds = 0, encodeSeconds = 0;
    uint64_t coveredTexels = 0, closedTexels = 0; // texels with a hit, and with exit > enter
    uint64_t bytes = 0;                           // the record's data
    uint32_t tiles = 0;                           // tiled bakes: tiles built (0: whole map)
    uint32_t emptyTiles = 0;                      // of them, empty ones (no caster reaches): not rendered
    uint64_t treeNodes = 0;                       // tiled bakes: the MH tree's nodes
    // Tiled CPVS (CpvsStats): visibility steps, the largest region's inserted nodes and leaves, the bytes
    // of sub-DAGs alive at once at most: what bake/bake_estimate.h allows for, printed beside it.
    uint64_t cpvsSteps = 0, regionNodesPeak = 0, regionLeavesPeak = 0, dagLiveBytes = 0;
};

struct BakeResult {
    BakeFile file;
    std::vector<SkippedLight> skipped;
    std::vector<LightBakeStats> lights; // one per record, same order
    double renderSeconds = 0, encodeSeconds = 0;
};

// Bakes the selected scene lights (indices into scene.lights, any order, duplicates ignored; records
// come out sorted by light index). `spec` is what re-creates `scene` (stored for verify). Fails when
// an index is out of range, the resolution is not one the method encodes, or no selected light can be
// baked. An empty `render` uses the CPU rasteriser, reporting progress per tile.
// Tiles (bakeTiled): MH, MMH, DAG-MH and CPVS above kBakeWholeMapMax, or at any resolution (SM: up to
// kBakeWholeMapMax) when `tiles.tile` is set, render on the CPU rasteriser tile by tile (bake_tiled.h)
// whatever `render` is; the words equal the whole-map bake's.
struct BakeTiles {
    uint32_t tile = 0;     // 0: tiles of kBakeDefaultTile, only above kBakeWholeMapMax
    uint64_t maxNodes = 0; // per record's MH tree; 0: unbounded
};
Result<BakeResult> bakeScene(const Scene& scene, const SceneSpec& spec, StaticMethod method,
                             uint32_t resolution, const std::vector<uint32_t>& lights,
                             const BakeProgressFn& progress = {}, const DualRenderFn& render = {},
                             const BakeTiles& tiles = {});

// Why bakeScene would skip this light ("" when it bakes it): the sharded bake's cost estimate needs it.
std::string bakeSkipReason(const Scene& scene, const Light& light);
// The frustums a light bakes in this scene (a directional light's covers the scene's bounds).
std::vector<LightFrustum> bakeFrustums(const Scene& scene, const Light& light);

// bakeScene of the `selected` lights (and those `need` lists) with each light's resolution from `need`
// (need.h: estimateNeed): lights of resolution 0 (no caster in their volume) get no record; lights that
// cannot be baked are skipped and listed as by bakeScene; a bakeable selected light without an entry is
// an error. The file carries the need block (version 2) with every baked or unbaked light's resolution
// and reason, and its resolution is need.maxRes.
Result<BakeResult> bakeSceneNeed(const Scene& scene, const SceneSpec& spec, StaticMethod method,
                                 const BakeNeed& need, const std::vector<uint32_t>& selected,
                                 const BakeProgressFn& progress = {}, const DualRenderFn& render = {},
                                 const BakeTiles& tiles = {});

// "all", "N", "A-B" (inclusive), or a comma-separated list of those; sorted, without duplicates.
// Errors are one line: malformed items and indices not below lightCount.
Result<std::vector<uint32_t>> parseLightSelection(const std::string& text, uint32_t lightCount);

struct VerifyLight {
    uint32_t light = 0;
    uint64_t checked = 0, mismatches = 0, undefined = 0; // undefined: CPVS voxels inside closed objects
    double renderSeconds = 0, checkSeconds = 0;
    // A fitted directional record: the share of the N equal depth slices of [near, far]
    // between the nearest and the deepest caster surface the re-rendered map enters; -1 otherwise.
    double casterSlices = -1.0;
};

struct VerifyReport {
    uint64_t checked = 0, mismatches = 0, undefined = 0;
    std::vector<VerifyLight> lights;
    std::vector<std::string> examples; // the first few mismatches, one line each
};

// Re-renders each record's dual depth map from `scene` (which must be the file's scene) with the
// record's frustum, and checks every texel: depth methods enter <= lookup <= exit, empty texels exactly
// kDepthEmpty; CPVS every voxel against the voxelisation of the maps (verifyCpvs; undefined voxels are
// counted apart). Fails (rather than counting mismatches) when the scene no longer matches the file:
// a record's light missing, not a static spot or point light, or with a different frustum.
// Depth-method records above kBakeWholeMapMax, or any when `tile` is set, are checked tile by tile on the
// CPU rasteriser (bounded memory at any resolution).
Result<VerifyReport> verifyBakeScene(const BakeFile& file, const Scene& scene,
                                     const DualRenderFn& render = {}, const BakeProgressFn& progress = {},
                                     uint32_t tile = 0);

// Scene modifiers: SceneSpec::scene is a scene name or path, optionally followed by what `bake` changed
// in it, so that verify re-creates the same scene:
//   "|bounds=x0,y0,z0,x1,y1,z1"  the scene bounds directional lights are fitted to
//   "|light-dir=x,y,z"           a static directional light appended after the scene's lights
// (floats printed with 9 significant digits, so they read back exactly). SceneSpec::lights counts the
// appended lights too. Without modifiers the string is the plain name.
struct SceneModifiers {
    std::string base; // the scene name or path
    bool bounds = false;
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};
    std::vector<glm::vec3> lightDirs;
};
Result<SceneModifiers> parseSceneModifiers(const std::string& scene);
std::string sceneModifierString(const SceneModifiers& m);
// Applies bounds and appends the directional lights (static, white, intensity 1).
void applySceneModifiers(Scene& scene, const SceneModifiers& m);

// The scene a bake file was made from (modifiers applied).
Result<Scene> loadBakeScene(const SceneSpec& spec, const LoadOptions& options = {});

// Reloads the scene from the file's SceneSpec, then verifyBakeScene.
Result<VerifyReport> verifyBake(const BakeFile& file, const DualRenderFn& render = {},
                                const BakeProgressFn& progress = {});

} // namespace ml
