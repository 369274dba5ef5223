// The tiled, out-of-core MH tree (shadows/static/mh_tiled.h) against the whole-map build: the same tree
// node for node and the same MH, MMH and DAG-MH words, so every texel decodes to the same value; and the
// rasteriser's blocks (renderRect) against its rows.
#include "static_test_util.h"
#include "bake/scene_casters.h"

#include "scenes/scenes.h"
#include "shadows/static/mh_tiled.h"

namespace ml::stest {
namespace {

void expectSameTree(const MhTree& a, const MhTree& b, const std::string& what) {
    ASSERT_EQ(a.resolution, b.resolution) << what;
    ASSERT_EQ(a.levels, b.levels) << what;
    ASSERT_EQ(a.nodes.size(), b.nodes.size()) << what;
    size_t bad = 0;
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        const MhTree::Node &x = a.nodes[i], &y = b.nodes[i];
        bool same = x.lo == y.lo && x.hi == y.hi && x.valued == y.valued && x.depth == y.depth;
        for (int c = 0; c < 4; ++c) same = same && x.child[c] == y.child[c];
        if (!same && ++bad <= 3) ADD_FAILURE() << what << ": node " << i << " differs";
    }
    EXPECT_EQ(bad, 0u) << what;
}

// Every method's words from the tiled tree equal the whole map's, and decode the same at every texel.
void expectSameEncodings(const DualDepthMap& map, const MhTree& tiled, const std::string& what) {
    auto mh = encodeMH(tiled), mmh = encodeMMH(tiled), dag = encodeDAGMH(tiled);
    auto mh0 = encodeMH(map), mmh0 = encodeMMH(map), dag0 = encodeDAGMH(map);
    ASSERT_TRUE(mh && mmh && dag && mh0 && mmh0 && dag0) << what;
    EXPECT_EQ(*mh, *mh0) << what << " MH";
    EXPECT_EQ(*mmh, *mmh0) << what << " MMH";
    EXPECT_EQ(*dag, *dag0) << what << " DAG-MH";
    uint64_t differ = 0;
    for (uint32_t y = 0; y < map.resolution; ++y)
        for (uint32_t x = 0; x < map.resolution; ++x)
            differ += mhLookup(mh->data(), x, y) != mhLookup(mh0->data(), x, y) ||
                      mmhLookup(mmh->data(), x, y) != mmhLookup(mmh0->data(), x, y) ||
                      dagmhLookup(dag->data(), x, y) != dagmhLookup(dag0->data(), x, y);
    EXPECT_EQ(differ, 0u) << what;
    // And they are lossless against the map (the whole-map codec tests check the same words).
    for (const Codec& c : codecs()) {
        // The far codecs' lookups are MH's and MMH's own (version 1 words decode the same way).
        const bool isMh = c.name == "MH" || c.name == "MH far",
                   isMmh = c.name == "MMH" || c.name == "MMH far";
        const std::vector<uint32_t>& words = isMh ? *mh : isMmh ? *mmh : *dag;
        EXPECT_EQ(countLossy(map, words, c), 0u) << what << " " << c.name;
    }
}

// Synthetic maps (boxes, slopes, 32-bit noise) at powers of two and not, 64^2 tiles, one and two
// workers, and one tile covering the whole map.
TEST(TiledMh, SyntheticMapsEqualTheWholeMapBuild) {
    struct Case {
        uint32_t res, tile, threads, seed;
    };
    for (const Case& c : {Case{256, 64, 1, 1}, Case{256, 64, 2, 2}, Case{300, 64, 2, 3}, Case{1024, 64, 2, 4},
                          Case{200, 256, 1, 5}, Case{64, 64, 1, 6}, Case{33, 8, 2, 7}}) {
        const std::string what = std::to_string(c.res) + "^2, tiles " + std::to_string(c.tile) + "^2, " +
                                 std::to_string(c.threads) + " threads";
        const DualDepthMap map = syntheticMap(c.res, c.seed);
        auto whole = buildMhTree(map);
        ASSERT_TRUE(whole.ok()) << whole.error();
        MhTiledOptions o;
        o.tile = c.tile, o.threads = c.threads;
        MhTiledStats st;
        auto tiled = buildMhTreeTiled(c.res, dualTileSourceOf(map), o, &st);
        ASSERT_TRUE(tiled.ok()) << what << ": " << tiled.error();
        expectSameTree(*whole, *tiled, what);
        expectSameEncodings(map, *tiled, what);
        uint64_t covered = 0, closed = 0;
        for (size_t i = 0; i < map.enter.size(); ++i)
            covered += map.enter[i] != kDepthEmpty, closed += map.exit[i] > map.enter[i];
        EXPECT_EQ(st.coveredTexels, covered) << what;
        EXPECT_EQ(st.closedTexels, closed) << what;
        EXPECT_EQ(st.nodes, tiled->nodes.size()) << what;
    }
}

// The rasteriser's blocks are its rows' texels, and a tiled build straight from the rasteriser (the
// bake's path) equals the whole-map build: the night city's moon (fitted orthographic, rows past the
// box empty) and a street spot light, 512^2 in 64^2 tiles.
TEST(TiledMh, NightCityRasterTilesEqualTheWholeMap) {
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    const CasterTriangles casters = castersFromScene(*scene);
    std::vector<std::pair<std::string, LightFrustum>> frusta;
    for (size_t i = 0; i < scene->lights.size(); ++i) {
        const Light& l = scene->lights[i];
        if (l.type == LightKind::Directional && frusta.empty())
            frusta.push_back({"moon " + std::to_string(i),
                              directionalLightFrustum(l.direction, scene->boundsMin, scene->boundsMax)});
    }
    ASSERT_FALSE(frusta.empty()) << "the night city has no directional light";
    for (size_t i = 0; i < scene->lights.size(); ++i)
        if (scene->lights[i].type == LightKind::Spot) {
            frusta.push_back({"spot " + std::to_string(i), spotLightFrustum(scene->lights[i])});
            break;
        }
    const uint32_t res = 512;
    for (const auto& [name, f] : frusta) {
        const DualRasterizer raster(casters, f, res);
        const DualDepthMap map = raster.render();
        uint64_t covered = 0;
        for (uint32_t e : map.enter) covered += e != kDepthEmpty;
        EXPECT_GT(covered, uint64_t(res) * res / 20) << name << ": the map should see the city";
        // Odd blocks: every texel of a block equals the whole render's.
        uint64_t differ = 0;
        for (uint32_t y0 = 0; y0 < res; y0 += 100)
            for (uint32_t x0 = 0; x0 < res; x0 += 70) {
                const uint32_t w = std::min(70u, res - x0), h = std::min(100u, res - y0);
                std::vector<uint32_t> e(size_t(w) * h), x(size_t(w) * h);
                raster.renderRect(x0, y0, w, h, e.data(), x.data());
                for (uint32_t y = 0; y < h; ++y)
                    for (uint32_t xx = 0; xx < w; ++xx) {
                        const size_t m = size_t(y0 + y) * res + x0 + xx, t = size_t(y) * w + xx;
                        differ += e[t] != map.enter[m] || x[t] != map.exit[m];
                    }
            }
        EXPECT_EQ(differ, 0u) << name;
        MhTiledOptions o;
        o.tile = 64, o.threads = 2;
        auto tiled = buildMhTreeTiled(
            res,
            [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* e,
                      uint32_t* x) -> Result<void> {
                raster.renderRect(x0, y0, w, h, e, x);
                return {};
            },
            o);
        ASSERT_TRUE(tiled.ok()) << tiled.error();
        auto whole = buildMhTree(map);
        ASSERT_TRUE(whole.ok());
        expectSameTree(*whole, *tiled, name);
        expectSameEncodings(map, *tiled, name);
    }
}

TEST(TiledMh, RefusesBadTilesAndPassesTheSourcesError) {
    const DualDepthMap map = syntheticMap(128, 9);
    MhTiledOptions o;
    o.tile = 48;
    auto r = buildMhTreeTiled(128, dualTileSourceOf(map), o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("not a power of two"), std::string::npos) << r.error();
    o.tile = 32, o.threads = 2;
    auto failing = [](uint32_t x0, uint32_t y0, uint32_t, uint32_t, uint32_t*, uint32_t*) -> Result<void> {
        if (x0 == 64 && y0 == 96) return fail("disk full");
        return {};
    };
    r = buildMhTreeTiled(128, failing, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("tile (64, 96): disk full"), std::string::npos) << r.error();
    EXPECT_FALSE(buildMhTreeTiled(0, dualTileSourceOf(map), o).ok());
    EXPECT_FALSE(buildMhTreeTiled(65537, dualTileSourceOf(map), o).ok());
}

// One light's tiles in shards: three builds of every third tile, put together, assemble to the whole
// map's tree; every built tile validates, and damaged ones are refused.
TEST(TiledMh, ShardsOfTilesAssembleToTheWholeTree) {
    const DualDepthMap map = syntheticMap(300, 11);
    auto grid = mhTileGrid(300, 64);
    ASSERT_TRUE(grid.ok());
    EXPECT_EQ(grid->count(), 64u); // 300 pads to 512: 8 x 8 tiles
    std::vector<MhTile> all(grid->count());
    MhTiledOptions o;
    o.tile = 64, o.threads = 2;
    for (uint32_t shard = 0; shard < 3; ++shard) {
        std::vector<MhTile> part;
        ASSERT_TRUE(buildMhTiles(
                        *grid, dualTileSourceOf(map), o, [&](uint32_t k) { return k % 3 == shard; }, part)
                        .ok());
        for (uint32_t k = 0; k < grid->count(); ++k) {
            EXPECT_EQ(part[k].built, k % 3 == shard) << k;
            if (!part[k].built) continue;
            EXPECT_TRUE(validateMhTile(*grid, part[k]).ok())
                << k << ": " << validateMhTile(*grid, part[k]).error();
            all[k] = std::move(part[k]);
        }
    }
    // Damaged tiles: each change alone is refused.
    const MhTile& good = all[0];
    ASSERT_GT(good.nodes.size(), 3u);
    std::vector<std::pair<std::string, std::function<void(MhTile&)>>> damage = {
        {"truncated", [](MhTile& t) { t.nodes.pop_back(); }},
        {"extra node", [](MhTile& t) { t.nodes.push_back(t.nodes.back()); }},
        {"depth", [](MhTile& t) { t.nodes[1].bits += 1u << 8; }},
        {"lo > hi", [](MhTile& t) { t.nodes[1].lo = 5, t.nodes[1].hi = 4; }},
        {"root interval", [](MhTile& t) { t.lo ^= 1u; }},
        {"flags", [](MhTile& t) { t.flags = 0; }},
        {"stray bits", [](MhTile& t) { t.nodes[2].bits |= 0x40u; }},
        {"empty", [](MhTile& t) { t.nodes.clear(); }},
    };
    for (auto& [name, f] : damage) {
        MhTile bad = good;
        f(bad);
        EXPECT_FALSE(validateMhTile(*grid, bad).ok()) << name;
    }
    auto whole = buildMhTree(map);
    ASSERT_TRUE(whole.ok());
    std::vector<MhTile> missing = all;
    missing[7] = MhTile{};
    auto incomplete = assembleMhTree(*grid, std::move(missing));
    ASSERT_FALSE(incomplete.ok());
    EXPECT_NE(incomplete.error().find("tile 7 of 64 is missing"), std::string::npos) << incomplete.error();
    auto tree = assembleMhTree(*grid, std::move(all));
    ASSERT_TRUE(tree.ok()) << tree.error();
    expectSameTree(*whole, *tree, "three shards of tiles");
}

} // namespace
} // namespace ml::stest
