// CPVS on synthetic dual depth maps: the voxel space (slice index against eq. 1, columns against the
// per-voxel reference) and exhaustive voxel checks of the baked DAG for boxes, slopes, noise, islands,
// uniform and near-plane maps, every grid size and the uncompressed insert. See shadows/static/cpvs.h.
#include "cpvs_test_util.h"

namespace ml::ctest {
namespace {

TEST(CpvsSpace, SliceIndexMonotoneAndMatchesEquation1) {
    for (uint32_t n : {64u, 1024u, 8192u}) {
        auto space = makeCpvsSpace(n, kNear, kFar);
        ASSERT_TRUE(space.ok());
        const auto& t = space->thresholds;
        for (uint32_t s = 1; s <= n; ++s) ASSERT_LT(t[s - 1], t[s]) << s;
        uint32_t prev = 0;
        for (uint64_t d = 0; d <= 0xFFFFFFFFull; d += 0xFFFFFFFFull / 100003) { // monotone
            uint32_t s = cpvsSliceOf(*space, uint32_t(d));
            ASSERT_GE(s, prev);
            ASSERT_LT(s, n);
            prev = s;
        }
        for (uint32_t s = 0; s < n; ++s) { // each slice holds exactly (T[s], T[s+1]]
            if (s > 0) {
                ASSERT_EQ(cpvsSliceOf(*space, t[s] + 1), s);
            }
            if (s + 1 < n) {
                ASSERT_EQ(cpvsSliceOf(*space, t[s + 1]), s);
            }
        }
        Rng r(7);
        const double quantum = double(kFar) / 4294967294.0;
        int compared = 0;
        for (int i = 0; i < 200000; ++i) {
            double z = kNear * std::pow(double(kFar) / kNear, double(r.uniform(-0.01f, 1.01f)));
            int64_t k = cpvsEquation1(z, n, kNear, kFar);
            int64_t expect = std::clamp<int64_t>(k - 1, 0, n - 1);
            double t = z / kFar;
            uint32_t d = t >= 1.0 ? 0xFFFFFFFEu : uint32_t(t * 4294967294.0);
            uint32_t got = cpvsSliceOf(*space, d);
            // a depth within two quanta of a slice boundary may fall either way
            double frac = double(n) * std::log(z / kNear) / std::log(double(kFar) / kNear);
            double zb = kNear * std::pow(double(kFar) / kNear, std::round(frac) / n);
            if (std::fabs(z - zb) < 2.0 * quantum) continue;
            ++compared;
            ASSERT_EQ(int64_t(got), expect) << "z " << z << " n " << n;
        }
        EXPECT_GT(compared, 199000);
    }
    EXPECT_FALSE(makeCpvsSpace(100, kNear, kFar).ok());
    EXPECT_FALSE(makeCpvsSpace(32, kNear, kFar).ok());
    EXPECT_FALSE(makeCpvsSpace(64, 0.0f, kFar).ok());
    EXPECT_FALSE(makeCpvsSpace(64, 2.0f, 1.0f).ok());
}

TEST(CpvsSpace, ColumnMatchesPerVoxelReferenceAndLookupSlice) {
    const uint32_t n = 256;
    DualDepthMap map = nearPlaneMap(n);
    DualDepthMap noise = noiseMap(n, 3);
    auto space = makeCpvsSpace(n, kNear, kFar);
    for (const DualDepthMap* m : {&map, &noise})
        for (uint32_t y = 0; y < n; y += 3)
            for (uint32_t x = 0; x < n; ++x) {
                size_t i = size_t(y) * n + x;
                CpvsColumn c = cpvsReferenceColumn(*space, m->enter[i], m->exit[i]);
                for (uint32_t s = 0; s < n; ++s) {
                    CpvsVoxel expect = s < c.litEnd
                                           ? CpvsVoxel::Lit
                                           : (s < c.shadowBegin ? CpvsVoxel::Undefined : CpvsVoxel::Shadowed);
                    ASSERT_EQ(cpvsReferenceVoxel(*space, *m, x, y, s), expect) << x << "," << y << "," << s;
                }
            }
    CpvsBake b = bakeOrDie(noise, n);
    for (uint32_t s = 0; s <= n; ++s)
        for (int64_t dd = -1; dd <= 1; ++dd) {
            uint32_t d = uint32_t(int64_t(space->thresholds[s]) + dd);
            ASSERT_EQ(cpvsSliceOfDepth(b.data.data(), 0, d), cpvsSliceOf(*space, d));
        }
    EXPECT_EQ(cpvsSliceOfDepth(b.data.data(), 0, 0u), 0u);
    EXPECT_EQ(cpvsSliceOfDepth(b.data.data(), 0, kDepthEmpty), n - 1);
}

TEST(CpvsExhaustive, BoxesClosedOpenMixed) {
    for (uint32_t n : {64u, 128u}) {
        exhaustive("boxes-mixed", boxesMap(n, 11, false, false), n);
        exhaustive("boxes-closed", boxesMap(n, 12, true, false), n);
        exhaustive("boxes-open", boxesMap(n, 13, false, true), n);
    }
    exhaustive("boxes-mixed", boxesMap(256, 14, false, false), 256);
    exhaustive("boxes-closed", boxesMap(256, 15, true, false), 256);
}

TEST(CpvsExhaustive, SlopesNoiseIslands) {
    for (uint32_t n : {64u, 128u}) {
        exhaustive("slopes", slopesMap(n), n);
        exhaustive("noise", noiseMap(n, 21), n);
        exhaustive("islands", islandsMap(n, 22), n);
    }
    exhaustive("slopes", slopesMap(256), 256);
    exhaustive("islands", islandsMap(256, 23), 256);
}

TEST(CpvsExhaustive, EmptyAllCasterNearPlane) {
    const uint32_t n = 128;
    exhaustive("empty", uniformMap(n, kDepthEmpty, kDepthEmpty), n);
    exhaustive("all-open", uniformMap(n, MapMaker::q(5.0f), MapMaker::q(5.0f)), n);
    exhaustive("all-closed", uniformMap(n, MapMaker::q(5.0f), MapMaker::q(7.0f)), n);
    exhaustive("all-at-near", uniformMap(n, MapMaker::q(kNear), MapMaker::q(kNear)), n);
    exhaustive("all-depth-0", uniformMap(n, 0, MapMaker::q(kNear)), n);
    exhaustive("near-plane", nearPlaneMap(n), n);
    exhaustive("near-plane", nearPlaneMap(256), 256);
    // an empty light is a few hundred bytes beyond the thresholds
    CpvsBake b = bakeOrDie(uniformMap(n, kDepthEmpty, kDepthEmpty), n);
    EXPECT_EQ(b.stats.nodesFinal, 0u);
    EXPECT_EQ(b.stats.leavesFinal, 0u);
}

TEST(CpvsExhaustive, GridSizesAndUncompressed) {
    DualDepthMap m = boxesMap(128, 31, false, false);
    for (uint32_t g : {0u, 1u, 2u, 3u, 4u, 9u}) exhaustive("grid", m, 128, g);
    exhaustive("insert-only", m, 128, 4, CpvsCompression::None);
}

} // namespace
} // namespace ml::ctest
