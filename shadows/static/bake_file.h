// The bake file: every static light of one scene bake, one method, one resolution, in one file.
//
// The file is a sequence of little-endian 32-bit words, so the data of each light is word-aligned and
// can be uploaded to an SSBO as is. Layout (word offsets from the start of the file):
//
//   header      [0, H)   H = 16 + ceil(sceneBytes / 4)
//     0 magic 'MLBK'       4 method (StaticMethod)   8 seed                   12 total words, low
//     1 version (1 or 2)   5 resolution              9 scene string bytes     13 total words, high
//     2 flags (bit 0: GPU-rendered maps)          6 record count           10 record table offset=H  14
//     need block words N (version 2; 0 in version 1)  3 header words H  7 scene lights  11 record words (32)
//     15 header checksum
//     16.. scene name or path (UTF-8, no NUL), zero-padded to a whole word
//     then (version 2) the need block, N words (bake --need: resolution from need, need.h):
//       0 entry count E   1 image width   2 image height   3 minimum resolution   4 maximum resolution
//       5 region string bytes   6 camera samples   7 reserved (0)
//       8.. region string (UTF-8, no NUL), zero-padded to a whole word
//       then E entries of 8 words, one per selected light, in increasing light index:
//         0 light   1 resolution (0: not baked)   2 reason (NeedReason) | bit 8: ray budget spent
//         3 camera depth of the deciding receiver (float)   4 camera sample   5 needed resolution (float)
//         6 receiver points in the light's volume   7 of them seen from some camera sample
//   record table [H, H + count * 32), one record per baked light, in increasing data offset:
//     0 scene light index   3..18 view matrix (16 floats, column-major)   22, 23 data offset (lo, hi)
//     1 method              19 fov   20 near   21 far (floats)              24, 25 data words (lo, hi)
//     2 resolution          26 data checksum   27 record checksum   28 cube face
//     29 orthographic half side (float; 0 = perspective, > 0 = a directional light's map, fov 0)
//     30 (version 3, directional) the fitted rectangle's half height orthoHalfY (float), else 0
//     31 (version 3, directional) the fit margin (float, metres), else 0
//   data        [H + count * 32, total): each record's words, back to back, no gaps
//
// Version 3: the file holds a directional record fitted to its box (LightFrustum::
// orthoHalfY, fitMargin: a res x mapRows(res) map, the depth range the box's slab, CPVS sliced
// linearly); the need block is optional there (header word 14 = its words, or 0). Files without a
// directional record keep version 1 or 2, byte for byte as before. A directional record in a version 1
// or 2 file (square map, log-sliced CPVS) is refused with a line saying to re-bake it.
// Version 2 files hold a need block; then the header's resolution is the cap and each record's
// resolution is its light's entry's (at most the cap), every record's light has an entry and every
// entry with a resolution has records. Files without a need block are written as version 1, so that
// builds from before version 2 still read them; this build reads both.
//
// Checksums are word-wise FNV-1a (format_common.h): the header's over words [0, H) and a record's over
// its 32 words, each with its own slot counted as 0; a record's data checksum over its data words.
// The scene description (name, light count, seed) is what `verify` needs to re-create the scene and
// re-render each light's dual depth map.
//
// Loading trusts nothing: sizes, offsets, counts, float ranges, rigid record views (rigidView) and
// checksums are checked, then every record's words go through validateStatic, which walks every
// internal offset. A file readBakeFile accepts can be uploaded and looked up without any read outside
// its buffers, on the CPU or the GPU.
// Writing is deterministic: every word is defined, there are no timestamps.
#pragma once
#include "io/result.h"
#include "shadows/static/static_method.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ml {

namespace bakefmt {
constexpr uint32_t kMagic = stat::fourcc('M', 'L', 'B', 'K');
constexpr uint32_t kVersion = 2;       // with a need block, no directional record
constexpr uint32_t kVersionFixed = 1;  // written when there is no need block (one resolution for all)
constexpr uint32_t kVersionFitted = 3; // the newest: a directional record fitted to its box
// A part of a sharded bake (bake_shard.h) wraps a bake file; the reader names it instead of failing
// with "wrong magic".
constexpr uint32_t kPartMagic = stat::fourcc('M', 'L', 'B', 'P');
constexpr uint32_t kFixedHeaderWords = 16;
constexpr uint32_t kRecordWords = 32;
constexpr uint32_t kMaxSceneBytes = 4096;
constexpr uint32_t kMaxRecords = 65536;
constexpr uint32_t kMaxResolution = 262144; // kMhMaxResolution: SM and CPVS records stop at 16384
enum : uint32_t {
    kHMagic,
    kHVersion,
    kHFlags,
    kHHeaderWords,
    kHMethod,
    kHResolution,
    kHRecordCount,
    kHSceneLights,
    kHSeed,
    kHSceneBytes,
    kHRecordOffset,
    kHRecordWords,
    kHTotalLo,
    kHTotalHi,
    kHNeedWords, // version 2; reserved (0) in version 1
    kHChecksum,
};
enum : uint32_t {
    kRLight = 0,
    kRMethod = 1,
    kRResolution = 2,
    kRView = 3, // 16 words
    kRFov = 19,
    kRNear = 20,
    kRFar = 21,
    kROffsetLo = 22,
    kROffsetHi = 23,
    kRWordsLo = 24,
    kRWordsHi = 25,
    kRDataChecksum = 26,
    kRChecksum = 27,
    kRFace = 28,       // 0 for spots; 0..5 for a point light's cube faces (+X, -X, +Y, -Y, +Z, -Z)
    kROrtho = 29,      // LightFrustum::orthoHalf; 0 in files written before directional bakes
    kROrthoHalfY = 30, // version 3: LightFrustum::orthoHalfY (directional), else 0
    kRFitMargin = 31,  // version 3: LightFrustum::fitMargin (directional), else 0
};
constexpr uint32_t kNeedFixedWords = 8;
constexpr uint32_t kNeedEntryWords = 8;
constexpr uint32_t kMaxRegionBytes = 1024;
} // namespace bakefmt

