// CPVS: Compact Precomputed Voxelized Shadows of one static light, after Kämpe, Sintorn, Dolonius and
// Assarsson, "Fast, Memory-Efficient Construction of Voxelized Shadows" (TVCG 2016; "the paper").
//
// VOXEL SPACE (paper section 5, eq. 1). A light with a square frustum, DualDepthMap of resolution N
// (power of two, 64..262144; whole maps up to 16384, larger ones tiled: cpvs_tiled.h) and depth range [near,
// far] is cut into N^3 voxels (x, y, s):
//   x, y  the texel column of the dual depth map (NDC x, y; row 0 at NDC y = -1);
//   s     the log-depth slice: s = k - 1 with k = ceil(N * log(z / near) / log(far / near)), clamped to
//         [0, N-1]. Slice s holds the linear depths z in (z_s, z_{s+1}], z_s = near * (far/near)^(s/N),
//         so every voxel has the same height-to-depth ratio.
// LINEAR SLICING (directional lights). An orthographic light has no perspective to
// compensate, so its N slices are equal: z_s = near + (far - near) s / N, where [near, far] is the box's
// tight slab along the light plus the fit margin (directionalLightFrustum), and slice s holds
// (z_s, z_{s+1}]. Spot and point lights keep eq. 1. The header's slicing word says which (version 1:
// log, version 2: linear); everything below works on the thresholds T and is the same for both.
// All of that is integer once the depth is quantised (dual_depth.h): the N+1 slice boundaries are
// stored as quantised depths T[0..N] (T[s] = quantizeDepth(z_s), computed in double once), and a
// receiver's quantised depth d lies in slice s iff T[s] < d <= T[s+1] (slice 0 and N-1 also take
// everything nearer / farther). The lookup finds s by a binary search over T: no float at all.
//
// VOXEL STATE. A voxel's representative depth is its near boundary T[s]; the voxel is SHADOWED iff a
// receiver at that depth is behind the first caster, T[s] > enter, else LIT. So the voxel holding a
// caster's surface is lit (no self-shadowing of the surface's own voxel) and every receiver in a shadowed
// voxel (depth > T[s] > enter) is truly shadowed. A voxel is UNDEFINED iff all of its receivers lie
// strictly inside closed geometry: T[s] > enter and hi(s) < exit, hi(s) = T[s+1] (0xFFFFFFFE for the
// last slice). Such a voxel is never queried by a receiver outside closed objects and may hold either
// value. Open geometry has exit = enter, so it has no undefined voxels. Per texel the states are a run
// lit [0, a), undefined [a, b), shadowed [b, N): every column is a step function.
//
// PIPELINE (paper sections 3.2-4, 6.1; timings as Table 3):
//   precompute  per 8x8 tile, the minimal list of cumulative visibility masks with the slice where each
//               starts (section 3.4: a mask is taken only when the previous one can no longer be
//               re-used, and it shadows every cell that may be shadowed); a min-max hierarchy of the
//               resolved transition slices over tiles. (cpvs_precompute.cpp)
//   insert      top-down, children in Z order (near slices first); homogeneous volumes end early; a
//               volume identical to an earlier one of the same footprint re-uses its node, tested with
//               the slice of the next casting surface (section 3.2). (cpvs_build.cpp)
//   compress    bottom-up sort and merge of every level (section 4.1), or top-down hash compression
//               (section 4.2); equality is always decided on the full content, never on a hash alone.
//               (cpvs_build.cpp)
//   regions     the default: insert and sort-compress one sub-DAG per x, y block of grid columns, then
//               merge the sub-DAGs' sorted levels pairwise from the leaves up (section 4.3). Equal nodes
//               are found by full content comparison; the result is the bottom-up DAG, byte for byte.
//               (cpvs_regions.cpp)
//   layout      flat uint32 words: header, slice thresholds, a grid of pointers replacing the top levels
//               (section 6.3), inner nodes with child masks, 64-bit leaf masks for the last two levels.
//               docs/cpvs-layout.md has the byte counts. (cpvs_layout.cpp)
// The lookup (single tap and up to 9x9 PCF with a normal bias in integer voxel coordinates, section 5)
// reads only those words; shaders/static/cpvs_lookup.glsl mirrors it line by line.
#pragma once
#include "io/result.h"
#include "shadows/static/dual_depth.h"

#include <bit>
#include <cstdint>
#include <functional>
#include <vector>

