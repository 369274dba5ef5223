// Exhaustive losslessness of MH, MMH and DAG-MH on synthetic dual depth maps, encoder edge cases and
// determinism. Every texel of every map is decoded and checked against its interval.
#include "static_test_util.h"

namespace ml::stest {
namespace {

void checkAll(const DualDepthMap& m) {
    for (const Codec& codec : codecs()) {
        SCOPED_TRACE(codec.name);
        encodeChecked(m, codec);
    }
}

TEST(StaticCodec, ConstantMap) {
    DualDepthMap m = emptyMap(256);
    std::fill(m.enter.begin(), m.enter.end(), 123456789u);
    std::fill(m.exit.begin(), m.exit.end(), 123456789u);
    checkAll(m);
    // A constant map is a single root leaf in MH/MMH.
    auto mh = encodeMH(m);
    ASSERT_TRUE(mh.ok());
    EXPECT_EQ(mh->size(), mhfmt::kHeaderWords + 1u);
}

TEST(StaticCodec, AllEmpty) {
    DualDepthMap m = emptyMap(512);
    checkAll(m);
}

TEST(StaticCodec, OneByOneAndTiny) {
    for (uint32_t res : {1u, 2u, 3u, 5u}) {
        DualDepthMap m = syntheticMap(res, res, false);
        checkAll(m);
    }
}

TEST(StaticCodec, SingleTexelIslands) {
    // Isolated texels on an empty background and on a constant floor, including the corners.
    for (bool floor : {false, true}) {
        DualDepthMap m = emptyMap(512);
        if (floor)
            std::fill(m.enter.begin(), m.enter.end(), 0x40000000u),
                std::fill(m.exit.begin(), m.exit.end(), 0x40000000u);
        std::mt19937 rng(7);
        for (int i = 0; i < 300; ++i) {
            uint32_t x = rng() % 512, y = rng() % 512, d = rng() % 0xFFFFFFF0u;
            setTexel(m, x, y, d, d + (i % 3 == 0 ? 1000u : 0u));
        }
        setTexel(m, 0, 0, 5, 5), setTexel(m, 511, 511, 7, 7), setTexel(m, 0, 511, 0, 0),
            setTexel(m, 511, 0, 0xFFFFFFFEu, 0xFFFFFFFEu);
        checkAll(m);
    }
}

TEST(StaticCodec, RandomBoxesSlopesNoise) {
    for (uint32_t res : {256u, 512u, 1024u}) {
        SCOPED_TRACE(res);
        checkAll(syntheticMap(res, 100 + res));
    }
}

TEST(StaticCodec, NonPowerOfTwo) {
    for (uint32_t res : {300u, 777u}) {
        SCOPED_TRACE(res);
        checkAll(syntheticMap(res, res));
    }
}

TEST(StaticCodec, NoiseForcesRawDagMhChunks) {
    DualDepthMap m = emptyMap(256);
    std::mt19937 rng(3);
    for (size_t i = 0; i < m.enter.size(); ++i) m.enter[i] = m.exit[i] = rng() % 0xFFFFFFFFu;
    auto tree = buildMhTree(m);
    ASSERT_TRUE(tree.ok());
    DagMhStats st;
    auto enc = encodeDAGMH(*tree, &st);
    ASSERT_TRUE(enc.ok()) << enc.error();
    EXPECT_GT(st.rawChunks, 0u);
    checkAll(m);
}

// The skip level follows the structure's size: a dense map starts its lookups deeper than the old rule
// clamp(L - 7, 0, 6) (here L = 8: 1) within an eighth of the other sections, an empty map keeps a short
// list; both decode every texel exactly (encodeChecked in checkAll).
TEST(StaticCodec, SkipLevelFollowsTheBudget) {
    DualDepthMap noise = emptyMap(256);
    std::mt19937 rng(5);
    for (size_t i = 0; i < noise.enter.size(); ++i) noise.enter[i] = noise.exit[i] = rng() % 0xFFFFFFFFu;
    checkAll(noise);
    for (bool dense : {true, false}) {
        SCOPED_TRACE(dense);
        auto tree = buildMhTree(dense ? noise : emptyMap(256));
        ASSERT_TRUE(tree.ok());
        auto enc = encodeDAGMH(*tree, nullptr);
        ASSERT_TRUE(enc.ok()) << enc.error();
        const uint32_t* d = enc->data();
        const uint32_t S = dagfmt::skipLevel(d);
        const uint64_t skipWords = uint64_t(dagfmt::kSkipWords) << (2 * S);
        const uint64_t rest = d[dagfmt::kTotalWords] - d[dagfmt::kNodeOffset];
        if (S > 0) { // level 0 (one entry) is the floor
            EXPECT_LE(skipWords * 8, rest);
        }
        if (dense) {
            EXPECT_GE(S, 4u);                      // 65,536 distinct values (~0.4 MB): the old rule gave 1
            EXPECT_GT((skipWords << 2) * 8, rest); // the next level would break the budget
        } else {
            EXPECT_EQ(S, 0u);
        }
    }
}

TEST(StaticCodec, WideIntervalsAndExtremes) {
    // Intervals touching 0 and 0xFFFFFFFE, wide closed intervals, and empty texels next to far.
    DualDepthMap m = emptyMap(256);
    for (uint32_t y = 0; y < 256; ++y)
        for (uint32_t x = 0; x < 256; ++x) {
            uint32_t k = (x * 7 + y * 13) % 5;
            if (k == 0)
                setTexel(m, x, y, 0, 0xFFFFFFFEu);
            else if (k == 1)
                setTexel(m, x, y, 0, 0);
            else if (k == 2)
                setTexel(m, x, y, 0xFFFFFFFEu, 0xFFFFFFFEu);
            else if (k == 3)
                setTexel(m, x, y, x << 20, (x << 20) + (y << 12));
        }
    checkAll(m);
}

TEST(StaticCodec, Deterministic) {
    DualDepthMap m = syntheticMap(512, 42);
    for (const Codec& codec : codecs()) {
        auto a = codec.encode(m), b = codec.encode(m);
        ASSERT_TRUE(a.ok() && b.ok()) << codec.name;
        EXPECT_TRUE(*a == *b) << codec.name << " encodes the same map to different bytes";
    }
}

} // namespace
} // namespace ml::stest
