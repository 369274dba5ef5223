// The bake file: every static light of one scene bake, one method, one resolution, in one file.
//
// The file is a sequence of little-endian 32-bit words, so the data of each light is word-aligned and
// can be uploaded to an SSBO as is. Layout (word offsets from the start of the file):
//
//   header      [0, H)   H = 16 + ceil(sceneBytes / 4)
//     0 magic 'MLBK'       4 method (StaticMethod)   8 seed                   12 total words, low
//     1 version (1)        5 resolution              9 scene string bytes     13 total words, high
//     2 flags (bit 0: GPU-rendered maps)          6 record count           10 record table offset=H  14
//     reserved (0) 3 header words H     7 scene lights           11 record words (32)      15 header checksum
//     16.. scene name or path (UTF-8, no NUL), zero-padded to a whole word
//   record table [H, H + count * 32), one record per baked light, in increasing data offset:
//     0 scene light index   3..18 view matrix (16 floats, column-major)   22, 23 data offset (lo, hi)
//     1 method              19 fov   20 near   21 far (floats)              24, 25 data words (lo, hi)
//     2 resolution          26 data checksum   27 record checksum   28 cube face
//     29 orthographic half side (float; 0 = perspective, > 0 = a directional light's map, fov 0)
//     30..31 reserved (0)
//   data        [H + count * 32, total): each record's words, back to back, no gaps
//
// Checksums are word-wise FNV-1a (format_common.h): the header's over words [0, H) and a record's over
// its 32 words, each with its own slot counted as 0; a record's data checksum over its data words.
// The scene description (name, light count, seed) is what `verify` needs to re-create the scene and
// re-render each light's dual depth map.
//
// Loading trusts nothing: sizes, offsets, counts, float ranges and checksums are checked, then every
// record's words go through validateStatic, which walks every internal offset. A file readBakeFile
// accepts can be uploaded and looked up without any read outside its buffers, on the CPU or the GPU.
// Writing is deterministic: every word is defined, there are no timestamps.
#pragma once
#include "engine/result.h"
#include "shadows/static/static_method.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ml {

namespace bakefmt {
constexpr uint32_t kMagic = stat::fourcc('M', 'L', 'B', 'K');
constexpr uint32_t kVersion = 1;
// A part of a sharded bake (bake_shard.h) wraps a bake file; the reader names it instead of failing
// with "wrong magic".
constexpr uint32_t kPartMagic = stat::fourcc('M', 'L', 'B', 'P');
constexpr uint32_t kFixedHeaderWords = 16;
constexpr uint32_t kRecordWords = 32;
constexpr uint32_t kMaxSceneBytes = 4096;
constexpr uint32_t kMaxRecords = 65536;
constexpr uint32_t kMaxResolution = 65536;
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
    kHReserved,
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
    kRFace = 28,  // 0 for spots; 0..5 for a point light's cube faces (+X, -X, +Y, -Y, +Z, -Z)
    kROrtho = 29, // LightFrustum::orthoHalf; 0 in files written before directional bakes
};
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

// Which renderer made the dual depth maps: verify must re-render with the same one (the Vulkan and CPU
// renderers agree on coverage but round depth differently).
enum class BakeRenderer : uint32_t { Cpu = 0, Gpu = 1 };
constexpr uint32_t kFlagGpuRenderer = 1u;

struct BakeFile {
    SceneSpec scene;
    BakeRenderer renderer = BakeRenderer::Cpu;
    StaticMethod method = StaticMethod::None;
    uint32_t resolution = 0;
    std::vector<BakeRecord> records;
};

// The exact file contents (checks the same invariants the reader does, except validateStatic).
Result<std::vector<uint32_t>> serializeBakeFile(const BakeFile& file);
// Parses and validates the words of a whole file; `name` prefixes error messages ("<name>: record 3: ...").
Result<BakeFile> parseBakeFile(const std::string& name, const uint32_t* words, size_t count);

Result<void> writeBakeFile(const std::string& path, const BakeFile& file);
Result<BakeFile> readBakeFile(const std::string& path);

// Bytes per part. `headers` holds the file header, the record table and each record's format header;
// the parts add up to the file size.
struct BakeBytes {
    uint64_t headers = 0, skipList = 0, nodes = 0, treelets = 0, values = 0, factors = 0;
    uint64_t total() const { return headers + skipList + nodes + treelets + values + factors; }
};
struct BakeRecordBytes {
    uint32_t light = 0;
    stat::ByteBreakdown parts; // of the record's data
    uint64_t recordBytes = 0;  // table entry
};
BakeBytes bakeFileBytes(const BakeFile& file, std::vector<BakeRecordBytes>* perRecord = nullptr);

} // namespace ml