// How to re-create the baked scene: loadScene(scene, lights, seed).
struct SceneSpec {
    std::string scene = "night-city";
    uint32_t lights = 256;
    uint32_t seed = 1;
};

struct BakeRecord {
    uint32_t light = 0; // index into the scene's lights
    uint32_t face = 0;  // point lights: cube face 0..5
    StaticMethod method = StaticMethod::None;
    uint32_t resolution = 0;
    LightFrustum frustum;
    std::vector<uint32_t> data; // encodeStatic's words
};

// Why a light got its resolution (resolution from need, need.h).
enum class NeedReason : uint32_t {
    Footprint = 1, // one texel per pixel at the receiver seen largest: that, rounded up to a power of two
    Capped = 2,    // needed more than the maximum
    Floor = 3,     // needed less than the minimum
    NotSeen = 4,   // no receiver in view of any camera sample: the minimum
    NoCaster = 5,  // no triangle in the light's volume: an empty map, not baked (no record)
};
struct LightNeed {
    uint32_t light = 0;
    uint32_t resolution = 0; // 0: not baked
    NeedReason reason = NeedReason::NoCaster;
    float distance = 0.0f;   // camera depth of the receiver that decided
    uint32_t sample = 0;     // the camera sample it was seen from
    float needed = 0.0f;     // resolution for one texel per pixel there, before rounding and clamping
    uint32_t receivers = 0;  // receiver points in the light's volume
    uint32_t seen = 0;       // of them in view of some camera sample
    uint32_t rays = 0;       // occlusion rays cast (not stored in the file)
    bool raysCapped = false; // ray budget spent: the decision was taken without an occlusion test
};
struct BakeNeed {
    std::string region;              // what the camera region was ("path:drive, 120 samples over 60 s")
    uint32_t width = 0, height = 0;  // the image the need was computed for
    uint32_t minRes = 0, maxRes = 0; // the clamp
    uint32_t samples = 0;            // camera samples
    std::vector<LightNeed> lights;   // every selected light, increasing index
};

// Which renderer made the dual depth maps: verify must re-render with the same one (the Vulkan and CPU
// renderers agree on coverage but round depth differently).
enum class BakeRenderer : uint32_t { Cpu = 0, Gpu = 1 };
constexpr uint32_t kFlagGpuRenderer = 1u;

struct BakeFile {
    SceneSpec scene;
    BakeRenderer renderer = BakeRenderer::Cpu;
    StaticMethod method = StaticMethod::None;
    uint32_t resolution = 0; // with a need block: the largest a record may have (the cap)
    std::vector<BakeRecord> records;
    bool hasNeed = false; // version 2: resolution from need
    BakeNeed need;
};
inline uint32_t bakeFileVersion(const BakeFile& f) {
    for (const BakeRecord& r : f.records)
        if (r.frustum.orthographic()) return bakefmt::kVersionFitted;
    return f.hasNeed ? bakefmt::kVersion : bakefmt::kVersionFixed;
}

// What a directional record spends where (inspect shows it): fractions 0..1.
struct DirectionalFit {
    uint32_t width = 0, rows = 0;     // the map's texels: width x rows (the rest of the grid is outside)
    double extentX = 0, extentY = 0;  // the box's light-space rectangle, metres
    double slabNear = 0, slabFar = 0; // the box's slab along the light, light-space depth
    double texelsInBox = 0;           // of the width x rows texels, centres inside the rectangle
    double depthSlicesInBox = 0;      // of the N depth slices (CPVS: its thresholds; depth methods: N
                                      // equal parts of [near, far]), those inside the slab
    // Of the N slices, the share between the nearest and the deepest stored shadow boundary (depth
    // methods: the stored depth; CPVS: per column the slice before the first shadowed one). For open
    // casters that is their depth; inside closed ones a lossless encoder may place it anywhere between
    // entry and exit, so `verify` reports the casters' own span from the re-rendered map.
    double casterSlices = 0;
};
// Fails for a record that is not a fitted directional one. Reads every texel (or column) once.
Result<DirectionalFit> directionalFit(const BakeRecord& record);

// The exact file contents (checks the same invariants the reader does, except validateStatic).
Result<std::vector<uint32_t>> serializeBakeFile(const BakeFile& file);
// Parses and validates the words of a whole file; `name` prefixes error messages ("<name>: record 3: ...").
Result<BakeFile> parseBakeFile(const std::string& name, const uint32_t* words, size_t count);

Result<void> writeBakeFile(const std::string& path, const BakeFile& file);
Result<BakeFile> readBakeFile(const std::string& path);

// Bytes per part. `headers` holds the file header, the record table and each record's format header;
// the parts add up to the file size.
struct BakeBytes {
    uint64_t headers = 0, skipList = 0, bounds = 0, nodes = 0, treelets = 0, values = 0, factors = 0;
    uint64_t total() const { return headers + skipList + bounds + nodes + treelets + values + factors; }
};
struct BakeRecordBytes {
    uint32_t light = 0;
    stat::ByteBreakdown parts; // of the record's data
    uint64_t recordBytes = 0;  // table entry
};
BakeBytes bakeFileBytes(const BakeFile& file, std::vector<BakeRecordBytes>* perRecord = nullptr);

} // namespace ml
