// The MH, MMH and DAG-MH lookups at every level of the hierarchy (mhLookupLevel, mmhLookupLevel,
// dagmhLookupLevel: filtering by level), at every node position of every level, against the construction
// tree: MH returns the midpoint of the deepest valued node on the path down to that level, MMH and DAG-MH a
// value inside that node's interval. The GLSL text of each (compiled as C++: glsl_shims.h) answers the
// same.
#include "static_test_util.h"
#include "glsl_shims.h"

namespace ml::stest {
namespace {

// The deepest valued tree node on the path to texel (x, y) of level `steps` (coordinates of that level).
const MhTree::Node& deepestValued(const MhTree& tree, uint32_t x, uint32_t y, uint32_t steps) {
    int32_t n = 0, last = 0;
    for (uint32_t s = steps; s > 0; --s) {
        const uint32_t c = (((y >> (s - 1)) & 1u) << 1) | ((x >> (s - 1)) & 1u);
        n = tree.nodes[size_t(n)].child[c];
        if (n < 0) break;
        if (tree.nodes[size_t(n)].valued) last = n;
    }
    return tree.nodes[size_t(last)];
}

void checkLevels(const DualDepthMap& m, const std::string& what) {
    SCOPED_TRACE(what);
    auto tree = buildMhTree(m);
    ASSERT_TRUE(tree.ok()) << tree.error();
    MmhOptions far;
    far.layout = {16, 3};
    auto mh = encodeMH(*tree), mhFar = encodeMH(*tree, {16, 3});
    auto mmh = encodeMMH(*tree), mmhFar = encodeMMH(*tree, far);
    auto dag = encodeDAGMH(*tree);
    ASSERT_TRUE(mh && mhFar && mmh && mmhFar && dag);
    const uint32_t L = tree->levels, base = 29;
    std::vector<uint32_t> dagShifted(base, 0xDEADBEEFu); // the GLSL reads from a base word, as in the buffer
    dagShifted.insert(dagShifted.end(), dag->begin(), dag->end());
    std::vector<uint32_t> shifted(base, 0xDEADBEEFu);
    shifted.insert(shifted.end(), mmh->begin(), mmh->end());
    uint64_t bad = 0, positions = 0;
    for (uint32_t steps = 0; steps <= L; ++steps) {
        const uint32_t n = 1u << steps;
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const MhTree::Node& node = deepestValued(*tree, x, y, steps);
                const uint32_t mid = stat::midpoint(node.lo, node.hi);
                const uint32_t a = mhLookupLevel(mh->data(), 0, x, y, steps);
                const uint32_t b = mmhLookupLevel(mmh->data(), 0, x, y, steps);
                bool ok = a == mid && mhLookupLevel(mhFar->data(), 0, x, y, steps) == a;
                ok =
                    ok && node.lo <= b && b <= node.hi && mmhLookupLevel(mmhFar->data(), 0, x, y, steps) == b;
                glsl::gStaticData = mh->data();
                ok = ok && glsl::mhLookupLevel(0, x, y, steps) == a;
                glsl::gStaticData = mhFar->data();
                ok = ok && glsl::mhLookupLevel(0, x, y, steps) == a;
                glsl::gStaticData = shifted.data();
                ok = ok && glsl::mmhLookupLevel(base, x, y, steps) == b;
                glsl::gStaticData = mmhFar->data();
                ok = ok && glsl::mmhLookupLevel(0, x, y, steps) == b;
                const uint32_t d = dagmhLookupLevel(dag->data(), 0, x, y, steps);
                ok = ok && node.lo <= d && d <= node.hi;
                glsl::gStaticData = dagShifted.data();
                ok = ok && glsl::dagmhLookupLevel(base, x, y, steps) == d;
                if (!ok && ++bad <= 5)
                    ADD_FAILURE() << "level " << steps << " texel (" << x << "," << y << "): MH " << a
                                  << " (tree " << mid << "), MMH " << b << ", DAG-MH " << d << " outside ["
                                  << node.lo << ", " << node.hi << "] or a twin differs";
                ++positions;
            }
    }
    EXPECT_EQ(bad, 0u);
    // The finest level is the map itself.
    uint64_t finest = 0;
    for (uint32_t y = 0; y < m.resolution; ++y)
        for (uint32_t x = 0; x < m.resolution; ++x)
            finest += mhLookupLevel(mh->data(), 0, x, y, L) != mhLookup(mh->data(), x, y) ||
                      dagmhLookupLevel(dag->data(), 0, x, y, L) != dagmhLookup(dag->data(), x, y);
    EXPECT_EQ(finest, 0u);
    std::printf("  [static] %s: %llu level positions checked (levels 0..%u)\n", what.c_str(),
                (unsigned long long)positions, L);
}

TEST(MhLevels, EveryLevelEveryPositionSynthetic) {
    checkLevels(syntheticMap(256, 31), "synthetic 256");
    checkLevels(syntheticMap(300, 32), "synthetic 300 (padded to 512)");
    checkLevels(syntheticMap(1, 33), "one texel");
}

TEST(MhLevels, EveryLevelEveryPositionRaster) {
    CasterTriangles c;
    std::mt19937 rng(5);
    for (int i = 0; i < 50; ++i) {
        glm::vec3 p(float(rng() % 100) / 10 - 5, float(rng() % 100) / 10 - 5, -3.0f - float(rng() % 50) / 10);
        glm::vec3 q = p + glm::vec3(0.3f + float(rng() % 10) / 10);
        c.add({p.x, p.y, p.z}, {q.x, p.y, q.z}, {q.x, q.y, p.z}, i % 2 == 0);
        c.add({p.x, p.y, p.z}, {q.x, q.y, p.z}, {p.x, q.y, q.z}, i % 2 == 0);
    }
    LightFrustum fr;
    fr.fov = 1.2f;
    fr.farPlane = 12.0f;
    checkLevels(rasterizeDual(c, fr, 256), "raster 256");
}

} // namespace
} // namespace ml::stest
