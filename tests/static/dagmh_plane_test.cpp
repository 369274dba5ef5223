// DAG-MH value chunks with the plane predictor: an exact integer-sloped open plane (the worst case of
// the old absolute values: every texel distinct) costs no factor bits, and every texel stays lossless.
#include "static_test_util.h"

namespace ml::stest {
namespace {

TEST(StaticDagMhValues, IntegerPlaneNeedsNoFactorBits) {
    DualDepthMap m = emptyMap(256);
    for (uint32_t y = 0; y < 256; ++y)
        for (uint32_t x = 0; x < 256; ++x)
            setTexel(m, x, y, 0x40000000u + x * 4001u + y * 70001u, 0x40000000u + x * 4001u + y * 70001u);
    auto tree = buildMhTree(m);
    ASSERT_TRUE(tree.ok());
    DagMhStats st;
    auto enc = encodeDAGMH(*tree, &st);
    ASSERT_TRUE(enc.ok()) << enc.error();
    EXPECT_EQ(st.factorBits, 0u);
    EXPECT_EQ(dagmhCheckValues(*tree, enc->data()), 0u);
    encodeChecked(m, codecs()[2]);
}

TEST(StaticDagMhValues, NegativeSlopesAndMixedSurfaces) {
    // A descending plane, a second plane and empty texels interleaved in the same chunks.
    DualDepthMap m = emptyMap(200);
    for (uint32_t y = 0; y < 200; ++y)
        for (uint32_t x = 0; x < 200; ++x) {
            if ((x / 3 + y / 5) % 7 == 0) continue;
            uint32_t d = (x + y) % 3 == 0 ? 0xF0000000u - x * 900001u - y * 12345u : 0x20000000u + y * 777u;
            setTexel(m, x, y, d, d + ((x ^ y) & 1u) * 5000u);
        }
    auto tree = buildMhTree(m);
    ASSERT_TRUE(tree.ok());
    auto enc = encodeDAGMH(*tree);
    ASSERT_TRUE(enc.ok()) << enc.error();
    EXPECT_EQ(dagmhCheckValues(*tree, enc->data()), 0u);
    encodeChecked(m, codecs()[2]);
}

// The moon's case in miniature: a thin closed slab (a roof 2^12 deep, rising across the chunk by more
// than its depth, so no one point covers it) on one plane, 2^30 above open ground on another,
// interleaved so that every chunk holds both. Each class of a chunk takes one surface with its own plane,
// so a factor only covers the slab's rise within a node's cell at the slab's lattice step (2^11): a few
// bits. One plane for both surfaces (a chunk's single plane before format version 4) needs factors
// spanning the 2^30 gap at the ground's step 1: 30 bits.
TEST(StaticDagMhValues, SlabOverGroundTakesTwoClasses) {
    DualDepthMap m = emptyMap(256);
    for (uint32_t y = 0; y < 256; ++y)
        for (uint32_t x = 0; x < 256; ++x) {
            const uint32_t ground = 0x80000000u + x * 3001u + y * 50001u;
            const uint32_t roof = 0x40000000u + x * 1500u + y * 300u;
            if (((x >> 2) + (y >> 3)) % 3 == 0)
                setTexel(m, x, y, roof, roof + 0x1000u);
            else
                setTexel(m, x, y, ground, ground);
        }
    auto tree = buildMhTree(m);
    ASSERT_TRUE(tree.ok());
    DagMhStats st;
    auto enc = encodeDAGMH(*tree, &st);
    ASSERT_TRUE(enc.ok()) << enc.error();
    EXPECT_EQ(st.rawChunks, 0u);
    EXPECT_GE(st.slopes, 3u); // the zero slope, the ground's and the roof's
    ASSERT_GT(st.values, 0u);
    printf("  [static] slab over ground: %llu values, %llu factors, %llu factor bits, %llu slopes\n",
           (unsigned long long)st.values, (unsigned long long)st.factors, (unsigned long long)st.factorBits,
           (unsigned long long)st.slopes);
    EXPECT_LT(st.factorBits, st.values); // under a bit a value (one plane: 30 bits a factor)
    EXPECT_EQ(dagmhCheckValues(*tree, enc->data()), 0u);
    encodeChecked(m, codecs()[2]);
}

// A version-3 buffer (one plane a chunk) is refused with the reason and the remedy, not misread.
TEST(StaticDagMhValues, OlderVersionIsRefusedWithRebake) {
    auto enc = encodeDAGMH(syntheticMap(64, 9));
    ASSERT_TRUE(enc.ok()) << enc.error();
    std::vector<uint32_t> old = *enc;
    old[dagfmt::kVersion] = dagfmt::kVersionNumber - 1;
    old[dagfmt::kChecksum] = stat::checksumWords(old.data(), old.size(), dagfmt::kChecksum);
    auto v = validateDAGMH(old.data(), old.size());
    ASSERT_FALSE(v.ok());
    EXPECT_NE(v.error().find("unsupported version " + std::to_string(dagfmt::kVersionNumber - 1)),
              std::string::npos)
        << v.error();
    EXPECT_NE(v.error().find("rebake"), std::string::npos) << v.error();
    EXPECT_TRUE(validateDAGMH(enc->data(), enc->size()).ok());
}

} // namespace
} // namespace ml::stest
