// SM: the uncompressed baseline, one 32-bit depth per texel (the "32-bit map" all ratios refer to).
//
// Each texel stores the midpoint of its [enter, exit] interval (the midpoint shadow map of Woo 1992:
// inside closed objects, away from both surfaces); empty texels store kDepthEmpty.
// Layout (words): header[6] = magic 'SM01' | version 1 | resolution | total words | checksum | 0,
// then resolution^2 values, row-major, row 0 at NDC y = -1.
#pragma once
#include "io/result.h"
#include "shadows/static/dual_depth.h"
#include "shadows/static/format_common.h"

#include <string>
#include <vector>

namespace ml {

namespace smfmt {
constexpr uint32_t kMagic = stat::fourcc('S', 'M', '0', '1');
constexpr uint32_t kHeaderWords = 6;
enum : uint32_t { kMagicWord, kVersion, kResolution, kTotalWords, kChecksum, kReserved };
} // namespace smfmt

inline std::vector<uint32_t> encodeSM(const DualDepthMap& map) {
    const size_t texels = size_t(map.resolution) * map.resolution;
    std::vector<uint32_t> out(smfmt::kHeaderWords + texels, 0u);
    out[smfmt::kMagicWord] = smfmt::kMagic, out[smfmt::kVersion] = 1,
    out[smfmt::kResolution] = map.resolution;
    out[smfmt::kTotalWords] = uint32_t(out.size());
    for (size_t i = 0; i < texels; ++i)
        out[smfmt::kHeaderWords + i] = stat::midpoint(map.enter[i], std::max(map.enter[i], map.exit[i]));
    out[smfmt::kChecksum] = stat::checksumWords(out.data(), out.size(), smfmt::kChecksum);
    return out;
}

inline Result<void> validateSM(const uint32_t* data, size_t size) {
    if (!data || size < smfmt::kHeaderWords) return fail("SM: buffer shorter than its header");
    if (data[smfmt::kMagicWord] != smfmt::kMagic || data[smfmt::kVersion] != 1)
        return fail("SM: wrong magic or version");
    uint64_t res = data[smfmt::kResolution];
    if (data[smfmt::kTotalWords] != size || smfmt::kHeaderWords + res * res != size)
        return fail("SM: size " + std::to_string(size) + " does not match resolution " + std::to_string(res));
    if (data[smfmt::kChecksum] != stat::checksumWords(data, size, smfmt::kChecksum))
        return fail("SM: checksum mismatch");
    if (data[smfmt::kReserved] != 0) return fail("SM: reserved header word is not 0");
    return {};
}

inline stat::ByteBreakdown breakdownSM(const uint32_t* data, size_t size) {
    stat::ByteBreakdown b;
    b.header = smfmt::kHeaderWords * 4u;
    b.values = size >= smfmt::kHeaderWords ? (uint64_t(size) - smfmt::kHeaderWords) * 4u : 0u;
    (void)data;
    return b;
}

inline uint32_t smLookup(const uint32_t* data, uint32_t base, uint32_t x, uint32_t y) {
    return data[base + smfmt::kHeaderWords + y * data[base + smfmt::kResolution] + x];
}

} // namespace ml
