// Tile parts (bake/bake_tile_part.h): one light's tiles in shards merge into the single bake's file; a
// part read back equals the one written; damaged parts (every truncation, every word changed with the
// checksum made to match) are refused with a message or parse into tiles that validate, never crash.
#include "bake/bake.h"
#include "bake/bake_tile_part.h"

#include "scenes/scenes.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

TEST(TileParts, ShardsMergeToTheSingleBakeAndDamageIsRefused) {
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    const SceneSpec spec{"night-city", 256, 1};
    const uint32_t moon = 239, res = 256;
    ASSERT_EQ(scene->lights[moon].type, LightKind::Directional);
    std::vector<TilePart> parts;
    std::vector<std::string> names;
    for (uint32_t i = 0; i < 3; ++i) {
        auto p =
            bakeTilePart(*scene, spec, StaticMethod::DAGMH, res, 64, moon, {i, 3}, BakeRenderer::Cpu, 42);
        ASSERT_TRUE(p.ok()) << p.error();
        auto words = serializeTilePart(*p);
        ASSERT_TRUE(words.ok());
        auto back = parseTilePart("part", words->data(), words->size());
        ASSERT_TRUE(back.ok()) << back.error();
        auto again = serializeTilePart(*back);
        ASSERT_TRUE(again.ok());
        EXPECT_EQ(*again, *words) << "part " << i << " does not read back to itself";
        parts.push_back(std::move(back.value()));
        names.push_back("part" + std::to_string(i));
    }
    // Damage part 1: every truncation, then every word xor-ed with 1 and with 0x80000000 (checksum fixed).
    auto words = serializeTilePart(parts[1]);
    ASSERT_TRUE(words.ok());
    for (size_t n = 0; n < words->size(); ++n) EXPECT_FALSE(parseTilePart("cut", words->data(), n).ok()) << n;
    size_t refused = 0, parsed = 0;
    for (size_t i = 0; i + 1 < words->size(); ++i)
        for (uint32_t flip : {1u, 0x80000000u}) {
            std::vector<uint32_t> w = *words;
            w[i] ^= flip;
            w.back() = stat::checksumWords(w.data(), w.size(), w.size() - 1);
            auto r = parseTilePart("flip", w.data(), w.size());
            if (!r) {
                EXPECT_FALSE(r.error().empty());
                ++refused;
                continue;
            }
            ++parsed; // a change the format cannot see (an interval bound, a frustum float): tiles valid
            auto grid = mhTileGrid(r->resolution, r->tile);
            ASSERT_TRUE(grid.ok());
            for (const auto& [k, t] : r->tiles) EXPECT_TRUE(validateMhTile(*grid, t, r->planes.size()).ok());
        }
    EXPECT_GT(refused, 0u);
    std::printf("tile part of %zu words: %zu damaged copies refused, %zu parsed (undetectable changes)\n",
                words->size(), refused, parsed);

    // Missing and doubled shards are refused; the three merge into the single bake's file.
    {
        std::vector<TilePart> two = {parts[0], parts[2]};
        auto m = mergeTileParts(std::move(two), {"part0", "part2"});
        ASSERT_FALSE(m.ok());
        EXPECT_NE(m.error().find("shard 1/3 is missing"), std::string::npos) << m.error();
        std::vector<TilePart> dup = {parts[0], parts[0], parts[2]};
        EXPECT_FALSE(mergeTileParts(std::move(dup), {"a", "b", "c"}).ok());
        std::vector<TilePart> other = {parts[0], parts[1], parts[2]};
        other[2].build = 43;
        auto b = mergeTileParts(std::move(other), names);
        ASSERT_FALSE(b.ok());
        EXPECT_NE(b.error().find("manylights builds"), std::string::npos) << b.error();
    }
    auto merged = mergeTileParts(std::move(parts), names);
    ASSERT_TRUE(merged.ok()) << merged.error();
    BakeTiles tiles;
    tiles.tile = 64;
    auto single = bakeScene(*scene, spec, StaticMethod::DAGMH, res, {moon}, {}, {}, tiles);
    ASSERT_TRUE(single.ok()) << single.error();
    auto a = serializeBakeFile(*merged), b = serializeBakeFile(single->file);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(*a, *b) << "merged tile parts differ from the single bake";
}

} // namespace
} // namespace ml
