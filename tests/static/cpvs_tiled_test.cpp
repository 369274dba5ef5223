// The tiled, out-of-core CPVS bake (shadows/static/cpvs_tiled.h) against the whole-map bake: the same
// words byte for byte and the same value at every voxel (compared column by column as runs), on
// synthetic maps with empty tiles and regions and on the night city's moon and a street spot light from
// the CPU rasteriser (the bake's path); clean failures on bad input; a 65536^2 map (slice N past 16 bits).
#include "cpvs_test_util.h"

#include "bake/scene_casters.h"
#include "scenes/scenes.h"
#include "shadows/static/cpvs_tiled.h"

#include <bit>

namespace ml::ctest {
namespace {

// A column (x, y) of a CPVS decoded as runs (first slice, shadowed), adjacent equal runs joined: two
// columns hold the same voxels iff their run lists are equal. Walks the layout itself (not ColumnWalk).
void columnRuns(const uint32_t* d, uint32_t x, uint32_t y, std::vector<std::pair<uint32_t, bool>>& runs) {
    runs.clear();
    auto put = [&](uint32_t z, bool sh) {
        if (runs.empty() || runs.back().second != sh) runs.push_back({z, sh});
    };
    const uint32_t gl = d[kCpvsHGridLog2], cl = d[kCpvsHLog2Resolution] - gl, g = 1u << gl;
    auto walk = [&](auto&& self, uint32_t ptr, uint32_t sizeLog2, uint32_t z0) -> void {
        const uint32_t half = 1u << (sizeLog2 - 1), h = d[ptr];
        const uint32_t cxy = ((x & half) ? 1u : 0u) | ((y & half) ? 2u : 0u);
        for (uint32_t cz = 0; cz < 2; ++cz) {
            const uint32_t c = cxy | cz << 2, bit = 1u << c, z = z0 + cz * half;
            if (!(h & bit)) {
                put(z, (h >> 8) & bit);
                continue;
            }
            const uint32_t p = d[ptr + 1 + std::popcount(h & (bit - 1))];
            if (half > 4) {
                self(self, p, sizeLog2 - 1, z);
                continue;
            }
            const uint64_t leaf = uint64_t(d[p]) | uint64_t(d[p + 1]) << 32;
            for (uint32_t dz = 0; dz < 4; ++dz) put(z + dz, (leaf >> ((x & 3) + 4 * (y & 3) + 16 * dz)) & 1u);
        }
    };
    for (uint32_t cz = 0; cz < g; ++cz) {
        const uint32_t e = d[d[kCpvsHGrid] + ((cz << gl | (y >> cl)) << gl | (x >> cl))];
        if (e == kCpvsLit || e == kCpvsShadowed)
            put(cz << cl, e == kCpvsShadowed);
        else
            walk(walk, e, cl, cz << cl);
    }
}

uint64_t columnsDiffering(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b, uint32_t n) {
    std::vector<std::pair<uint32_t, bool>> ra, rb;
    uint64_t bad = 0;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            columnRuns(a.data(), x, y, ra);
            columnRuns(b.data(), x, y, rb);
            bad += ra != rb;
        }
    return bad;
}

// Empty when every texel of the block is empty: the tiled bake then skips it without rendering.
std::function<bool(uint32_t, uint32_t, uint32_t, uint32_t)> emptyBlockOf(const DualDepthMap& m) {
    return [&m](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
        for (uint32_t y = y0; y < y0 + h; ++y)
            for (uint32_t x = x0; x < x0 + w; ++x)
                if (m.enter[size_t(y) * m.resolution + x] != kDepthEmpty) return false;
        return true;
    };
}

// Tiled (tiles of `tile`, with and without the empty-block skip) equals the whole-map bake.
void expectTiledEqualsWhole(const DualDepthMap& map, const CpvsParams& p, uint32_t tile,
                            const DualTileSource& src,
                            const std::function<bool(uint32_t, uint32_t, uint32_t, uint32_t)>& empty,
                            const std::string& what, bool everyVoxel, uint32_t* emptyRegions = nullptr) {
    auto whole = bakeCpvs(map, p);
    ASSERT_TRUE(whole.ok()) << what << ": " << whole.error();
    for (bool skip : {false, true}) {
        CpvsTiledOptions o;
        o.tile = tile, o.threads = 2;
        if (skip) o.emptyBlock = empty;
        CpvsTiledStats st;
        auto tiled = bakeCpvsTiled(src, p, o, &st);
        ASSERT_TRUE(tiled.ok()) << what << ": " << tiled.error();
        EXPECT_EQ(tiled->data, whole->data) << what << (skip ? ", empty blocks skipped" : "");
        EXPECT_EQ(tiled->stats.nodesFinal, whole->stats.nodesFinal) << what;
        EXPECT_EQ(tiled->stats.tileSteps, whole->stats.tileSteps) << what;
        ASSERT_TRUE(validateCpvs(tiled->data.data(), tiled->data.size()).ok()) << what;
        if (skip && emptyRegions) *emptyRegions = st.emptyRegions;
        if (!skip) {
            EXPECT_EQ(st.emptyRegions, 0u);
        }
        uint64_t covered = 0;
        for (uint32_t e : map.enter) covered += e != kDepthEmpty;
        if (!skip) {
            EXPECT_EQ(st.coveredTexels, covered) << what;
        }
        if (everyVoxel && skip) {
            EXPECT_EQ(columnsDiffering(tiled->data, whole->data, map.resolution), 0u) << what;
        }
        CpvsVerifyReport v = verifyCpvs(tiled->data.data(), map);
        EXPECT_EQ(v.mismatches, 0u) << what;
        EXPECT_EQ(v.checked + v.undefined, uint64_t(map.resolution) * map.resolution * map.resolution)
            << what;
    }
}

// Boxes over a quarter of the map (the rest empty: whole regions and strips skipped), closed and open.
DualDepthMap quarterBoxes(uint32_t n, uint32_t seed) {
    DualDepthMap m = boxesMap(n / 2, seed, false, false), out;
    out.resolution = n;
    out.enter.assign(size_t(n) * n, kDepthEmpty);
    out.exit.assign(size_t(n) * n, kDepthEmpty);
    for (uint32_t y = 0; y < n / 2; ++y)
        for (uint32_t x = 0; x < n / 2; ++x) {
            if ((x / 8 + y / 8) % 5 == 0) continue; // holes of whole 8x8 tiles inside the covered quarter
            out.enter[size_t(y + n / 4) * n + x] = m.enter[size_t(y) * (n / 2) + x];
            out.exit[size_t(y + n / 4) * n + x] = m.exit[size_t(y) * (n / 2) + x];
        }
    return out;
}

TEST(CpvsTiled, SyntheticMapsWithEmptyTilesEqualTheWholeMapBake) {
    struct Case {
        uint32_t res, tile, grid;
    };
    // 64^2 tiles: regions of several cells (256^2: C = 16), one cell (1024^2: C = 64), and tiles below a
    // cell (strips of 8 rows inside a 64^2 cell; 512^2 with a 2^2 grid: cells of 128, strips of 32 rows).
    for (const Case& c : {Case{256, 64, 4}, Case{1024, 64, 4}, Case{1024, 16, 4}, Case{512, 64, 2}}) {
        const std::string what = std::to_string(c.res) + "^2, tiles " + std::to_string(c.tile) +
                                 "^2, grid 2^" + std::to_string(c.grid);
        const DualDepthMap map = quarterBoxes(c.res, c.res + c.tile);
        CpvsParams p;
        p.resolution = c.res, p.nearPlane = kNear, p.farPlane = kFar, p.gridLog2 = c.grid;
        uint32_t emptyRegions = 0;
        expectTiledEqualsWhole(map, p, c.tile, dualTileSourceOf(map), emptyBlockOf(map), what, true,
                               &emptyRegions);
        EXPECT_GT(emptyRegions, 0u) << what << ": the empty half should skip whole regions";
    }
    // Linear slicing (directional maps) and noise (every tile its own steps).
    const DualDepthMap noise = noiseMap(256, 9);
    CpvsParams p;
    p.resolution = 256, p.nearPlane = kNear, p.farPlane = kFar, p.slicing = CpvsSlicing::Linear;
    expectTiledEqualsWhole(noise, p, 64, dualTileSourceOf(noise), emptyBlockOf(noise), "noise, linear", true);
}

// The bake's path: the rasteriser's strips (renderRect, blockEmpty) of the night city's moon (light 239,
// fitted orthographic: linear slices, rows past the box empty) and a street spot light, 256^2 and 512^2
// in 64^2 tiles, against the whole rendered map's bake.
TEST(CpvsTiled, NightCityMoonAndSpotEqualTheWholeMapBake) {
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    ASSERT_GT(scene->lights.size(), 239u);
    ASSERT_EQ(scene->lights[239].type, LightKind::Directional);
    const CasterTriangles casters = castersFromScene(*scene);
    std::vector<std::pair<std::string, LightFrustum>> frusta{
        {"moon 239",
         directionalLightFrustum(scene->lights[239].direction, scene->boundsMin, scene->boundsMax)}};
    for (size_t i = 0; i < scene->lights.size(); ++i)
        if (scene->lights[i].type == LightKind::Spot && !scene->lights[i].dynamic) {
            frusta.push_back({"spot " + std::to_string(i), spotLightFrustum(scene->lights[i])});
            break;
        }
    ASSERT_EQ(frusta.size(), 2u);
    for (const auto& [name, f] : frusta)
        for (uint32_t res : {256u, 512u}) {
            const std::string what = name + " at " + std::to_string(res) + "^2";
            const DualRasterizer raster(casters, f, res);
            DualDepthMap map = raster.render();
            map.orthographic = f.orthographic();
            uint64_t covered = 0;
            for (uint32_t e : map.enter) covered += e != kDepthEmpty;
            EXPECT_GT(covered, uint64_t(res) * res / 20) << what << ": the map should see the city";
            CpvsParams p;
            p.resolution = res, p.nearPlane = f.nearPlane, p.farPlane = f.farPlane;
            p.slicing = f.orthographic() ? CpvsSlicing::Linear : CpvsSlicing::Log;
            DualTileSource src = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* e,
                                           uint32_t* x, uint32_t* pl) -> Result<void> {
                raster.renderRect(x0, y0, w, h, e, x, pl);
                return {};
            };
            auto empty = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
                return raster.blockEmpty(x0, y0, w, h);
            };
            expectTiledEqualsWhole(map, p, 64, src, empty, what, res == 256);
        }
}

