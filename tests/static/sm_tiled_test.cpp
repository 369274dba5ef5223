// SM baked tile by tile (bake/bake_tiled.h) against the whole-map bake: the same words byte for byte on
// the night city's moon (a fitted directional map: version 2, fewer rows than columns) and a street spot
// (version 1, square), at powers of two and not, in 64^2 tiles; and SM refused past kBakeWholeMapMax.
#include "bake/bake_tiled.h"

#include "bake/scene_casters.h"
#include "scenes/scenes.h"
#include "shadows/static/sm.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

struct NightCity {
    Scene scene;
    CasterTriangles casters;
    uint32_t moon = 0, spot = 0;
};

const NightCity& nightCity() {
    static const NightCity city = [] {
        NightCity c;
        auto scene = loadScene("night-city", 256, 1);
        EXPECT_TRUE(scene.ok()) << scene.error();
        c.scene = std::move(scene.value());
        c.casters = castersFromScene(c.scene);
        c.moon = 239;
        for (uint32_t i = 0; i < c.scene.lights.size() && !c.spot; ++i)
            if (c.scene.lights[i].type == LightKind::Spot && !c.scene.lights[i].dynamic) c.spot = i;
        return c;
    }();
    return city;
}

TEST(SmTiled, NightCityMoonAndSpotEqualTheWholeMapBake) {
    const NightCity& c = nightCity();
    ASSERT_GT(c.scene.lights.size(), c.moon);
    ASSERT_EQ(c.scene.lights[c.moon].type, LightKind::Directional);
    ASSERT_NE(c.spot, 0u) << "the night city has no static spot light";
    const std::vector<std::pair<std::string, LightFrustum>> frusta{
        {"moon 239", bakeFrustums(c.scene, c.scene.lights[c.moon])[0]},
        {"spot " + std::to_string(c.spot), bakeFrustums(c.scene, c.scene.lights[c.spot])[0]}};
    for (const auto& [name, f] : frusta)
        for (uint32_t res : {256u, 300u, 512u, 1024u}) {
            const std::string what = name + " at " + std::to_string(res) + "^2";
            // The whole-map bake's words (bake.cpp: the rows from the frustum, then encodeSM).
            DualDepthMap map = rasterizeDual(c.casters, f, res);
            map.rows = f.mapRows(res) < res ? f.mapRows(res) : 0;
            const std::vector<uint32_t> whole = encodeSM(map);
            uint64_t covered = 0, closed = 0;
            for (size_t i = 0; i < map.enter.size(); ++i)
                covered += map.enter[i] != kDepthEmpty, closed += map.exit[i] > map.enter[i];
            EXPECT_GT(covered, uint64_t(res) * res / 20) << what << ": the map should see the city";
            // The moon's fitted map stores fewer rows than columns; the spot's all of them.
            const bool fitted = f.fitted();
            EXPECT_EQ(fitted, name.rfind("moon", 0) == 0) << what;
            EXPECT_EQ(whole[smfmt::kVersion], fitted ? 2u : 1u) << what;
            EXPECT_EQ(smRows(whole.data(), 0) < res, fitted) << what << ": rows stored";
            TiledBakeOptions o;
            o.tile = 64;
            LightBakeStats st;
            auto tiled = bakeRecordTiled(StaticMethod::SM, c.casters, f, res, o, st);
            ASSERT_TRUE(tiled.ok()) << what << ": " << tiled.error();
            ASSERT_TRUE(validateSM(tiled->data(), tiled->size()).ok()) << what;
            ASSERT_EQ(tiled->size(), whole.size()) << what;
            size_t differ = 0;
            for (size_t i = 0; i < whole.size(); ++i) differ += (*tiled)[i] != whole[i];
            EXPECT_EQ(differ, 0u) << what << ": words differ from the whole-map bake's";
            EXPECT_EQ(st.coveredTexels, covered) << what;
            EXPECT_EQ(st.closedTexels, closed) << what;
            const uint32_t side = (res + 63) / 64, rows = smRows(whole.data(), 0);
            EXPECT_EQ(st.tiles, side * ((rows + 63) / 64)) << what << ": tiles past the stored rows";
        }
}

// The bake driver both ways: the file's record of a tiled bake is the whole-map bake's.
TEST(SmTiled, BakeSceneTiledEqualsWhole) {
    const NightCity& c = nightCity();
    const SceneSpec spec{"night-city", 256, 1};
    for (uint32_t light : {c.moon, c.spot}) {
        auto whole = bakeScene(c.scene, spec, StaticMethod::SM, 512, {light});
        ASSERT_TRUE(whole.ok()) << whole.error();
        auto tiled = bakeScene(c.scene, spec, StaticMethod::SM, 512, {light}, {}, {}, {64, 0});
        ASSERT_TRUE(tiled.ok()) << tiled.error();
        ASSERT_EQ(whole->file.records.size(), 1u);
        ASSERT_EQ(tiled->file.records.size(), 1u);
        const uint32_t rows = smRows(whole->file.records[0].data.data(), 0);
        EXPECT_EQ(tiled->lights[0].tiles, 8u * ((rows + 63) / 64)) << "light " << light << ": 64^2 tiles";
        EXPECT_EQ(whole->lights[0].tiles, 0u) << "light " << light << ": the whole map is not tiled";
        EXPECT_EQ(tiled->file.records[0].data, whole->file.records[0].data) << "light " << light;
    }
}

// Past kBakeWholeMapMax SM is refused, tiled or not, with its output's size as the reason.
TEST(SmTiled, RefusedPastTheWholeMapLimit) {
    EXPECT_TRUE(bakeTiled(StaticMethod::SM, kBakeWholeMapMax, 64));
    EXPECT_FALSE(bakeTiled(StaticMethod::SM, kBakeWholeMapMax, 0));
    EXPECT_FALSE(bakeTiled(StaticMethod::SM, kBakeWholeMapMax * 2, 64));
    const NightCity& c = nightCity();
    const SceneSpec spec{"night-city", 256, 1};
    for (uint32_t tile : {0u, 512u}) {
        auto baked = bakeScene(c.scene, spec, StaticMethod::SM, 32768, {c.moon}, {}, {}, {tile, 0});
        ASSERT_FALSE(baked.ok()) << "tile " << tile;
        EXPECT_NE(baked.error().find("32768^2 is 4096 MiB, past any storage buffer a device binds"),
                  std::string::npos)
            << baked.error();
    }
    LightBakeStats st;
    auto tiled = bakeRecordTiled(StaticMethod::SM, c.casters,
                                 bakeFrustums(c.scene, c.scene.lights[c.moon])[0], 32768, {}, st);
    ASSERT_FALSE(tiled.ok());
    EXPECT_NE(tiled.error().find("sm bakes up to 16384^2"), std::string::npos) << tiled.error();
}

} // namespace
} // namespace ml
