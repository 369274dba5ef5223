// SM: the uncompressed baseline, one 32-bit depth per texel (the "32-bit map" all ratios refer to).
//
// Each texel stores the midpoint of its [enter, exit] interval (the midpoint shadow map of Woo 1992:
// inside closed objects, away from both surfaces); empty texels store kDepthEmpty.
// Layout (words): header[6] = magic 'SM01' | version | resolution | total words | checksum | rows,
// then resolution x rows values, row-major, row 0 at NDC y = -1. Version 1: square, the rows word 0 and
// resolution^2 values (spot and point maps, unchanged). Version 2: a directional map fitted to its box
// (DualDepthMap::rows), rows in 1..resolution-1; texels in rows >= rows are outside the light
// and read as kDepthEmpty (lit).
#pragma once
#include "io/result.h"
#include "shadows/static/dual_depth.h"
#include "shadows/static/format_common.h"

#include <algorithm>
#include <string>
#include <vector>

namespace ml {

namespace smfmt {
constexpr uint32_t kMagic = stat::fourcc('S', 'M', '0', '1');
constexpr uint32_t kHeaderWords = 6;
enum : uint32_t { kMagicWord, kVersion, kResolution, kTotalWords, kChecksum, kRows, kReserved = kRows };
} // namespace smfmt

// A texel's stored value: the midpoint of [enter, max(enter, exit)] (kDepthEmpty for an empty texel).
inline uint32_t smValue(uint32_t enter, uint32_t exit) {
    return stat::midpoint(enter, std::max(enter, exit));
}

// Rows an SM record of this map stores: `rows` (DualDepthMap::rows) when 1..resolution-1, else all.
inline uint32_t smStoredRows(uint32_t resolution, uint32_t rows) {
    return rows != 0 && rows < resolution ? rows : resolution;
}

// The words of an SM record of resolution x smStoredRows(resolution, rows) values: the header filled,
// values 0 and no checksum yet. encodeSM fills the values from a whole map, the tiled bake
// (bake/bake_tiled.cpp) tile by tile; smSeal then writes the checksum.
inline std::vector<uint32_t> smBlankWords(uint32_t resolution, uint32_t rows) {
    const uint32_t stored = smStoredRows(resolution, rows);
    std::vector<uint32_t> out(smfmt::kHeaderWords + size_t(resolution) * stored, 0u);
    out[smfmt::kMagicWord] = smfmt::kMagic, out[smfmt::kVersion] = stored < resolution ? 2u : 1u,
    out[smfmt::kResolution] = resolution;
    out[smfmt::kRows] = stored < resolution ? stored : 0u;
    out[smfmt::kTotalWords] = uint32_t(out.size());
    return out;
}

inline void smSeal(std::vector<uint32_t>& out) {
    out[smfmt::kChecksum] = stat::checksumWords(out.data(), out.size(), smfmt::kChecksum);
}

inline std::vector<uint32_t> encodeSM(const DualDepthMap& map) {
    std::vector<uint32_t> out = smBlankWords(map.resolution, map.rows);
    const size_t texels = out.size() - smfmt::kHeaderWords;
    for (size_t i = 0; i < texels; ++i) out[smfmt::kHeaderWords + i] = smValue(map.enter[i], map.exit[i]);
    smSeal(out);
    return out;
}

// Rows stored: resolution (version 1) or the rows word (version 2).
inline uint32_t smRows(const uint32_t* data, uint32_t base) {
    return data[base + smfmt::kVersion] == 2u ? data[base + smfmt::kRows] : data[base + smfmt::kResolution];
}

inline Result<void> validateSM(const uint32_t* data, size_t size) {
    if (!data || size < smfmt::kHeaderWords) return fail("SM: buffer shorter than its header");
    const uint32_t version = data[smfmt::kVersion];
    if (data[smfmt::kMagicWord] != smfmt::kMagic || (version != 1 && version != 2))
        return fail("SM: wrong magic or version");
    uint64_t res = data[smfmt::kResolution];
    if (version == 1 && data[smfmt::kRows] != 0)
        return fail("SM: reserved (rows) header word is not 0 in version 1");
    if (version == 2 && (data[smfmt::kRows] == 0 || data[smfmt::kRows] >= res))
        return fail("SM: version 2 rows " + std::to_string(data[smfmt::kRows]) + " not in 1.." +
                    std::to_string(res > 0 ? res - 1 : 0));
    const uint64_t rows = version == 2 ? data[smfmt::kRows] : res;
    if (data[smfmt::kTotalWords] != size || smfmt::kHeaderWords + res * rows != size)
        return fail("SM: size " + std::to_string(size) + " does not match resolution " + std::to_string(res) +
                    " x " + std::to_string(rows) + " rows");
    if (data[smfmt::kChecksum] != stat::checksumWords(data, size, smfmt::kChecksum))
        return fail("SM: checksum mismatch");
    return {};
}

inline stat::ByteBreakdown breakdownSM(const uint32_t* data, size_t size) {
    stat::ByteBreakdown b;
    b.header = smfmt::kHeaderWords * 4u;
    b.values = size >= smfmt::kHeaderWords ? (uint64_t(size) - smfmt::kHeaderWords) * 4u : 0u;
    (void)data;
    return b;
}

// The shader reads the same words in staticDepthAt (shaders/static/static_pcf.h).
inline uint32_t smLookup(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y) {
    if (y >= smRows(data, base)) return kDepthEmpty; // outside a fitted directional light's rows
    return data[base + smfmt::kHeaderWords + y * data[base + smfmt::kResolution] + x];
}

} // namespace ml
