// The bake's memory estimate (bake/bake_estimate.h): CPVS bakes whose maps are all tiled take the region
// build's formula, below the MH family's and growing with the map's side; the others keep the whole-map
// and MH formula; SM in tiles counts its words and tiles, no map; the base counts the process, the
// device and the scene's caster triangles.
#include "bake/bake_estimate.h"

#include "bake/bake_tiled.h"
#include "bake/scene_casters.h"
#include "scenes/scenes.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

constexpr uint64_t kMiB = uint64_t(1) << 20;

TEST(BakeEstimate, CpvsTilesHaveTheirOwnFormulaBelowTheMhFamilys) {
    BakeBase base;
    base.residentBytes = 20 * kMiB, base.casterTriangles = 100000;
    uint64_t previous = 0;
    for (uint32_t n : {4096u, 8192u, 16384u, 65536u, 262144u}) {
        const uint64_t cpvs = bakePeakBytes({n}, StaticMethod::CPVS, 512, 1, base);
        EXPECT_EQ(cpvs, cpvsTiledPeakBytes({n}, 512, base)) << n;
        EXPECT_LT(cpvs, bakePeakBytes({n}, StaticMethod::DAGMH, 512, 1, base)) << n;
        EXPECT_GT(cpvs, previous) << n;
        previous = cpvs;
    }
    // The DAG grows with the side: from 65536^2 to 262144^2 (16x the texels) well under 16x the bytes.
    const uint64_t floor = base.residentBytes + 128 * kMiB + base.casterTriangles * 256;
    EXPECT_LT(cpvsTiledPeakBytes({262144}, 512, base, 2) - floor,
              6 * (cpvsTiledPeakBytes({65536}, 512, base, 2) - floor));
    // Each term of the base counts once: the device only with it, each triangle 256 B.
    BakeBase cpu = base;
    cpu.gpuDevice = false;
    EXPECT_EQ(cpvsTiledPeakBytes({4096}, 512, base, 2) - cpvsTiledPeakBytes({4096}, 512, cpu, 2), 128 * kMiB);
    BakeBase more = base;
    more.casterTriangles += 1000;
    EXPECT_EQ(cpvsTiledPeakBytes({4096}, 512, more, 2) - cpvsTiledPeakBytes({4096}, 512, base, 2), 256000u);
    // Strips of at most max(T^2, 8 R) texels: more threads hold more of them where a region has more
    // rows than the threads' strips (65536^2: R = 4096, 64 rows a strip, 16 x 76 B x 4096 x 64 against
    // 2 x), the same where the threads split one region's rows (4096^2: R = 512, 512^2 texels either way).
    EXPECT_EQ(cpvsTiledPeakBytes({65536}, 512, base, 16) - cpvsTiledPeakBytes({65536}, 512, base, 2),
              uint64_t(14) * 76 * 4096 * 64);
    EXPECT_EQ(cpvsTiledPeakBytes({4096}, 512, base, 16), cpvsTiledPeakBytes({4096}, 512, base, 2));
}

TEST(BakeEstimate, WholeMapsAndMixedBakesKeepTheWholeMapFormula) {
    BakeBase base;
    base.residentBytes = 20 * kMiB;
    // 2048^2 without --tile is a whole map: 400 MiB, the words twice (4 B a texel), map and scratch 24 B.
    const uint64_t texels = uint64_t(2048) * 2048;
    const uint64_t whole = 400 * kMiB + 2 * texels * 4 + texels * 24;
    EXPECT_EQ(bakePeakBytes({2048}, StaticMethod::CPVS, 0, 1, base), whole);
    EXPECT_EQ(bakePeakBytes({2048}, StaticMethod::SM, 0, 1, base), whole);
    // --need may mix a whole map with a tiled one: not every map tiled, so not the region formula.
    EXPECT_GE(bakePeakBytes({2048, 32768}, StaticMethod::CPVS, 0, 1, base), whole);
    EXPECT_NE(bakePeakBytes({2048, 32768}, StaticMethod::CPVS, 0, 1, base),
              cpvsTiledPeakBytes({2048, 32768}, 0, base));
}

// SM in tiles holds its words and the tiles, not the whole map's 24 B a texel of map and scratch; past
// kBakeWholeMapMax it does not tile (bakeTiled), so the whole-map formula stays.
TEST(BakeEstimate, SmTilesDropTheWholeMapsMapAndScratch) {
    BakeBase base;
    const uint64_t texels = uint64_t(8192) * 8192;
    const uint64_t whole = bakePeakBytes({8192}, StaticMethod::SM, 0, 1, base);
    const uint64_t tiled = bakePeakBytes({8192}, StaticMethod::SM, 512, 1, base);
    EXPECT_EQ(whole, 400 * kMiB + 2 * texels * 4 + texels * 24);
    EXPECT_EQ(tiled, 400 * kMiB + 2 * texels * 4 + tiledWorkingBytes(512));
    EXPECT_EQ(bakePeakBytes({32768}, StaticMethod::SM, 512, 1, base),
              400 * kMiB + 2 * uint64_t(32768) * 32768 * 4 + uint64_t(32768) * 32768 * 24);
}

TEST(BakeEstimate, BaseCountsTheScenesStaticCasterTriangles) {
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    const BakeBase b = bakeBaseOf(scene.value(), true);
    EXPECT_EQ(b.casterTriangles, castersFromScene(scene.value()).triangleCount());
    EXPECT_GT(b.residentBytes, 0u);
    EXPECT_GE(b.residentBytes, currentResidentBytes() / 2); // the same process, moments apart
    EXPECT_GE(b.peakBytes, b.residentBytes);
    // The estimate is never below the process's peak so far.
    BakeBase loaded = b;
    loaded.peakBytes = uint64_t(64) << 30;
    EXPECT_EQ(cpvsTiledPeakBytes({1024}, 128, loaded), loaded.peakBytes);
}

} // namespace
} // namespace ml
