// The tiled, out-of-core MH tree (shadows/static/mh_tiled.h) against the whole-map build: the same tree
// node for node and the same MH, MMH and DAG-MH words, so every texel decodes to the same value; and the
// rasteriser's blocks (renderRect) against its rows.
#include "static_test_util.h"
#include "bake/scene_casters.h"

#include "scenes/scenes.h"
#include "shadows/static/mh_tiled.h"

#include <atomic>

namespace ml::stest {
namespace {

// The bake's tile source: the rasteriser's blocks.
DualTileSource rasterSource(const DualRasterizer& raster) {
    return [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* e, uint32_t* x,
                     uint32_t* pl) -> Result<void> {
        raster.renderRect(x0, y0, w, h, e, x, pl);
        return {};
    };
}

void expectSameTree(const MhTree& a, const MhTree& b, const std::string& what) {
    ASSERT_EQ(a.resolution, b.resolution) << what;
    ASSERT_EQ(a.levels, b.levels) << what;
    ASSERT_EQ(a.nodes.size(), b.nodes.size()) << what;
    size_t bad = 0;
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        const MhTree::Node &x = a.nodes[i], &y = b.nodes[i];
        bool same =
            x.lo == y.lo && x.hi == y.hi && x.valued == y.valued && x.depth == y.depth && x.plane == y.plane;
        for (int c = 0; c < 4; ++c) same = same && x.child[c] == y.child[c];
        if (!same && ++bad <= 3) ADD_FAILURE() << what << ": node " << i << " differs";
    }
    EXPECT_EQ(bad, 0u) << what;
    EXPECT_EQ(a.planes, b.planes) << what;
}

// Every method's words from the tiled tree equal the whole map's, and decode the same at every texel.
// DAG-MH's from `planarTiled` when the map has planes (its whole-map encoder builds the planar tree).
void expectSameEncodings(const DualDepthMap& map, const MhTree& tiled, const std::string& what,
                         const MhTree* planarTiled = nullptr) {
    auto mh = encodeMH(tiled), mmh = encodeMMH(tiled), dag = encodeDAGMH(planarTiled ? *planarTiled : tiled);
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
        auto tiled = buildMhTreeTiled(res, rasterSource(raster), o);
        ASSERT_TRUE(tiled.ok()) << tiled.error();
        auto whole = buildMhTree(map);
        ASSERT_TRUE(whole.ok());
        expectSameTree(*whole, *tiled, name);
        // The planar tree (DAG-MH's, mh.h): the moon's texels name their planes, the spot's none.
        EXPECT_EQ(map.enterPlane.empty(), !f.orthographic()) << name;
        o.planes = raster.planes();
        auto tiledPlanar = buildMhTreeTiled(res, rasterSource(raster), o);
        ASSERT_TRUE(tiledPlanar.ok()) << tiledPlanar.error();
        auto wholePlanar = buildMhTree(map, true);
        ASSERT_TRUE(wholePlanar.ok());
        expectSameTree(*wholePlanar, *tiledPlanar, name + " planar");
        if (f.orthographic()) {
            // Tilted roofs and walls are blocks of one plane: fewer values than the plain tree's (0.61x
            // at 512^2, 0.18x at 16384^2, where blocks hold more texels).
            EXPECT_LT(wholePlanar->valuedCount() * 3, whole->valuedCount() * 2) << name;
        }
        expectSameEncodings(map, *tiled, name, &*tiledPlanar);
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
    auto failing = [](uint32_t x0, uint32_t y0, uint32_t, uint32_t, uint32_t*, uint32_t*,
                      uint32_t*) -> Result<void> {
        if (x0 == 64 && y0 == 96) return fail("disk full");
        return {};
    };
    r = buildMhTreeTiled(128, failing, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("tile (64, 96): disk full"), std::string::npos) << r.error();
    EXPECT_FALSE(buildMhTreeTiled(0, dualTileSourceOf(map), o).ok());
    EXPECT_FALSE(buildMhTreeTiled(kMhMaxResolution + 1, dualTileSourceOf(map), o).ok());
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

// Tiles that no caster reaches are not rendered: blockEmpty is never wrong about a block (every block
// it calls empty renders empty, at three block sizes), and a build that skips them is the whole map's
// tree node for node, for the moon (rows past its box) and a spot.
TEST(TiledMh, EmptyTilesAreSkippedExactly) {
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    const CasterTriangles casters = castersFromScene(*scene);
    std::vector<std::pair<std::string, LightFrustum>> frusta;
    for (const Light& l : scene->lights) {
        if (l.type == LightKind::Directional && frusta.empty())
            frusta.push_back(
                {"moon", directionalLightFrustum(l.direction, scene->boundsMin, scene->boundsMax)});
    }
    for (const Light& l : scene->lights)
        if (l.type == LightKind::Spot) {
            frusta.push_back({"spot", spotLightFrustum(l)});
            break;
        }
    ASSERT_EQ(frusta.size(), 2u);
    const uint32_t res = 512;
    for (const auto& [name, f] : frusta) {
        const DualRasterizer raster(casters, f, res);
        const DualDepthMap map = raster.render();
        for (uint32_t b : {16u, 32u, 64u}) {
            uint32_t empty = 0, wrong = 0;
            for (uint32_t y0 = 0; y0 < res; y0 += b)
                for (uint32_t x0 = 0; x0 < res; x0 += b) {
                    if (!raster.blockEmpty(x0, y0, b, b)) continue;
                    ++empty;
                    for (uint32_t y = y0; y < y0 + b; ++y)
                        for (uint32_t x = x0; x < x0 + b; ++x)
                            wrong += map.enter[size_t(y) * res + x] != kDepthEmpty ||
                                     map.exit[size_t(y) * res + x] != kDepthEmpty;
                }
            EXPECT_EQ(wrong, 0u) << name << ", blocks of " << b;
            if (name == "moon") {
                EXPECT_GT(empty, 0u) << "the moon's rows past its box are empty";
            }
        }
        MhTiledOptions o;
        o.tile = 32, o.threads = 2;
        o.emptyBlock = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
            return raster.blockEmpty(x0, y0, w, h);
        };
        MhTiledStats st;
        auto tiled = buildMhTreeTiled(res, rasterSource(raster), o, &st);
        ASSERT_TRUE(tiled.ok()) << tiled.error();
        auto whole = buildMhTree(map);
        ASSERT_TRUE(whole.ok());
        expectSameTree(*whole, *tiled, name + " with empty tiles skipped");
        if (name == "moon") {
            EXPECT_GT(st.emptyTiles, 0u);
        }
        std::printf("  %s: %u of %u tiles empty\n", name.c_str(), st.emptyTiles, st.tiles);
    }
}

// The largest map, 262144^2 (18 levels): a tiled build whose tiles are empty but for five 1024^2
// feature tiles (the corners and one inside: synthetic slopes, boxes and 32-bit noise) encodes to MH,
// MMH and DAG-MH words that validate, decode every texel of the feature tiles inside its interval and
// the empty rest (a sample, and the corners of every seventh row of tiles) to kDepthEmpty.
TEST(TiledMh, LargestMapBuildsEncodesAndDecodes) {
    const uint32_t res = kMhMaxResolution, T = 1024, m = res / T;
    ASSERT_EQ(res, 262144u);
    const uint32_t features[5][2] = {{0, 0}, {m - 1, 0}, {0, m - 1}, {m - 1, m - 1}, {m / 3, (2 * m) / 3}};
    std::vector<DualDepthMap> maps;
    for (uint32_t i = 0; i < 5; ++i) maps.push_back(syntheticMap(T, 11 + i));
    auto featureOf = [&](uint32_t x, uint32_t y) -> int {
        for (int i = 0; i < 5; ++i)
            if (x / T == features[i][0] && y / T == features[i][1]) return i;
        return -1;
    };
    MhTiledOptions o;
    o.tile = T, o.threads = 2;
    o.emptyBlock = [&](uint32_t x0, uint32_t y0, uint32_t, uint32_t) { return featureOf(x0, y0) < 0; };
    std::atomic<uint32_t> rendered{0};
    DualTileSource source = [&](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* e, uint32_t* x,
                                uint32_t*) -> Result<void> {
        const int f = featureOf(x0, y0);
        if (f < 0 || w != T || h != T) return fail("a tile the test calls empty was rendered");
        ++rendered;
        std::copy(maps[f].enter.begin(), maps[f].enter.end(), e);
        std::copy(maps[f].exit.begin(), maps[f].exit.end(), x);
        return {};
    };
    MhTiledStats st;
    auto tree = buildMhTreeTiled(res, source, o, &st);
    ASSERT_TRUE(tree.ok()) << tree.error();
    EXPECT_EQ(rendered.load(), 5u);
    EXPECT_EQ(st.emptyTiles, m * m - 5);
    EXPECT_EQ(tree->levels, 18u);
    auto mh = encodeMH(*tree), mmh = encodeMMH(*tree), dag = encodeDAGMH(*tree);
    ASSERT_TRUE(mh && mmh && dag) << (mh ? "" : mh.error()) << (mmh ? "" : mmh.error())
                                  << (dag ? "" : dag.error());
    ASSERT_TRUE(validateMH(mh->data(), mh->size()).ok());
    ASSERT_TRUE(validateMMH(mmh->data(), mmh->size()).ok());
    auto dv = validateDAGMH(dag->data(), dag->size());
    ASSERT_TRUE(dv.ok()) << dv.error();
    uint64_t bad = 0, checked = 0;
    auto check = [&](uint32_t x, uint32_t y, uint32_t e, uint32_t f) {
        for (uint32_t v :
             {mhLookup(mh->data(), x, y), mmhLookup(mmh->data(), x, y), dagmhLookup(dag->data(), x, y)}) {
            const bool ok = e == kDepthEmpty ? v == kDepthEmpty : (e <= v && v <= std::max(e, f));
            if (!ok && ++bad <= 3) ADD_FAILURE() << "texel (" << x << ", " << y << ") decodes " << v;
            ++checked;
        }
    };
    for (int i = 0; i < 5; ++i)
        for (uint32_t y = 0; y < T; ++y)
            for (uint32_t x = 0; x < T; ++x)
                check(features[i][0] * T + x, features[i][1] * T + y, maps[i].enter[size_t(y) * T + x],
                      maps[i].exit[size_t(y) * T + x]);
    std::mt19937 rng(5);
    for (int s = 0; s < 200000; ++s) {
        const uint32_t x = rng() % res, y = rng() % res;
        if (featureOf(x, y) < 0) check(x, y, kDepthEmpty, kDepthEmpty);
    }
    for (uint32_t ty = 0; ty < m; ty += 7)
        for (uint32_t tx = 0; tx < m; ++tx)
            if (featureOf(tx * T, ty * T) < 0)
                for (uint32_t c = 0; c < 4; ++c)
                    check(tx * T + (c & 1) * (T - 1), ty * T + (c >> 1) * (T - 1), kDepthEmpty, kDepthEmpty);
    EXPECT_EQ(bad, 0u) << "of " << checked;
    std::printf("  262144^2: %zu tree nodes; MH %zu, MMH %zu, DAG-MH %zu words; %llu lookups checked\n",
                tree->nodes.size(), mh->size(), mmh->size(), dag->size(), (unsigned long long)checked);
}

} // namespace
} // namespace ml::stest