TEST(CpvsTiled, BadInputFailsCleanly) {
    const DualDepthMap map = quarterBoxes(256, 3);
    CpvsParams p;
    p.resolution = 256, p.nearPlane = kNear, p.farPlane = kFar;
    CpvsTiledOptions o;
    o.tile = 64;
    auto expectFail = [&](const CpvsParams& q, const CpvsTiledOptions& oo, const DualTileSource& s,
                          const std::string& says) {
        auto r = bakeCpvsTiled(s, q, oo);
        ASSERT_FALSE(r.ok()) << says;
        EXPECT_NE(r.error().find(says), std::string::npos) << r.error();
    };
    CpvsParams q = p;
    q.resolution = 300; // not a power of two
    expectFail(q, o, dualTileSourceOf(map), "not a power of two");
    q.resolution = 32; // below 64
    expectFail(q, o, dualTileSourceOf(map), "not a power of two in [64, 262144]");
    q.resolution = 524288; // past the format's limit
    expectFail(q, o, dualTileSourceOf(map), "not a power of two in [64, 262144]");
    for (uint32_t tile : {0u, 4u, 96u, 100u}) { // does not divide the map into whole 8x8 tiles
        CpvsTiledOptions bad = o;
        bad.tile = tile;
        expectFail(p, bad, dualTileSourceOf(map), "tile side " + std::to_string(tile));
    }
    q = p;
    q.farPlane = q.nearPlane; // empty depth range
    expectFail(q, o, dualTileSourceOf(map), "near < far");
    expectFail(p, o, {}, "without a tile source");
    // The source's error, with the strip it failed on.
    DualTileSource failing = [](uint32_t, uint32_t y0, uint32_t, uint32_t, uint32_t*, uint32_t*,
                                uint32_t*) -> Result<void> {
        if (y0 >= 128) return fail("disk gone");
        return {};
    };
    expectFail(p, o, failing, "disk gone");
    // The live bound: a bake past it stops with the size.
    CpvsTiledOptions tight = o;
    tight.maxLiveBytes = 1;
    expectFail(p, tight, dualTileSourceOf(map), "over its bound");
    // A whole-map bake past kCpvsWholeMapMax is refused before it reads the (absent) map.
    q = p;
    q.resolution = 32768;
    auto whole = bakeCpvs(DualDepthMap{}, q);
    ASSERT_FALSE(whole.ok());
    EXPECT_NE(whole.error().find("whole-map bake stops at 16384"), std::string::npos) << whole.error();
}

