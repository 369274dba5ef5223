// Sizes at 4K^2 and 8K^2 (the papers compare at 8K^2 and above). Slow (tens of seconds): runs only
// with ML_STATIC_BENCH=1 and prints MH / MMH / DAG-MH bytes and the ratios the issue names
// (MMH <= 0.85 MH, DAG-MH <= 0.75 MMH). Every texel is still checked.
#include "static_test_util.h"
#include "bake/scene_casters.h"

#include "scenes/scenes.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace ml::stest {
namespace {

TEST(StaticSizeBench, Overview4Kand8K) {
    if (!std::getenv("ML_STATIC_BENCH")) GTEST_SKIP() << "set ML_STATIC_BENCH=1";
    NightCityOptions o;
    o.lights = 16;
    auto city = makeNightCity(o);
    ASSERT_TRUE(city.ok()) << city.error();
    auto building = loadScene(sharedScene("sample-building.gltf"), 8, 1);
    ASSERT_TRUE(building.ok()) << building.error();
    for (const Scene* s : {&*city, &*building})
        for (uint32_t res : {4096u, 8192u}) {
            glm::vec3 c = (s->boundsMin + s->boundsMax) * 0.5f;
            float r = glm::length(s->boundsMax - s->boundsMin) * 0.5f;
            Light l;
            l.direction = glm::normalize(glm::vec3(0.35f, -1.0f, 0.25f));
            l.position = c - l.direction * (r * 2.0f);
            l.outerAngle = std::asin(0.5f) * 1.05f;
            l.range = r * 3.2f;
            auto t0 = std::chrono::steady_clock::now();
            DualDepthMap m = DualRasterizer(castersFromScene(*s), spotLightFrustum(l), res).render();
            auto t1 = std::chrono::steady_clock::now();
            auto tree = buildMhTree(m);
            ASSERT_TRUE(tree.ok());
            auto mh = encodeMH(*tree);
            auto t2 = std::chrono::steady_clock::now();
            auto mmh = encodeMMH(*tree);
            auto t3 = std::chrono::steady_clock::now();
            DagMhStats ds;
            auto dag = encodeDAGMH(*tree, &ds);
            auto t4 = std::chrono::steady_clock::now();
            ASSERT_TRUE(mh.ok() && mmh.ok() && dag.ok());
            auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
            double sm = double(m.enter.size()) * 4, a = mh->size() * 4.0, b = mmh->size() * 4.0,
                   d = dag->size() * 4.0;
            std::printf("  [static] %s overview %u^2: SM %.0f, MH %.0f (1/%.1f), MMH %.0f (1/%.1f), DAG-MH "
                        "%.0f (1/%.1f) B; "
                        "MMH/MH %.3f, DAG-MH/MMH %.3f; raster %.0f ms, MH %.0f, MMH %.0f, DAG-MH %.0f ms; "
                        "%.2f bits/factor, %.0f%% values with factors\n",
                        s->name.c_str(), res, sm, a, sm / a, b, sm / b, d, sm / d, b / a, d / b, ms(t0, t1),
                        ms(t1, t2), ms(t2, t3), ms(t3, t4),
                        ds.factors ? double(ds.factorBits) / ds.factors : 0.0,
                        100.0 * ds.factors / double(ds.values));
            for (int k = 0; k < 3; ++k) {
                const auto& enc = k == 0 ? *mh : k == 1 ? *mmh : *dag;
                EXPECT_EQ(countLossy(m, enc, codecs()[k]), 0u) << codecs()[k].name;
            }
        }
}

} // namespace
} // namespace ml::stest
