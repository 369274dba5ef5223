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

} // namespace
} // namespace ml::stest