namespace ml {

// ---------------------------------------------------------------------------------------------------
// Voxel space

constexpr uint32_t kCpvsMinResolution = 64;
// The format's limit: N + 1 thresholds and the (2^g)^3 grid stay small, voxel coordinates fit an int, and
// every offset is a uint32 word index (writeLayout refuses a DAG past 2^32 - 1 words). A whole-map bake
// holds the dual depth map (8 B a texel: 2 GiB at 16384^2), so only tiled bakes go past kCpvsWholeMapMax.
// Readers built before N could exceed 16384 refuse such records (validateCpvs: "resolution invalid").
constexpr uint32_t kCpvsMaxResolution = 262144;
constexpr uint32_t kCpvsWholeMapMax = 16384;

enum class CpvsSlicing : uint32_t {
    Log = 0,    // eq. 1 (spot and point lights)
    Linear = 1, // equal slices over [near, far] (directional lights)
};

struct CpvsSpace {
    uint32_t resolution = 0; // N
    CpvsSlicing slicing = CpvsSlicing::Log;
    uint32_t log2Resolution = 0;
    float nearPlane = 0.0f, farPlane = 0.0f;
    std::vector<uint32_t> thresholds; // N + 1 quantised depths T[s], non-decreasing
};

// Fails unless N is a power of two in [64, 262144] and 0 < near < far (finite).
Result<CpvsSpace> makeCpvsSpace(uint32_t resolution, float nearPlane, float farPlane,
                                CpvsSlicing slicing = CpvsSlicing::Log);

// Slice of a receiver's quantised depth: the number of s in [1, N-1] with T[s] < depth.
uint32_t cpvsSliceOf(const CpvsSpace& space, uint32_t depth);

// Eq. 1 evaluated in double from a linear depth: k = ceil(N * log(z / near) / log(far / near)). The slice
// is clamp(k - 1, 0, N - 1). For tests only: the bake and the lookup use the thresholds.
int64_t cpvsEquation1(double z, uint32_t resolution, double nearPlane, double farPlane);

enum class CpvsVoxel : uint8_t { Lit = 0, Shadowed = 1, Undefined = 2 };

// The voxelisation derived directly from the depth maps, one voxel at a time (the reference of verify
// and of the exhaustive tests). map.resolution must equal space.resolution.
CpvsVoxel cpvsReferenceVoxel(const CpvsSpace& space, const DualDepthMap& map, uint32_t x, uint32_t y,
                             uint32_t s);

// The same per column: voxels [0, litEnd) lit, [litEnd, shadowBegin) undefined, [shadowBegin, N) shadowed.
struct CpvsColumn {
    uint32_t litEnd = 0, shadowBegin = 0;
};
CpvsColumn cpvsReferenceColumn(const CpvsSpace& space, uint32_t enter, uint32_t exit);

// ---------------------------------------------------------------------------------------------------
// Precompute (section 3.4, 6.1)

struct CpvsPrecompute {
    uint32_t resolution = 0, tiles = 0; // tiles = N / 8 per axis
    // Per tile (row-major, tiles^2): steps [stepFirst[i], stepFirst[i+1]). Step j: from slice
    // stepStart[j] on (until the next step's start) the tile's cells in stepMask[j] (bit x + 8 y) are
    // shadowed. Before the first step all cells are lit. Masks only grow; starts strictly increase, so
    // they are exactly the distinct resolved transition slices t < N of the tile's texels.
    std::vector<uint32_t> stepFirst;
    std::vector<uint32_t> stepStart; // 32 bits: slice N = 65536 and beyond must fit (16 bits would wrap)
    std::vector<uint64_t> stepMask;
    // Min-max hierarchy of the resolved transition slice t (column lit below t, shadowed from t on; t = N
    // if never shadowed). Level k covers (8 << k)^2 texels, (tiles >> k)^2 entries.
    std::vector<std::vector<uint32_t>> minT, maxT;
};

// Resolves undefined voxels by the paper's rules and builds the hierarchy up to footprints of topSize
// texels (a power of two, 8..N).
Result<CpvsPrecompute> cpvsPrecompute(const CpvsSpace& space, const DualDepthMap& map, uint32_t topSize);

// The resolved state the DAG encodes exactly (undefined voxels decided).
bool cpvsResolvedShadowed(const CpvsPrecompute& pre, uint32_t x, uint32_t y, uint32_t s);

// ---------------------------------------------------------------------------------------------------
// Bake

enum class CpvsCompression : uint8_t {
    None,     // output the DAG right after insertion (section 3.2, "size of DAG after insertion")
    BottomUp, // sort and merge level by level from the leaves (section 4.1): the optimal DAG
    TopDown,  // hashes from contents, merged top-down, each match confirmed (section 4.2): the same DAG
    Regions,  // sub-DAGs inserted and sorted per region, merged layer by layer (section 4.3): the same
              // DAG, identical bytes to BottomUp
};

struct CpvsParams {
    uint32_t resolution = 0; // N; the map's resolution must match
    float nearPlane = 0.05f, farPlane = 10.0f;
    CpvsSlicing slicing = CpvsSlicing::Log; // Linear for orthographic (directional) maps
    uint32_t gridLog2 = 4; // the top levels become a 2^g per axis grid of pointers; clamped to log2(N) - 3
    CpvsCompression compression = CpvsCompression::Regions;
    // Regions only: the grid's x, y are split into 2^r per axis blocks of cells (r clamped to gridLog2),
    // each a column through every slice; (2^r)^2 sub-DAGs. Default: one sub-DAG per column of grid cells.
    uint32_t regionLog2 = 4;
    std::function<void(float)> progress; // called with a fraction in [0, 1], monotone; may be empty
    uint32_t hashBits = 64;              // TopDown only; < 64 forces collisions (tests of the confirm)
};

struct CpvsBytes {
    uint64_t header = 0, thresholds = 0, grid = 0, innerNodes = 0, leafMasks = 0, total = 0;
};

struct CpvsStats {
    // compressMs is all compression after insertion; for Regions it is the sub-DAG sorts plus mergeMs, so
    // precompute + insert + compress + layout is the whole bake in every mode.
    double precomputeMs = 0, insertMs = 0, compressMs = 0, layoutMs = 0;
    uint64_t nodesInserted = 0, leavesInserted = 0; // after insertion (culling included)
    uint64_t nodesFinal = 0, leavesFinal = 0;       // after compression
    uint64_t tileSteps = 0;                         // visibility masks over all tiles
    uint64_t hashCollisions = 0;                    // TopDown: equal hashes refuted by the confirm
    std::vector<uint64_t> nodesPerLevel;            // final inner nodes, index 0 = 8^3 nodes
    CpvsBytes bytes;
    // Region build (section 4.3). Other modes: one region, the peaks are the whole insertion.
    double mergeMs = 0;                                 // merging the sub-DAGs (part of compressMs)
    uint32_t regions = 1;                               // sub-DAGs built
    uint64_t regionNodesPeak = 0, regionLeavesPeak = 0; // inserted by the largest region
    uint64_t liveBytesPeak = 0; // most bytes of DAG nodes, leaves and grid entries alive at once
};

struct CpvsBake {
    std::vector<uint32_t> data; // the GPU-uploadable words (header first)
    CpvsStats stats;
};

Result<CpvsBake> bakeCpvs(const DualDepthMap& map, const CpvsParams& params);

// ---------------------------------------------------------------------------------------------------
// Layout and lookup (cpvs_layout.cpp; words relative to the CPVS's base in a larger buffer)

constexpr uint32_t kCpvsMagic = 0x53565043u; // "CPVS"
constexpr uint32_t kCpvsVersion = 1;         // log slicing (eq. 1): spot and point lights, unchanged
constexpr uint32_t kCpvsVersionLinear = 2;   // linear slicing (directional lights); header word 15 = 1
constexpr uint32_t kCpvsHeaderWords = 16;
constexpr uint32_t kCpvsLit = 0, kCpvsShadowed = 1; // grid entries that are not node pointers

// Header word indices.
enum CpvsHeader : uint32_t {
    kCpvsHMagic = 0,
    kCpvsHVersion,
    kCpvsHResolution,
    kCpvsHLog2Resolution,
    kCpvsHGridLog2,
    kCpvsHNearBits,
    kCpvsHFarBits,
    kCpvsHTotalWords,
    kCpvsHThresholds, // offset of T[0..N]
    kCpvsHGrid,       // offset of the (2^g)^3 grid, index x + G (y + G s)
    kCpvsHNodes,      // offset and size of the inner-node region
    kCpvsHNodeWords,
    kCpvsHLeaves, // offset and size of the leaf region (2 words per leaf)
    kCpvsHLeafWords,
    kCpvsHChecksum, // FNV-1a over all words, this one counted as 0
    kCpvsHSlicing,  // CpvsSlicing: 0 in version 1 (was reserved), 1 in version 2
};

uint32_t cpvsChecksum(const uint32_t* data, size_t words);

// Checks header, regions, checksum and every reachable pointer, so that the lookups below stay inside
// [0, totalWords) and terminate. words = how many words are readable from data.
Result<void> validateCpvs(const uint32_t* data, size_t words);

CpvsBytes cpvsBytes(const uint32_t* data); // data must be valid

// The decoder: cpvsSliceOfDepth(data, base, depth), the slice of a quantised depth, and
// cpvsShadowedVoxel(data, base, x, y, s), a voxel's bit (x, y outside [0, N) are lit: outside the light's
// frustum; s is clamped to [0, N-1]). One source text with the GLSL decoder, shaders/static/cpvs_decode.h,
// compiled here with the buffer as an argument.
namespace cpvstwin {
using uint = uint32_t;
inline int bitCount(uint32_t x) {
    return std::popcount(x);
}
#define CPVS_FN inline
#define CPVS_DATA_PARAM const uint32_t *data,
#define CPVS_DATA_ARG data,
#define CPVS_WORD(i) data[i]
#include "shaders/static/cpvs_decode.h"
static_assert(CPVS_H_RESOLUTION == kCpvsHResolution && CPVS_H_LOG2_RESOLUTION == kCpvsHLog2Resolution &&
              CPVS_H_GRID_LOG2 == kCpvsHGridLog2 && CPVS_H_THRESHOLDS == kCpvsHThresholds &&
              CPVS_H_GRID == kCpvsHGrid && CPVS_LIT == kCpvsLit && CPVS_SHADOWED == kCpvsShadowed);
} // namespace cpvstwin
using cpvstwin::cpvsPcfLitLevel;
using cpvstwin::cpvsShadowedVoxel;
using cpvstwin::cpvsSliceOfDepth;
// cpvsPcfLitLevel(data, base, x, y, s, nx, ny, nz, radius, step): the lit taps of a (2 radius + 1)^2 PCF
// kernel (radius 0..4) around the receiver biased along its voxel normal, on the map `step` levels above
// the finest (cpvs_decode.h says what a level voxel answers). The same text as the shader's.
// Normal bias (section 5): the lookup point moves along the voxel-space normal nq (any integer scale,
// e.g. quantised to +-1024) until its largest component is radius + 1 voxels; rounding half away from 0.
void cpvsNormalOffset(const int32_t nq[3], int32_t radius, int32_t out[3]);
// Lit taps of a (2 radius + 1)^2 PCF kernel (radius 0..4) around the biased voxel, in the x, y plane: the
// finest level of cpvsPcfLitLevel.
uint32_t cpvsPcfLitCount(const uint32_t* data, uint32_t base, int32_t x, int32_t y, int32_t s,
                         const int32_t nq[3], int32_t radius);

// Voxel-space direction of a light-view normal (float part, caller side; see cpvs_lookup.glsl):
// light looks down -Z; ndc = the receiver's NDC x, y; tanHalfFov = tan(fov / 2). A linear-sliced
// orthographic map passes ndc 0, tanHalfFov = orthoHalf and logFarOverNear = far - near: u = N (x / h
// + 1) / 2 and w = N (z - near) / (far - near) give du = N dx / (2 h), dw = N dz / (far - near).
void cpvsVoxelNormal(const float nView[3], float ndcX, float ndcY, float tanHalfFov, float logFarOverNear,
                     int32_t out[3]);

// ---------------------------------------------------------------------------------------------------
// Verification and the uncompressed reference (cpvs_reference.cpp)

struct CpvsVerifyReport {
    uint64_t checked = 0, undefined = 0, mismatches = 0;
};
// Every voxel of the baked data against cpvsReferenceColumn of the maps, walking each texel's column
// through the DAG (homogeneous runs are checked as runs). data must have passed validateCpvs.
CpvsVerifyReport verifyCpvs(const uint32_t* data, const DualDepthMap& map);
// The same in pieces, for maps never held whole (a tiled verify): the voxel space the header describes;
// the stored thresholds that differ from it (each a mismatch); and the columns of a w x h block of texels
// at (x0, y0) (enter / exit row-major, w words a row), added to `report`.
Result<CpvsSpace> cpvsSpaceOf(const uint32_t* data);
uint64_t cpvsThresholdMismatches(const uint32_t* data, const CpvsSpace& space);
void verifyCpvsBlock(const uint32_t* data, const CpvsSpace& space, uint32_t x0, uint32_t y0, uint32_t w,
                     uint32_t h, const uint32_t* enter, const uint32_t* exit, CpvsVerifyReport& report);

// A plain sparse voxel octree (no sharing), built by brute force from a voxel function, for small N.
// Child refs: node index into the next finer level (levels[k] holds (8 << k)^3 nodes), or a leaf index.
struct CpvsOctree {
    struct Node {
        uint8_t childMask = 0, shadowMask = 0;
        uint32_t child[8] = {};
    };
    uint32_t resolution = 0;
    std::vector<std::vector<Node>> levels; // levels[k]: nodes of size 8 << k
    std::vector<uint64_t> leaves;          // 4^3 masks, bit x + 4 y + 16 z
    uint8_t rootKind = 0;                  // 0 lit, 1 shadowed, 2 node (index 0 of the top level)
};
CpvsOctree cpvsBuildOctree(uint32_t resolution,
                           const std::function<bool(uint32_t, uint32_t, uint32_t)>& shadowed);

} // namespace ml
