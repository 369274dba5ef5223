// CPVS region build (section 4.3) against the global bottom-up build: synthetic maps, exhaustive
// voxels, determinism and the default, night-city spotlights.
#include "cpvs_test_util.h"

#include "bake/scene_casters.h"
#include "scenes/scenes.h"

#include <bit>

namespace ml::ctest {
namespace {

// ---------------------------------------------------------------------------------------------------
// Region build (section 4.3): sub-DAGs per block of grid columns, merged layer by layer. The merged DAG
// is canonical (every level = the sorted distinct subtrees), so it must equal the global bottom-up DAG
// node for node and byte for byte, for every region count.

CpvsBake bakeRegions(const DualDepthMap& map, uint32_t n, uint32_t gridLog2, uint32_t regionLog2) {
    CpvsParams p;
    p.resolution = n;
    p.nearPlane = kNear;
    p.farPlane = kFar;
    p.gridLog2 = gridLog2;
    p.compression = CpvsCompression::Regions;
    p.regionLog2 = regionLog2;
    auto b = bakeCpvs(map, p);
    EXPECT_TRUE(b.ok()) << b.error();
    return b.ok() ? std::move(*b) : CpvsBake{};
}

// The region bake against the global bottom-up bake: same bytes, same nodes per level, same insertion.
void sameAsGlobal(const CpvsBake& regions, const CpvsBake& global, uint32_t expectRegions) {
    ASSERT_TRUE(validateCpvs(regions.data.data(), regions.data.size()).ok());
    EXPECT_EQ(regions.stats.regions, expectRegions);
    EXPECT_EQ(regions.stats.nodesPerLevel, global.stats.nodesPerLevel);
    EXPECT_EQ(regions.stats.leavesFinal, global.stats.leavesFinal);
    // insertion re-uses nodes only along z inside one x, y footprint: regions insert the same nodes
    EXPECT_EQ(regions.stats.nodesInserted, global.stats.nodesInserted);
    EXPECT_EQ(regions.stats.leavesInserted, global.stats.leavesInserted);
    EXPECT_LE(regions.stats.regionNodesPeak, global.stats.nodesInserted);
    EXPECT_LE(regions.stats.mergeMs, regions.stats.compressMs);
    EXPECT_TRUE(regions.data == global.data) << "region build differs from the global bottom-up bytes";
}

// Every voxel of two bakes through the lookup.
uint64_t voxelDifferences(const CpvsBake& a, const CpvsBake& b, uint32_t n) {
    uint64_t differ = 0;
    for (int32_t s = 0; s < int32_t(n); ++s)
        for (int32_t y = 0; y < int32_t(n); ++y)
            for (int32_t x = 0; x < int32_t(n); ++x)
                differ += cpvsShadowedVoxel(a.data.data(), 0, x, y, s) !=
                          cpvsShadowedVoxel(b.data.data(), 0, x, y, s);
    return differ;
}

TEST(CpvsRegions, SyntheticMapsEqualGlobalBottomUp) {
    struct Case {
        const char* name;
        DualDepthMap map;
        uint32_t n;
    };
    std::vector<Case> cases;
    for (uint32_t n : {64u, 128u}) {
        cases.push_back({"boxes-mixed", boxesMap(n, 91, false, false), n});
        cases.push_back({"boxes-closed", boxesMap(n, 92, true, false), n});
        cases.push_back({"boxes-open", boxesMap(n, 93, false, true), n});
        cases.push_back({"slopes", slopesMap(n), n});
        cases.push_back({"noise", noiseMap(n, 94), n});
        cases.push_back({"islands", islandsMap(n, 95), n});
        cases.push_back({"near-plane", nearPlaneMap(n), n});
    }
    cases.push_back({"empty", uniformMap(128, kDepthEmpty, kDepthEmpty), 128});
    cases.push_back({"all-closed", uniformMap(128, MapMaker::q(5.0f), MapMaker::q(7.0f)), 128});
    for (const auto& c : cases) {
        SCOPED_TRACE(std::string(c.name) + " at " + std::to_string(c.n));
        const uint32_t maxGrid = std::countr_zero(c.n) - 3;
        for (uint32_t g : {0u, 2u, 4u}) {
            CpvsBake global = bakeOrDie(c.map, c.n, g, CpvsCompression::BottomUp);
            const uint32_t gl = std::min(g, maxGrid);
            for (uint32_t r : {0u, 1u, 2u, 9u}) {
                SCOPED_TRACE("grid " + std::to_string(g) + " regions 2^" + std::to_string(r));
                CpvsBake reg = bakeRegions(c.map, c.n, g, r);
                sameAsGlobal(reg, global, 1u << (2 * std::min(r, gl)));
            }
        }
    }
}

// Exhaustive at 64^3 .. 256^3: the region bake against the direct voxelisation at every voxel (via the
// shared exhaustive() helper), and against the global bake's lookup at every voxel.
TEST(CpvsRegions, ExhaustiveAgainstVoxelisationAndGlobal) {
    for (uint32_t n : {64u, 128u, 256u}) {
        DualDepthMap boxes = boxesMap(n, 96, false, false), noise = noiseMap(n, 97);
        exhaustive("regions-boxes", boxes, n, 4, CpvsCompression::Regions);
        exhaustive("regions-noise", noise, n, 4, CpvsCompression::Regions);
        for (const DualDepthMap* m : {&boxes, &noise}) {
            CpvsBake global = bakeOrDie(*m, n, 4, CpvsCompression::BottomUp);
            CpvsBake reg = bakeRegions(*m, n, 4, 3);
            EXPECT_EQ(voxelDifferences(reg, global, n), 0u) << n;
            sameAsGlobal(reg, global, 64);
        }
    }
    exhaustive("regions-slopes", slopesMap(256), 256, 4, CpvsCompression::Regions);
    exhaustive("regions-near", nearPlaneMap(256), 256, 4, CpvsCompression::Regions);
}

TEST(CpvsRegions, DeterministicAndDefault) {
    DualDepthMap m = boxesMap(256, 98, false, false);
    CpvsParams p;
    p.resolution = 256;
    p.nearPlane = kNear;
    p.farPlane = kFar;
    EXPECT_EQ(p.compression, CpvsCompression::Regions); // the default build
    std::vector<float> seen;
    p.progress = [&](float f) { seen.push_back(f); };
    auto a = bakeCpvs(m, p);
    ASSERT_TRUE(a.ok());
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end())); // monotone through the regions
    EXPECT_GT(seen.size(), size_t(1u << (2 * p.regionLog2)));
    EXPECT_EQ(seen.back(), 1.0f);
    auto b = bakeCpvs(m, p);
    ASSERT_TRUE(b.ok());
    EXPECT_EQ(a->data, b->data);
    EXPECT_EQ(a->stats.regions, 1u << (2 * p.regionLog2));
    EXPECT_GT(a->stats.liveBytesPeak, 0u);
    EXPECT_GT(a->stats.regionNodesPeak, 0u);
    EXPECT_LT(a->stats.regionNodesPeak, a->stats.nodesInserted);
}

