// MH and MMH records with far child groups (version 2, shadows/static/mh.h): the layout a node array past
// 2^24 words needs, sent through small maps by lowering the near-offset limit. Every texel decodes to
// the version 1 record's value; the header fields version 2 adds are checked on forged records.
#include "static_test_util.h"

namespace ml::stest {
namespace {

std::vector<uint32_t> forge(std::vector<uint32_t> d, uint32_t word, uint32_t value) {
    d[word] = value;
    d[mhfmt::kChecksum] = stat::checksumWords(d.data(), d.size(), mhfmt::kChecksum);
    return d;
}

// Far groups reached from every header whose own offset is larger than maxNear.
uint64_t farHeaders(const std::vector<uint32_t>& d) {
    uint64_t n = 0;
    std::vector<uint32_t> stack{d[mhfmt::kNodeOffset] + 1u};
    std::vector<uint8_t> seen(d.size(), 0);
    while (!stack.empty()) {
        uint32_t hp = stack.back();
        stack.pop_back();
        uint32_t hdr = d[hp], off = hdr >> 8;
        bool far = (off & mhfmt::kFarBit) != 0;
        n += far;
        uint32_t q = far ? (off & (mhfmt::kFarBit - 1u)) << d[mhfmt::kFarShift] : hp + off;
        for (uint32_t c = 0; c < 4; ++c) {
            uint32_t t = (hdr >> (2 * c)) & 3u;
            if (t >= 2 && !seen[q + (t == 2)]) seen[q + (t == 2)] = 1, stack.push_back(q + (t == 2));
            q += (0x64u >> (2 * t)) & 3u;
        }
    }
    return n;
}

TEST(MhFarGroups, DecodeAsVersionOneAtEveryTexel) {
    for (const DualDepthMap& m : {syntheticMap(512, 5), syntheticMap(300, 6)}) {
        auto tree = buildMhTree(m);
        ASSERT_TRUE(tree.ok()) << tree.error();
        for (uint32_t maxNear : {1u, 16u, 300u}) {
            for (uint32_t shift : {1u, 3u, 9u}) {
                SCOPED_TRACE("maxNear " + std::to_string(maxNear) + " shift " + std::to_string(shift));
                auto mh1 = encodeMH(*tree), mh2 = encodeMH(*tree, {maxNear, shift});
                MmhOptions o;
                o.layout = {maxNear, shift};
                auto mmh1 = encodeMMH(*tree), mmh2 = encodeMMH(*tree, o);
                ASSERT_TRUE(mh1 && mh2 && mmh1 && mmh2);
                EXPECT_EQ((*mh1)[mhfmt::kVersion], 1u);
                EXPECT_EQ((*mmh1)[mhfmt::kVersion], 1u);
                for (const auto* d : {&*mh2, &*mmh2}) {
                    EXPECT_EQ((*d)[mhfmt::kVersion], 2u);
                    EXPECT_EQ((*d)[mhfmt::kNodeOffset], mhfmt::kHeaderWordsFar);
                    EXPECT_EQ((*d)[mhfmt::kFarShift], shift);
                    EXPECT_GT(farHeaders(*d), 0u);
                    if (shift > 1) {
                        EXPECT_GT((*d)[mhfmt::kPaddingWords], 0u);
                    }
                }
                ASSERT_TRUE(validateMH(mh2->data(), mh2->size()).ok());
                ASSERT_TRUE(validateMMH(mmh2->data(), mmh2->size()).ok());
                uint64_t differ = 0;
                for (uint32_t y = 0; y < m.resolution; ++y)
                    for (uint32_t x = 0; x < m.resolution; ++x)
                        differ += (mhLookup(mh2->data(), x, y) != mhLookup(mh1->data(), x, y)) +
                                  (mmhLookup(mmh2->data(), x, y) != mmhLookup(mmh1->data(), x, y));
                EXPECT_EQ(differ, 0u);
            }
        }
    }
}

TEST(MhFarGroups, ValidateRefusesForgedHeaders) {
    DualDepthMap m = syntheticMap(256, 8);
    auto good = encodeMH(m, {16, 3});
    ASSERT_TRUE(good.ok());
    ASSERT_TRUE(validateMH(good->data(), good->size()).ok());
    const std::vector<uint32_t>& g = *good;
    struct Case {
        uint32_t word, value;
        const char* what;
    };
    const Case cases[] = {
        {mhfmt::kFarShift, 0u, "far shift 0"},
        {mhfmt::kFarShift, mhfmt::kMaxFarShift + 1u, "far shift past 9"},
        {mhfmt::kPaddingWords, g[mhfmt::kPaddingWords] + 1u, "padding count"},
        {mhfmt::kVersion, 3u, "version 3"},
        {mhfmt::kVersion, 1u, "version 1 with a 14-word header"},
        {mhfmt::kNodeOffset, mhfmt::kHeaderWords, "node offset 12"},
    };
    for (const Case& c : cases)
        EXPECT_FALSE(validateMH(forge(g, c.word, c.value).data(), g.size()).ok()) << c.what;
    // The root's header pointed far: before itself, at the header, and past the end.
    const uint32_t hp = g[mhfmt::kNodeOffset] + 1u, flags = g[hp] & 0xFFu;
    for (uint64_t pos : {uint64_t(0), uint64_t(hp), uint64_t(g.size()) + 8u}) {
        uint32_t field = mhfmt::kFarBit | uint32_t(pos >> g[mhfmt::kFarShift]);
        EXPECT_FALSE(validateMH(forge(g, hp, flags | field << 8).data(), g.size()).ok()) << "far to " << pos;
    }
}

} // namespace
} // namespace ml::stest
