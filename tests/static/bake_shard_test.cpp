// Sharded bakes (bake_shard.h): the split is stable and balanced, a part round-trips and any damage to it
// is refused, and the merged parts equal a single bake byte for byte for every method, with a point
// light (6 faces) and skipped lights among the selection; mismatched, missing and doubled parts are
// refused with one line naming the parts and lights.
#include "scenes/scenes.h"
#include "bake/bake.h"
#include "bake/bake_shard.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

namespace ml {
namespace {

const StaticMethod kMethods[] = {StaticMethod::SM, StaticMethod::MH, StaticMethod::MMH, StaticMethod::DAGMH,
                                 StaticMethod::CPVS};

void expectOneLine(const std::string& error, const std::string& needle) {
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_NE(error.find(needle), std::string::npos) << "'" << needle << "' not in: " << error;
}

TEST(BakeShardSplit, ParsesShardIds) {
    auto s = parseShard("2/5");
    ASSERT_TRUE(s.ok()) << s.error();
    EXPECT_EQ(s->index, 2u);
    EXPECT_EQ(s->count, 5u);
    for (const char* bad : {"", "1", "5/5", "0/0", "-1/4", "1/x", "a/2", "1/2/3", "0/65537", " 0/2"})
        EXPECT_FALSE(parseShard(bad).ok()) << bad;
}

TEST(BakeShardSplit, GreedyLongestFirstWithIndexTieBreaks) {
    // Costs 6 (a point light) and 1 (spots); 0 = skipped. Longest first: 7 (6) -> shard 0; then the
    // spots in index order, each to the least loaded shard (lower index on a tie).
    std::vector<std::pair<uint32_t, uint64_t>> costs = {{1, 1}, {3, 1}, {4, 0}, {7, 6}, {9, 1}, {12, 1}};
    auto s = splitShards(costs, 3);
    ASSERT_EQ(s.size(), 3u);
    EXPECT_EQ(s[0], (std::vector<uint32_t>{7}));
    EXPECT_EQ(s[1], (std::vector<uint32_t>{1, 4, 9})); // 4 (cost 0) goes where the load was 2, not 6
    EXPECT_EQ(s[2], (std::vector<uint32_t>{3, 12}));
    // The input order does not matter.
    std::reverse(costs.begin(), costs.end());
    EXPECT_EQ(splitShards(costs, 3), s);
    // More shards than lights: the rest are empty.
    auto wide = splitShards(costs, 8);
    size_t total = 0, empty = 0;
    for (const auto& v : wide) total += v.size(), empty += v.empty();
    EXPECT_EQ(total, costs.size());
    EXPECT_EQ(empty, 2u);
}

TEST(BakeShardSplit, EveryLightInExactlyOneShardAndBalanced) {
    std::vector<std::pair<uint32_t, uint64_t>> costs;
    for (uint32_t i = 0; i < 1000; ++i) costs.push_back({i * 3, (i % 17 == 0) ? 6 : (i % 13 == 0 ? 0 : 1)});
    const uint64_t sum = std::accumulate(costs.begin(), costs.end(), uint64_t(0),
                                         [](uint64_t a, const auto& c) { return a + c.second; });
    for (uint32_t n : {1u, 2u, 7u, 64u}) {
        auto s = splitShards(costs, n);
        std::vector<uint32_t> all;
        uint64_t maxLoad = 0;
        for (const auto& v : s) {
            uint64_t load = 0;
            for (uint32_t l : v) load += costs[l / 3].second;
            maxLoad = std::max(maxLoad, load);
            all.insert(all.end(), v.begin(), v.end());
        }
        std::sort(all.begin(), all.end());
        ASSERT_EQ(all.size(), costs.size());
        for (size_t i = 0; i < all.size(); ++i) ASSERT_EQ(all[i], costs[i].first);
        // Greedy longest-first is within the largest item (6) of the mean.
        EXPECT_LE(maxLoad, (sum + n - 1) / n + 6) << n << " shards";
    }
}

class BakeShardScene : public testing::Test {
  protected:
    static void SetUpTestSuite() {
        auto s = loadScene(spec_.scene, spec_.lights, spec_.seed);
        ASSERT_TRUE(s.ok()) << s.error();
        scene_ = new Scene(std::move(s.value()));
        // A point light among the spots (6 cube faces; the night city has none of its own).
        scene_->lights[2].type = LightKind::Point;
        for (uint32_t i = 0; i < scene_->lights.size(); ++i)
            if (scene_->lights[i].dynamic) dynamicLight_ = i;
    }
    static void TearDownTestSuite() { delete scene_, scene_ = nullptr; }