// Real geometry: night-city spotlights from the CPU rasteriser, every voxel at 256^3 against the global
// bake, bytes equal at 256^3 and 512^3 for several region counts.
TEST(CpvsRegions, NightCityEqualsGlobal) {
    auto scene = loadScene("night-city", 64, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    CasterTriangles casters = castersFromScene(*scene);
    std::vector<Light> spots;
    for (const Light& l : scene->lights)
        if (l.type == LightKind::Spot && !l.dynamic && spots.size() < 2) spots.push_back(l);
    ASSERT_FALSE(spots.empty());
    for (size_t li = 0; li < spots.size(); ++li) {
        LightFrustum f = spotLightFrustum(spots[li]);
        for (uint32_t n : {256u, 512u}) {
            SCOPED_TRACE("light " + std::to_string(li) + " at " + std::to_string(n));
            DualDepthMap map = rasterizeDual(casters, f, n);
            CpvsParams p;
            p.resolution = n;
            p.nearPlane = f.nearPlane;
            p.farPlane = f.farPlane;
            p.compression = CpvsCompression::BottomUp;
            auto global = bakeCpvs(map, p);
            ASSERT_TRUE(global.ok());
            p.compression = CpvsCompression::Regions;
            for (uint32_t r : {1u, 2u, 4u}) {
                p.regionLog2 = r;
                auto reg = bakeCpvs(map, p);
                ASSERT_TRUE(reg.ok());
                sameAsGlobal(*reg, *global, 1u << (2 * r));
                if (n == 256 && r == 2) {
                    EXPECT_EQ(voxelDifferences(*reg, *global, n), 0u);
                }
                if (r == 2)
                    std::printf(
                        "  [cpvs] night-city light %zu %u^3: %u regions, peak nodes per region %llu of "
                        "%llu, peak live %.1f KB vs %.1f KB global\n",
                        li, n, reg->stats.regions, (unsigned long long)reg->stats.regionNodesPeak,
                        (unsigned long long)reg->stats.nodesInserted, reg->stats.liveBytesPeak / 1024.0,
                        global->stats.liveBytesPeak / 1024.0);
            }
            CpvsVerifyReport v = verifyCpvs(global->data.data(), map);
            EXPECT_EQ(v.mismatches, 0u);
        }
    }
}

} // namespace
} // namespace ml::ctest
