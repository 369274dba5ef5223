// CPVS compression: the DAG equals the uncompressed octree (subtree by subtree, through the grid) and
// holds exactly its distinct subtrees; top-down hash compression equals bottom-up even with collisions.
#include "cpvs_test_util.h"

#include <array>
#include <bit>
#include <map>

namespace ml::ctest {
namespace {

// ---------------------------------------------------------------------------------------------------
// DAG == uncompressed octree

struct DRef {
    bool node;
    uint32_t v; // shadow bit, or the word offset of the node / leaf
};

bool sameSubtree(const CpvsOctree& t, uint8_t kind, uint32_t id, uint32_t sizeLog2,
                 const std::vector<uint32_t>& d, DRef r) {
    if (kind != 2) return !r.node && r.v == kind;
    if (!r.node) return false;
    if (sizeLog2 == 2) return t.leaves[id] == (uint64_t(d[r.v]) | uint64_t(d[r.v + 1]) << 32);
    const auto& n = t.levels[sizeLog2 - 3][id];
    uint32_t h = d[r.v];
    if ((h & 0xFF) != n.childMask || (h >> 8) != n.shadowMask) return false;
    for (uint32_t c = 0; c < 8; ++c)
        if ((n.childMask >> c) & 1u) {
            uint32_t p = d[r.v + 1 + std::popcount(h & ((1u << c) - 1))];
            if (!sameSubtree(t, 2, n.child[c], sizeLog2 - 1, d, {true, p})) return false;
        }
    return true;
}

// Descends the octree through the levels the grid replaces and compares each grid cell's subtree.
bool sameAsGrid(const CpvsOctree& t, uint8_t kind, uint32_t id, uint32_t sizeLog2, uint32_t x0, uint32_t y0,
                uint32_t z0, const std::vector<uint32_t>& d) {
    const uint32_t gl = d[kCpvsHGridLog2], cellLog2 = d[kCpvsHLog2Resolution] - gl;
    if (sizeLog2 == cellLog2) {
        uint32_t e =
            d[d[kCpvsHGrid] + (((z0 >> cellLog2) << gl | (y0 >> cellLog2)) << gl | (x0 >> cellLog2))];
        return sameSubtree(t, kind, id, sizeLog2, d, {e >= 2, e});
    }
    const uint32_t h = 1u << (sizeLog2 - 1);
    for (uint32_t c = 0; c < 8; ++c) {
        uint8_t k = kind;
        uint32_t cid = 0;
        if (kind == 2) {
            const auto& n = t.levels[sizeLog2 - 3][id];
            k = (n.childMask >> c) & 1u ? 2 : ((n.shadowMask >> c) & 1u);
            cid = n.child[c];
        }
        if (!sameAsGrid(t, k, cid, sizeLog2 - 1, x0 + (c & 1) * h, y0 + ((c >> 1) & 1) * h, z0 + (c >> 2) * h,
                        d))
            return false;
    }
    return true;
}

// Unique subtrees per level of the octree (levels up to the grid cell size), by exact canonical ids.
std::vector<uint64_t> uniquePerLevel(const CpvsOctree& t, uint32_t topLevel, uint64_t& uniqueLeaves) {
    std::map<uint64_t, uint32_t> leafIds;
    std::vector<uint32_t> canon(t.leaves.size());
    for (size_t i = 0; i < t.leaves.size(); ++i)
        canon[i] = leafIds.emplace(t.leaves[i], leafIds.size()).first->second;
    uniqueLeaves = leafIds.size();
    std::vector<uint64_t> out;
    for (uint32_t k = 0; k <= topLevel; ++k) {
        std::map<std::array<uint32_t, 10>, uint32_t> ids;
        std::vector<uint32_t> next(t.levels[k].size());
        for (size_t i = 0; i < t.levels[k].size(); ++i) {
            const auto& n = t.levels[k][i];
            std::array<uint32_t, 10> key{n.childMask, n.shadowMask};
            for (uint32_t c = 0; c < 8; ++c) key[2 + c] = (n.childMask >> c) & 1u ? canon[n.child[c]] : 0u;
            next[i] = ids.emplace(key, ids.size()).first->second;
        }
        out.push_back(ids.size());
        canon = std::move(next);
    }
    return out;
}

TEST(CpvsOctree, DagEqualsUncompressedOctree) {
    struct Case {
        const char* name;
        DualDepthMap map;
        uint32_t n;
    };
    std::vector<Case> cases;
    cases.push_back({"boxes", boxesMap(64, 41, false, false), 64});
    cases.push_back({"closed", boxesMap(64, 42, true, false), 64});
    cases.push_back({"noise", noiseMap(64, 43), 64});
    cases.push_back({"near", nearPlaneMap(64), 64});
    cases.push_back({"slopes", slopesMap(128), 128});
    cases.push_back({"boxes", boxesMap(128, 44, false, false), 128});
    for (const auto& c : cases) {
        SCOPED_TRACE(std::string(c.name) + " " + std::to_string(c.n));
        auto space = makeCpvsSpace(c.n, kNear, kFar);
        auto pre = cpvsPrecompute(*space, c.map, 8);
        CpvsOctree t = cpvsBuildOctree(
            c.n, [&](uint32_t x, uint32_t y, uint32_t s) { return cpvsResolvedShadowed(*pre, x, y, s); });
        const uint32_t lg = space->log2Resolution;
        for (uint32_t g : {0u, 2u, 3u}) {
            for (auto comp : {CpvsCompression::None, CpvsCompression::BottomUp, CpvsCompression::TopDown}) {
                CpvsBake b = bakeOrDie(c.map, c.n, g, comp);
                EXPECT_TRUE(sameAsGrid(t, t.rootKind, 0, lg, 0, 0, 0, b.data)) << "grid " << g;
                uint64_t uniqueLeaves = 0;
                auto unique = uniquePerLevel(t, lg - g - 3, uniqueLeaves);
                if (comp != CpvsCompression::None) { // optimal: exactly the distinct subtrees
                    EXPECT_EQ(b.stats.nodesPerLevel, unique);
                    EXPECT_EQ(b.stats.leavesFinal, uniqueLeaves);
                } else { // insertion already culls, but never below the optimum
                    uint64_t sum = 0;
                    for (auto u : unique) sum += u;
                    EXPECT_GE(b.stats.nodesInserted, sum);
                }
            }
        }
    }
}

// Top-down hash compression gives the optimal DAG too; with the hash cut to a few bits, collisions are
// frequent and the structural confirm must keep every colliding pair apart.
TEST(CpvsCompress, TopDownEqualsBottomUpEvenWithCollisions) {
    for (uint32_t seed : {81u, 82u}) {
        DualDepthMap m = seed == 81 ? boxesMap(128, seed, false, false) : noiseMap(128, seed);
        CpvsBake bu = bakeOrDie(m, 128, 2, CpvsCompression::BottomUp);
        for (uint32_t bits : {64u, 6u, 1u}) {
            CpvsParams p;
            p.resolution = 128;
            p.nearPlane = kNear;
            p.farPlane = kFar;
            p.gridLog2 = 2;
            p.compression = CpvsCompression::TopDown;
            p.hashBits = bits;
            auto td = bakeCpvs(m, p);
            ASSERT_TRUE(td.ok());
            EXPECT_EQ(td->stats.nodesPerLevel, bu.stats.nodesPerLevel) << bits;
            EXPECT_EQ(td->stats.leavesFinal, bu.stats.leavesFinal);
            EXPECT_EQ(td->stats.bytes.total, bu.stats.bytes.total);
            if (bits == 64) {
                EXPECT_EQ(td->stats.hashCollisions, 0u);
            }
            if (bits == 1) {
                EXPECT_GT(td->stats.hashCollisions, 0u);
            }
            std::printf("  [cpvs] top-down, %u-bit hash: %llu collisions refuted\n", bits,
                        (unsigned long long)td->stats.hashCollisions);
            uint64_t differ = 0;
            for (int32_t s = 0; s < 128; ++s)
                for (int32_t y = 0; y < 128; ++y)
                    for (int32_t x = 0; x < 128; ++x)
                        differ += cpvsShadowedVoxel(td->data.data(), 0, x, y, s) !=
                                  cpvsShadowedVoxel(bu.data.data(), 0, x, y, s);
            EXPECT_EQ(differ, 0u);
        }
    }
    exhaustive("top-down", boxesMap(256, 83, true, false), 256, 4, CpvsCompression::TopDown);
}

} // namespace
} // namespace ml::ctest