    // The selection: 5 static lights (one a point light) and one dynamic light (skipped).
    static std::vector<uint32_t> selection() { return {0, 1, 2, 3, 4, dynamicLight_}; }

    static Result<BakePart> bakePart(StaticMethod m, uint32_t res, ShardId id, const Scene& scene) {
        BakePart p;
        p.shard = id;
        p.selected = selection();
        p.own = shardLights(scene, p.selected, res, id);
        p.fingerprint = sceneFingerprint(scene);
        p.build = 42;
        p.device = "cpu";
        p.file.scene = spec_, p.file.method = m, p.file.resolution = res;
        std::vector<uint32_t> bakeable;
        for (uint32_t l : p.own)
            if (bakeSkipReason(scene, scene.lights[l]).empty()) bakeable.push_back(l);
        if (!bakeable.empty()) {
            auto b = bakeScene(scene, spec_, m, res, bakeable, {}, cpuDualRenderer());
            if (!b) return fail(b.error());
            p.file = std::move(b->file);
        }
        return p;
    }

    static inline SceneSpec spec_{"night-city", 256, 1};
    static inline Scene* scene_ = nullptr;
    static inline uint32_t dynamicLight_ = 0;
};

TEST_F(BakeShardScene, MergedPartsEqualASingleBakeForEveryMethod) {
    for (StaticMethod m : kMethods) {
        SCOPED_TRACE(staticMethodName(m));
        auto single = bakeScene(*scene_, spec_, m, 64, selection(), {}, cpuDualRenderer());
        ASSERT_TRUE(single.ok()) << single.error();
        ASSERT_EQ(single->file.records.size(), 10u); // 4 spots + 6 faces
        auto singleWords = serializeBakeFile(single->file);
        ASSERT_TRUE(singleWords.ok());
        for (uint32_t n : {1u, 3u, 8u}) { // 8: more shards than bakeable lights, some parts empty
            std::vector<BakePart> parts;
            std::vector<std::string> names;
            for (uint32_t i = 0; i < n; ++i) {
                auto p = bakePart(m, 64, {i, n}, *scene_);
                ASSERT_TRUE(p.ok()) << p.error();
                // Through the file format and back.
                auto w = serializeBakePart(p.value());
                ASSERT_TRUE(w.ok()) << w.error();
                auto back = parseBakePart("part", w->data(), w->size());
                ASSERT_TRUE(back.ok()) << back.error();
                parts.push_back(std::move(back.value()));
                names.push_back("part" + std::to_string(i));
            }
            // Any order of parts merges to the same file.
            std::reverse(parts.begin(), parts.end());
            std::reverse(names.begin(), names.end());
            auto merged = mergeBakeParts(parts, names);
            ASSERT_TRUE(merged.ok()) << merged.error();
            auto mergedWords = serializeBakeFile(merged.value());
            ASSERT_TRUE(mergedWords.ok());
            EXPECT_EQ(mergedWords.value(), singleWords.value()) << n << " shards";
        }
    }
}

TEST_F(BakeShardScene, DamagedPartsAreRefused) {
    auto p = bakePart(StaticMethod::MH, 16, {1, 2}, *scene_);
    ASSERT_TRUE(p.ok()) << p.error();
    auto w = serializeBakePart(p.value());
    ASSERT_TRUE(w.ok());
    // Every word of the part (header, lists, inner header, records, data), each bit pattern changed.
    for (size_t i = 0; i < w->size(); ++i) {
        std::vector<uint32_t> d = w.value();
        d[i] ^= 0x00010000u;
        auto r = parseBakePart("damaged", d.data(), d.size());
        ASSERT_FALSE(r.ok()) << "word " << i << " flipped";
        expectOneLine(r.error(), "damaged");
    }
    for (size_t cut : {size_t(0), size_t(3), size_t(16), w->size() - 1}) {
        auto r = parseBakePart("cut", w->data(), cut);
        ASSERT_FALSE(r.ok()) << cut;
        expectOneLine(r.error(), "cut");
    }
    std::vector<uint32_t> longer = w.value();
    longer.push_back(0);
    EXPECT_FALSE(parseBakePart("long", longer.data(), longer.size()).ok());
    // A whole bake file is not a part, and a part is not a bake file: each reader names the other.
    auto whole = serializeBakeFile(p->file);
    ASSERT_TRUE(whole.ok());
    auto r = parseBakePart("whole", whole->data(), whole->size());
    ASSERT_FALSE(r.ok());
    expectOneLine(r.error(), "whole bake file");
    auto f = parseBakeFile("part", w->data(), w->size());
    ASSERT_FALSE(f.ok());
    expectOneLine(f.error(), "manylights merge");
}

TEST_F(BakeShardScene, MismatchedMissingAndDoubledPartsAreRefused) {
    auto p0 = bakePart(StaticMethod::MH, 64, {0, 2}, *scene_);
    auto p1 = bakePart(StaticMethod::MH, 64, {1, 2}, *scene_);
    ASSERT_TRUE(p0.ok() && p1.ok());
    ASSERT_TRUE(mergeBakeParts({p0.value(), p1.value()}, {"a", "b"}).ok());
    auto refused = [&](const BakePart& b, const std::string& needle) {
        auto r = mergeBakeParts({p0.value(), b}, {"a.mlbp", "b.mlbp"});
        ASSERT_FALSE(r.ok()) << needle;
        expectOneLine(r.error(), needle);
        expectOneLine(r.error(), "a.mlbp and b.mlbp");
    };
    {
        auto other = bakePart(StaticMethod::SM, 64, {1, 2}, *scene_);
        ASSERT_TRUE(other.ok());
        refused(other.value(), "method mh vs sm");
        other = bakePart(StaticMethod::MH, 32, {1, 2}, *scene_);
        ASSERT_TRUE(other.ok());
        refused(other.value(), "resolution 64 vs 32");
        Scene moved = *scene_;
        moved.lights[1].position.x += 0.25f; // same name, other lights
        other = bakePart(StaticMethod::MH, 64, {1, 2}, moved);
        ASSERT_TRUE(other.ok());
        refused(other.value(), "scene fingerprint");
    }
    BakePart b = p1.value();
    b.file.scene.seed = 2;
    refused(b, "scene night-city (256 lights, seed 1) vs night-city (256 lights, seed 2)");
    b = p1.value(), b.file.renderer = BakeRenderer::Gpu;
    refused(b, "renderer cpu vs gpu");
    b = p1.value(), b.device = "gpu: other";
    refused(b, "device");
    b = p1.value(), b.build = 43;
    refused(b, "build");
    b = p1.value(), b.shard.count = 3;
    refused(b, "shard count 2 vs 3");
    b = p1.value(), b.selected.push_back(200);
    refused(b, "light selection");

    // Missing: one part of two; the error names the lights and the shard.
    auto r = mergeBakeParts({p1.value()}, {"b.mlbp"});
    ASSERT_FALSE(r.ok());
    std::string lights;
    for (uint32_t l : p0->own) lights += (lights.empty() ? "" : ", ") + std::to_string(l);
    expectOneLine(r.error(), lights + " of the selection in no part (missing shard 0/2)");
    // Doubled: the same part twice.
    r = mergeBakeParts({p0.value(), p1.value(), p0.value()}, {"a.mlbp", "b.mlbp", "c.mlbp"});
    ASSERT_FALSE(r.ok());
    expectOneLine(r.error(), lights + " baked twice: in a.mlbp (shard 0/2) and c.mlbp (shard 0/2)");
    EXPECT_FALSE(mergeBakeParts({}, {}).ok());
}

TEST_F(BakeShardScene, FingerprintSeesGeometryAndLights) {
    const uint64_t h = sceneFingerprint(*scene_);
    EXPECT_EQ(sceneFingerprint(*scene_), h); // deterministic
    Scene s = *scene_;
    s.lights[5].outerAngle *= 0.9f;
    EXPECT_NE(sceneFingerprint(s), h);
    s = *scene_;
    s.lights[240].dynamic = !s.lights[240].dynamic;
    EXPECT_NE(sceneFingerprint(s), h);
    s = *scene_;
    ASSERT_FALSE(s.instances.empty());
    for (Instance& inst : s.instances)
        if (!inst.dynamic) {
            inst.transform[3][1] += 0.01f;
            break;
        }
    EXPECT_NE(sceneFingerprint(s), h);
}

} // namespace
} // namespace ml
