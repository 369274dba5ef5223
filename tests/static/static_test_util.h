// Helpers for the static shadow tests: synthetic dual depth maps, the codec table (encode, validate,
// lookup per format) and the exhaustive losslessness check.
#pragma once
#include "shadows/static/dagmh.h"
#include "shadows/static/mh.h"
#include "shadows/static/mmh.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/sm.h"

#include <gtest/gtest.h>

#include "tests/common/shared_scenes.h"

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace ml::stest {

inline std::string sharedScene(const char* name) {
    return test::sharedScenePath(name);
}

inline DualDepthMap emptyMap(uint32_t res) {
    DualDepthMap m;
    m.resolution = res;
    m.enter.assign(size_t(res) * res, kDepthEmpty);
    m.exit.assign(size_t(res) * res, kDepthEmpty);
    return m;
}

inline void setTexel(DualDepthMap& m, uint32_t x, uint32_t y, uint32_t enter, uint32_t exit) {
    m.enter[size_t(y) * m.resolution + x] = enter;
    m.exit[size_t(y) * m.resolution + x] = exit;
}

// Random axis-aligned boxes (closed: thick intervals), sloped planes (open: exit = enter), per-texel
// noise regions (open, values spread over the whole 32-bit range: forces raw 32-bit DAG-MH chunks),
// empty background.
inline DualDepthMap syntheticMap(uint32_t res, uint32_t seed, bool noise = true) {
    std::mt19937 rng(seed);
    DualDepthMap m = emptyMap(res);
    auto uni = [&](uint32_t a, uint32_t b) { return std::uniform_int_distribution<uint32_t>(a, b)(rng); };
    // A ground slope over the lower half.
    for (uint32_t y = 0; y < res / 2; ++y)
        for (uint32_t x = 0; x < res; ++x)
            setTexel(m, x, y, 0x80000000u + x * 4001u + y * 70001u, 0x80000000u + x * 4001u + y * 70001u);
    for (int b = 0; b < 40; ++b) {
        uint32_t x0 = uni(0, res - 1), y0 = uni(0, res - 1), w = uni(1, res / 6 + 1), h = uni(1, res / 6 + 1);
        uint32_t d = uni(0x10000000u, 0x70000000u), thick = uni(0, 0x08000000u);
        int32_t sx = int32_t(uni(0, 20000)) - 10000, sy = int32_t(uni(0, 20000)) - 10000;
        for (uint32_t y = y0; y < std::min(res, y0 + h); ++y)
            for (uint32_t x = x0; x < std::min(res, x0 + w); ++x) {
                uint32_t e = uint32_t(int64_t(d) + int64_t(sx) * (x - x0) + int64_t(sy) * (y - y0));
                setTexel(m, x, y, e, e + thick);
            }
    }
    if (noise) {
        uint32_t x0 = uni(0, res / 2), y0 = uni(0, res / 2);
        for (uint32_t y = y0; y < std::min(res, y0 + res / 8 + 3); ++y)
            for (uint32_t x = x0; x < std::min(res, x0 + res / 8 + 3); ++x) {
                uint32_t e = uni(0, 0xFFFFFFFEu);
                setTexel(m, x, y, e, e);
            }
    }
    return m;
}

struct Codec {
    std::string name;
    std::function<Result<std::vector<uint32_t>>(const DualDepthMap&)> encode;
    std::function<Result<void>(const uint32_t*, size_t)> validate;
    std::function<uint32_t(const uint32_t*, uint32_t, uint32_t)> lookup;
    std::function<stat::ByteBreakdown(const uint32_t*, size_t)> breakdown;
};

inline std::vector<Codec> codecs() {
    return {
        {"MH", [](const DualDepthMap& m) { return encodeMH(m); }, validateMH,
         [](const uint32_t* d, uint32_t x, uint32_t y) { return mhLookup(d, x, y); }, breakdownMH},
        {"MMH", [](const DualDepthMap& m) { return encodeMMH(m); }, validateMMH,
         [](const uint32_t* d, uint32_t x, uint32_t y) { return mmhLookup(d, x, y); }, breakdownMMH},
        {"DAG-MH", [](const DualDepthMap& m) { return encodeDAGMH(m); }, validateDAGMH,
         [](const uint32_t* d, uint32_t x, uint32_t y) { return dagmhLookup(d, x, y); }, breakdownDAGMH},
        // MH and MMH with far child groups (version 2, mh.h) on maps of test size: every offset past 16
        // words goes far, at shifts 2 and 5, so most groups are aligned and padded.
        {"MH far",
         [](const DualDepthMap& m) {
             return encodeMH(m, {16, 2});
         },
         validateMH, [](const uint32_t* d, uint32_t x, uint32_t y) { return mhLookup(d, x, y); },
         breakdownMH},
        {"MMH far",
         [](const DualDepthMap& m) {
             MmhOptions o;
             o.layout = {16, 5};
             return encodeMMH(m, o);
         },
         validateMMH, [](const uint32_t* d, uint32_t x, uint32_t y) { return mmhLookup(d, x, y); },
         breakdownMMH},
    };
}

// Every texel: empty decodes to exactly kDepthEmpty, otherwise enter <= value <= exit.
// Returns the number of failing texels (and reports the first few).
inline uint64_t countLossy(const DualDepthMap& m, const std::vector<uint32_t>& data, const Codec& codec) {
    uint64_t bad = 0;
    for (uint32_t y = 0; y < m.resolution; ++y)
        for (uint32_t x = 0; x < m.resolution; ++x) {
            size_t i = size_t(y) * m.resolution + x;
            uint32_t e = m.enter[i], f = std::max(m.enter[i], m.exit[i]);
            uint32_t v = codec.lookup(data.data(), x, y);
            bool ok = e == kDepthEmpty ? v == kDepthEmpty : (e <= v && v <= f);
            if (!ok && ++bad <= 5)
                ADD_FAILURE() << codec.name << " texel (" << x << "," << y << ") decodes " << v
                              << " outside [" << e << ", " << f << "]";
        }
    return bad;
}

// DAG-MH's value bounds, every texel: its bounds cell's word holds its value, and the bounds test never
// calls a tap lit that is shadowed or the reverse (depths at, around and far from the value). Every
// cell inside the map is tight: its bounds are its texels' smallest and largest value (rounded to 16
// bits), so the walk that computes them sees exactly the lookup's values. Returns the failing texels.
inline uint64_t countDagmhBoundsViolations(const DualDepthMap& m, const std::vector<uint32_t>& data) {
    const uint32_t* d = data.data();
    const uint32_t L = d[dagfmt::kLevels], S = dagfmt::skipLevel(d), B = dagfmt::boundsLevel(d), sh = L - B;
    const uint32_t* bounds = d + d[dagfmt::kSkipOffset] + (dagfmt::kSkipWords << (2 * S));
    std::vector<uint32_t> lo(size_t(1) << (2 * B), 0xFFFFFFFFu), hi(size_t(1) << (2 * B), 0u);
    const DagmhHeader h = dagmhHeader(d, 0);
    uint64_t bad = 0;
    for (uint32_t y = 0; y < m.resolution; ++y)
        for (uint32_t x = 0; x < m.resolution; ++x) {
            const uint32_t v = dagmhLookup(d, x, y), cell = ((y >> sh) << B) + (x >> sh);
            lo[cell] = std::min(lo[cell], v), hi[cell] = std::max(hi[cell], v);
            const uint32_t w = bounds[cell];
            bool ok = (w << 16) <= v && v <= (w | 0xFFFFu);
            for (uint32_t depth : {v, v + 1u, v - 1u, 0u, 0xFFFFFFFFu, w << 16, (w << 16) + 1u, w | 0xFFFFu,
                                   (w | 0xFFFFu) + 1u}) {
                const uint32_t k = dagmhBoundsClass(d, h, x, y, x, y, depth);
                ok = ok && (k == 0u || (k == 1u) == (depth <= v));
            }
            if (!ok && ++bad <= 5)
                ADD_FAILURE() << "DAG-MH texel (" << x << "," << y << ") value " << v << " vs bounds word "
                              << w;
        }
    for (uint32_t Y = 0; Y < (1u << B); ++Y)
        for (uint32_t X = 0; X < (1u << B); ++X) {
            if (((X + 1) << sh) > m.resolution || ((Y + 1) << sh) > m.resolution) continue; // padded cells
            const uint32_t cell = (Y << B) + X;
            if (bounds[cell] != dagfmt::packBounds(lo[cell], hi[cell]) && ++bad <= 5)
                ADD_FAILURE() << "DAG-MH bounds cell (" << X << "," << Y << ") bounds word " << bounds[cell]
                              << " is not its texels' " << dagfmt::packBounds(lo[cell], hi[cell]);
        }
    return bad;
}

// Encodes, validates and checks every texel; returns the encoded buffer.
inline std::vector<uint32_t> encodeChecked(const DualDepthMap& m, const Codec& codec) {
    auto enc = codec.encode(m);
    if (!enc) {
        ADD_FAILURE() << codec.name << " encode failed: " << enc.error();
        return {};
    }
    auto v = codec.validate(enc->data(), enc->size());
    EXPECT_TRUE(v.ok()) << codec.name << " validate: " << v.error();
    if (!v) return {};
    EXPECT_EQ(countLossy(m, *enc, codec), 0u) << codec.name;
    if (codec.name == "DAG-MH") {
        EXPECT_EQ(countDagmhBoundsViolations(m, *enc), 0u);
    }
    return *enc;
}

} // namespace ml::stest