// The streaming verify's block check walks aligned 4x4 columns at once: its counts equal the one-column
// walk's on a good bake and on one with damaged leaves and homogeneous children (mismatches found).
TEST(CpvsTiled, BlockVerifyEqualsColumnWalk) {
    const DualDepthMap map = boxesMap(256, 12, false, false);
    CpvsParams p;
    p.resolution = 256, p.nearPlane = kNear, p.farPlane = kFar;
    auto bake = bakeCpvs(map, p);
    ASSERT_TRUE(bake.ok()) << bake.error();
    auto space = cpvsSpaceOf(bake->data.data());
    ASSERT_TRUE(space.ok());
    std::vector<uint32_t> bad = bake->data;
    for (uint32_t i = bad[kCpvsHLeaves]; i < bad[kCpvsHLeaves] + bad[kCpvsHLeafWords]; i += 7)
        bad[i] ^= 0x10204u;
    // The node region is a sequence of (header, one pointer per childMask bit): in every 5th node, flip the
    // value of its first homogeneous child.
    for (uint32_t i = bad[kCpvsHNodes], k = 0; i < bad[kCpvsHLeaves]; ++k) {
        const uint32_t h = bad[i], free = ~h & 0xFFu;
        if (k % 5 == 0 && free) bad[i] = h ^ ((free & (0u - free)) << 8);
        i += 1 + uint32_t(std::popcount(h & 0xFFu));
    }
    for (const std::vector<uint32_t>* words : {&bake->data, &bad}) {
        CpvsVerifyReport block, columns;
        verifyCpvsBlock(words->data(), *space, 0, 0, 256, 256, map.enter.data(), map.exit.data(), block);
        for (uint32_t y = 0; y < 256; ++y)
            for (uint32_t x = 0; x < 256; ++x) { // 1x1 blocks: the one-column walk
                const size_t i = size_t(y) * 256 + x;
                verifyCpvsBlock(words->data(), *space, x, y, 1, 1, &map.enter[i], &map.exit[i], columns);
            }
        EXPECT_EQ(block.checked, columns.checked);
        EXPECT_EQ(block.undefined, columns.undefined);
        EXPECT_EQ(block.mismatches, columns.mismatches);
        EXPECT_EQ(block.checked + block.undefined, uint64_t(256) * 256 * 256);
        if (words == &bad) {
            EXPECT_GT(block.mismatches, 1000u) << "the damage should show";
        } else {
            EXPECT_EQ(block.mismatches, 0u);
        }
    }
}

