// DAG-MH size bench on real maps: night-city overview and spotlights, sample-building overview and a
// spotlight, at 4K^2 and 8K^2 (16K^2 with ML_DAGMH_16K=1). Slow: runs only with ML_STATIC_BENCH=1.
// Prints MH / MMH / DAG-MH bytes, the ratios (MMH <= 0.85 MH, DAG-MH <= 0.75 MMH) and the
// DAG-MH breakdown; every value is checked against its MH node's interval with the decoder's arithmetic
// (the per-texel check of the same encoder runs in the exhaustive tests and in StaticSizeBench).
// ML_DAGMH_CACHE=dir keeps the MH trees on disk so reruns skip the rasteriser.
#include "static_test_util.h"
#include "bake/scene_casters.h"

#include "scenes/scenes.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace ml::stest {
namespace {

LightFrustum overview(const Scene& s) {
    glm::vec3 c = (s.boundsMin + s.boundsMax) * 0.5f;
    float r = glm::length(s.boundsMax - s.boundsMin) * 0.5f;
    Light l;
    l.direction = glm::normalize(glm::vec3(0.35f, -1.0f, 0.25f));
    l.position = c - l.direction * (r * 2.0f);
    l.outerAngle = std::asin(0.5f) * 1.05f;
    l.range = r * 3.2f;
    return spotLightFrustum(l);
}

bool loadTree(const std::string& path, MhTree& t) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return false;
    uint64_t n = 0;
    f.read(reinterpret_cast<char*>(&t.resolution), 4).read(reinterpret_cast<char*>(&t.levels), 4);
    f.read(reinterpret_cast<char*>(&n), 8);
    t.nodes.resize(n);
    f.read(reinterpret_cast<char*>(t.nodes.data()), std::streamsize(n * sizeof(MhTree::Node)));
    return bool(f);
}

void saveTree(const std::string& path, const MhTree& t) {
    std::ofstream f(path, std::ios::binary);
    uint64_t n = t.nodes.size();
    f.write(reinterpret_cast<const char*>(&t.resolution), 4)
        .write(reinterpret_cast<const char*>(&t.levels), 4);
    f.write(reinterpret_cast<const char*>(&n), 8);
    f.write(reinterpret_cast<const char*>(t.nodes.data()), std::streamsize(n * sizeof(MhTree::Node)));
}

TEST(StaticSizeBench, DagMhRealMaps) {
    if (!std::getenv("ML_STATIC_BENCH")) GTEST_SKIP() << "set ML_STATIC_BENCH=1";
    const char* cache = std::getenv("ML_DAGMH_CACHE");
    const char* only = std::getenv("ML_DAGMH_ONLY"); // substring filter on the case name
    std::vector<uint32_t> sizes{4096u, 8192u};
    if (std::getenv("ML_DAGMH_16K")) sizes.push_back(16384u);
    Result<Scene> city = fail("not loaded"), building = fail("not loaded");
    struct Case {
        std::string name;
        int scene;   // 0 city, 1 building
        int frustum; // -1 overview, else spotlight index
    };
    const std::vector<Case> cases{{"night-city overview", 0, -1},
                                  {"night-city spot0", 0, 0},
                                  {"night-city spot1", 0, 1},
                                  {"sample-building overview", 1, -1},
                                  {"sample-building spot0", 1, 0}};
    double sumRatio = 0;
    int count = 0;
    for (uint32_t res : sizes)
        for (const Case& c : cases) {
            std::string name = c.name + " " + std::to_string(res);
            if (only && name.find(only) == std::string::npos) continue;
            std::string file;
            if (cache) {
                file = std::string(cache) + "/" + name + ".tree";
                for (char& ch : file)
                    if (ch == ' ') ch = '_';
            }
            MhTree tree;
            if (file.empty() || !loadTree(file, tree)) {
                Result<Scene>& s = c.scene == 0 ? city : building;
                if (!s)
                    s = c.scene == 0 ? loadScene("night-city", 256, 1)
                                     : loadScene(sharedScene("sample-building.gltf"), 8, 1);
                ASSERT_TRUE(s.ok()) << s.error();
                LightFrustum fr;
                if (c.frustum < 0) {
                    fr = overview(*s);
                } else {
                    int k = 0;
                    bool found = false;
                    for (const Light& l : s->lights)
                        if (l.type == LightKind::Spot && k++ == c.frustum)
                            fr = spotLightFrustum(l), found = true;
                    ASSERT_TRUE(found);
                }
                DualDepthMap m = DualRasterizer(castersFromScene(*s), fr, res).render();
                auto t = buildMhTree(m);
                ASSERT_TRUE(t.ok());
                tree = std::move(*t);
                if (!file.empty()) saveTree(file, tree);
            }
            auto mh = encodeMH(tree);
            auto mmh = encodeMMH(tree);
            DagMhStats ds;
            auto t0 = std::chrono::steady_clock::now();
            auto dag = encodeDAGMH(tree, &ds);
            double ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            if (!mh.ok() || !mmh.ok()) // MH/MMH child offsets are 24-bit: large maps can exceed them
                std::printf("  [dagmh] %s: MH/MMH not encodable (%s)\n", name.c_str(),
                            (!mh.ok() ? mh.error() : mmh.error()).c_str());
            ASSERT_TRUE(dag.ok()) << name << ": " << dag.error();
            ASSERT_TRUE(validateDAGMH(dag->data(), dag->size()).ok()) << name;
            EXPECT_EQ(dagmhCheckValues(tree, dag->data()), 0u) << name;
            stat::ByteBreakdown b = breakdownDAGMH(dag->data(), dag->size());
            double a = mh.ok() ? mh->size() * 4.0 : NAN, m = mmh.ok() ? mmh->size() * 4.0 : NAN,
                   d = dag->size() * 4.0;
            std::printf(
                "  [dagmh] %-30s MH %9.0f MMH %9.0f DAG-MH %9.0f B | MMH/MH %.3f DAG/MMH %.3f | skip %llu "
                "nodes %llu treelets %llu chunks %llu factors %llu | %llu values, %.1f%% with factors, "
                "%.2f bits/factor, %llu raw chunks | %.0f ms\n",
                name.c_str(), a, m, d, m / a, d / m, (unsigned long long)b.skipList,
                (unsigned long long)b.nodes, (unsigned long long)b.treelets, (unsigned long long)b.values,
                (unsigned long long)b.factors, (unsigned long long)ds.values,
                100.0 * double(ds.factors) / double(ds.values),
                ds.factors ? double(ds.factorBits) / double(ds.factors) : 0.0,
                (unsigned long long)ds.rawChunks, ms);
            std::fflush(stdout);
            if (mmh.ok()) sumRatio += d / m, ++count;
        }
    if (count) std::printf("  [dagmh] mean DAG-MH/MMH %.3f over %d maps\n", sumRatio / count, count);
}

} // namespace
} // namespace ml::stest
