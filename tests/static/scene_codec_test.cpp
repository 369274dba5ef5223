// Real geometry: sample-building.gltf and the night city rasterised from deterministic spotlight
// frusta, then MH, MMH and DAG-MH checked at every texel; sizes printed against the 32-bit map.
// The scene loader (scenes/) is another engineer's: a loader error fails these tests (never skips).
#include "static_test_util.h"
#include "bake/scene_casters.h"

#include "scenes/scenes.h"

#include <chrono>
#include <cmath>
#include <cstdio>

namespace ml::stest {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A frustum looking at the scene bounds from above and aside, covering all of it.
LightFrustum overviewFrustum(const Scene& s, glm::vec3 dir) {
    glm::vec3 c = (s.boundsMin + s.boundsMax) * 0.5f;
    float r = glm::length(s.boundsMax - s.boundsMin) * 0.5f;
    Light l;
    l.direction = glm::normalize(dir);
    l.position = c - l.direction * (r * 2.0f);
    l.outerAngle = std::asin(0.5f) * 1.05f; // r / (2r)
    l.range = r * 3.2f;
    return spotLightFrustum(l, 0.05f);
}

struct MapCase {
    std::string name;
    DualDepthMap map;
};

std::vector<MapCase> sceneMaps(const Scene& scene, const std::string& name, uint32_t res, uint32_t spots,
                               bool overview) {
    CasterTriangles casters = castersFromScene(scene);
    std::vector<MapCase> out;
    std::vector<LightFrustum> frusta;
    if (overview) frusta.push_back(overviewFrustum(scene, {0.35f, -1.0f, 0.25f}));
    for (const Light& l : scene.lights)
        if (l.type == LightKind::Spot && frusta.size() < spots + (overview ? 1u : 0u))
            frusta.push_back(spotLightFrustum(l));
    for (size_t i = 0; i < frusta.size(); ++i) {
        auto t0 = std::chrono::steady_clock::now();
        DualRasterizer r(casters, frusta[i], res);
        DualDepthMap m = r.render();
        uint64_t covered = 0, thick = 0;
        for (size_t k = 0; k < m.enter.size(); ++k)
            covered += m.enter[k] != kDepthEmpty, thick += m.exit[k] > m.enter[k];
        std::printf("  [static] %s frustum %zu %u^2: %zu triangles -> %zu projected, raster %.0f ms, %.1f%% "
                    "covered, %.1f%% closed\n",
                    name.c_str(), i, res, casters.triangleCount(), r.projectedTriangles(), msSince(t0),
                    100.0 * covered / m.enter.size(), 100.0 * thick / m.enter.size());
        out.push_back({name + " frustum " + std::to_string(i), std::move(m)});
    }
    return out;
}

void checkAndReport(const MapCase& mc) {
    SCOPED_TRACE(mc.name);
    const uint64_t smBytes = uint64_t(mc.map.resolution) * mc.map.resolution * 4u;
    std::printf("  [static] %s %u^2: 32-bit map %llu B\n", mc.name.c_str(), mc.map.resolution,
                (unsigned long long)smBytes);
    for (const Codec& codec : codecs()) {
        auto t0 = std::chrono::steady_clock::now();
        auto enc = codec.encode(mc.map);
        double encMs = msSince(t0);
        ASSERT_TRUE(enc.ok()) << codec.name << ": " << enc.error();
        ASSERT_TRUE(codec.validate(enc->data(), enc->size()).ok()) << codec.name;
        t0 = std::chrono::steady_clock::now();
        EXPECT_EQ(countLossy(mc.map, *enc, codec), 0u) << codec.name;
        double lookMs = msSince(t0);
        stat::ByteBreakdown b = codec.breakdown(enc->data(), enc->size());
        EXPECT_EQ(b.total(), enc->size() * 4u) << codec.name;
        std::printf("  [static]   %-6s %9llu B = 1/%.1f of the map (header %llu, skip %llu, nodes %llu, "
                    "treelets %llu, "
                    "values %llu, factors %llu); encode %.0f ms, %u^2 lookups %.0f ms\n",
                    codec.name.c_str(), (unsigned long long)b.total(), double(smBytes) / double(b.total()),
                    (unsigned long long)b.header, (unsigned long long)b.skipList, (unsigned long long)b.nodes,
                    (unsigned long long)b.treelets, (unsigned long long)b.values,
                    (unsigned long long)b.factors, encMs, mc.map.resolution, lookMs);
    }
}

TEST(StaticScenes, SampleBuildingExhaustive1K) {
    ML_SKIP_WITHOUT_SHARED();
    auto scene = loadScene(sharedScene("sample-building.gltf"), 8, 1);
    ASSERT_TRUE(scene.ok()) << "scene loader failed: " << scene.error();
    auto maps = sceneMaps(*scene, "sample-building", 1024, 2, true);
    ASSERT_GE(maps.size(), 2u);
    for (const MapCase& mc : maps) checkAndReport(mc);
}

TEST(StaticScenes, NightCityExhaustive1Kand2K) {
    NightCityOptions o;
    o.lights = 16;
    auto scene = makeNightCity(o);
    ASSERT_TRUE(scene.ok()) << "night city failed: " << scene.error();
    for (const MapCase& mc : sceneMaps(*scene, "night-city", 1024, 2, false)) checkAndReport(mc);
    for (const MapCase& mc : sceneMaps(*scene, "night-city", 2048, 0, true)) checkAndReport(mc);
}

// Size ordering on a realistic map (printed; the papers' 0.85x / 0.75x hold at 8K^2 and above, so at
// 2K^2 only the coarse order is asserted).
TEST(StaticScenes, SizeOrderingSampleBuilding2K) {
    ML_SKIP_WITHOUT_SHARED();
    auto scene = loadScene(sharedScene("sample-building.gltf"), 8, 1);
    ASSERT_TRUE(scene.ok()) << "scene loader failed: " << scene.error();
    CasterTriangles casters = castersFromScene(*scene);
    DualDepthMap m = DualRasterizer(casters, overviewFrustum(*scene, {0.35f, -1.0f, 0.25f}), 2048).render();
    auto tree = buildMhTree(m);
    ASSERT_TRUE(tree.ok());
    auto mh = encodeMH(*tree);
    MmhStats ms;
    auto mmh = encodeMMH(*tree, {}, &ms);
    DagMhStats ds;
    auto dag = encodeDAGMH(*tree, &ds);
    ASSERT_TRUE(mh.ok() && mmh.ok() && dag.ok());
    double sm = double(m.enter.size()) * 4.0;
    double a = double(mh->size()) * 4, b = double(mmh->size()) * 4, c = double(dag->size()) * 4;
    std::printf(
        "  [static] sample-building overview 2048^2: SM %.0f B, MH %.0f B (1/%.1f), MMH %.0f B (1/%.1f), "
        "DAG-MH %.0f B (1/%.1f); MMH/MH %.3f, DAG-MH/MMH %.3f\n",
        sm, a, sm / a, b, sm / b, c, sm / c, b / a, c / b);
    std::printf("  [static]   MMH: %llu candidates, %llu rejected by statistics, %llu by offset, %llu by the "
                "full test, "
                "%llu merges, %llu nodes dropped\n",
                (unsigned long long)ms.candidates, (unsigned long long)ms.rejectedStats,
                (unsigned long long)ms.rejectedOffset, (unsigned long long)ms.rejectedFull,
                (unsigned long long)ms.merges, (unsigned long long)ms.droppedNodes);
    std::printf(
        "  [static]   DAG-MH: inner nodes %llu -> %llu, treelets %llu -> %llu, %llu values in %llu chunks "
        "(%llu raw), %llu factors, %.2f bits per factor\n",
        (unsigned long long)ds.treeInner, (unsigned long long)ds.innerNodes,
        (unsigned long long)ds.treeTreelets, (unsigned long long)ds.treelets, (unsigned long long)ds.values,
        (unsigned long long)ds.chunks, (unsigned long long)ds.rawChunks, (unsigned long long)ds.factors,
        ds.factors ? double(ds.factorBits) / double(ds.factors) : 0.0);
    EXPECT_LT(a, sm);
    EXPECT_LE(b, a);
    EXPECT_LT(c, a);
}

} // namespace
} // namespace ml::stest