// 65536^2: slice N = 65536 does not fit 16 bits (the precompute's "never shadowed" value), the N + 1
// thresholds and the grid of 4096^2 cells. One 64^2 block of boxes near the far end (slices past 65000);
// the rest is declared empty, so only its 4096^2 region is rendered. Every voxel of the block's columns
// against the voxelisation, and a column outside it lit throughout.
TEST(CpvsTiled, Resolution65536SparseMap) {
    const uint32_t n = 65536, bx = 40960, by = 12288, side = 64;
    auto space = makeCpvsSpace(n, kNear, kFar);
    ASSERT_TRUE(space.ok()) << space.error();
    ASSERT_EQ(space->thresholds.size(), size_t(n) + 1);
    auto inBlock = [&](uint32_t x, uint32_t y) {
        return x >= bx && x < bx + side && y >= by && y < by + side;
    };
    // Near the far plane: slices above 65000 (eq. 1); a closed interval in half the texels.
    const uint32_t enter = space->thresholds[65300] + 5, exit = space->thresholds[65500] + 7;
    DualTileSource src = [&](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* e, uint32_t* x,
                             uint32_t*) -> Result<void> {
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t xx = 0; xx < w; ++xx) {
                const bool in = inBlock(x0 + xx, y0 + y);
                const size_t i = size_t(y) * w + xx;
                e[i] = in ? enter + (xx & 3) : kDepthEmpty;
                x[i] = in ? ((xx + y) % 2 ? exit : e[i]) : kDepthEmpty;
            }
        return {};
    };
    CpvsParams p;
    p.resolution = n, p.nearPlane = kNear, p.farPlane = kFar;
    CpvsTiledOptions o;
    o.tile = 512, o.threads = 2;
    o.emptyBlock = [&](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
        return x0 + w <= bx || x0 >= bx + side || y0 + h <= by || y0 >= by + side;
    };
    CpvsTiledStats st;
    auto bake = bakeCpvsTiled(src, p, o, &st);
    ASSERT_TRUE(bake.ok()) << bake.error();
    ASSERT_TRUE(validateCpvs(bake->data.data(), bake->data.size()).ok());
    EXPECT_EQ(bake->data[kCpvsHResolution], n);
    EXPECT_EQ(st.regions, 256u);
    EXPECT_EQ(st.emptyRegions, 255u);
    EXPECT_EQ(st.coveredTexels, uint64_t(side) * side);
    uint64_t bad = 0, shadowed = 0;
    for (uint32_t y = by - 1; y < by + side + 1; ++y)
        for (uint32_t x = bx - 1; x < bx + side + 1; ++x) {
            const bool in = inBlock(x, y);
            const uint32_t e = in ? enter + ((x - bx) & 3) : kDepthEmpty;
            const uint32_t f = in ? (((x - bx) + (y - by)) % 2 ? exit : e) : kDepthEmpty;
            const CpvsColumn c = cpvsReferenceColumn(*space, e, f);
            for (uint32_t s = 65200; s < n; ++s) {
                const bool sh = cpvsShadowedVoxel(bake->data.data(), 0, int(x), int(y), int(s));
                shadowed += sh;
                bad += s < c.litEnd ? sh : (s >= c.shadowBegin ? !sh : 0);
            }
            bad += cpvsShadowedVoxel(bake->data.data(), 0, int(x), int(y), 100); // near slices are lit
        }
    EXPECT_EQ(bad, 0u);
    EXPECT_GT(shadowed, uint64_t(side) * side * 30) << "the block should shadow the last slices";
    EXPECT_EQ(cpvsSliceOfDepth(bake->data.data(), 0, 0xFFFFFFFEu), n - 1);
}

} // namespace
} // namespace ml::ctest
