// CPVS tests: voxel space (eq. 1), exhaustive voxel checks of the baked DAG against the voxelisation
// derived directly from synthetic dual depth maps, DAG == uncompressed octree, region build == global build,
// determinism, validation of damaged data, and the lookup helpers. See shadows/static/cpvs.h.
#include "scenes/scenes.h"
#include "bake/scene_casters.h"
#include "shadows/static/cpvs.h"
#include "shadows/static/raster_dual.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <random>
#include <sys/mman.h>
#include <unistd.h>

namespace ml {
namespace {

constexpr float kNear = 0.1f, kFar = 20.0f;

// ---------------------------------------------------------------------------------------------------
// Synthetic dual depth maps: per texel a list of surfaces, closed intervals [enter, exit] or open
// surfaces (a single depth). enter = the nearest surface; exit = the end of the chain of closed
// intervals overlapping from there (enter itself when the nearest surface is open).

struct Surface {
    uint32_t a, b; // quantised; open when a == b and !closed
    bool closed;
};

struct MapMaker {
    uint32_t n;
    std::vector<std::vector<Surface>> texels;
    explicit MapMaker(uint32_t res) : n(res), texels(size_t(res) * res) {}

    static uint32_t q(float z) { return quantizeDepth(z, kFar); }
    void add(uint32_t x, uint32_t y, uint32_t a, uint32_t b, bool closed) {
        if (b < a) std::swap(a, b);
        texels[size_t(y) * n + x].push_back({a, closed ? b : a, closed});
    }
    void box(uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, float z0, float z1, bool closed) {
        for (uint32_t y = y0; y < std::min(y1, n); ++y)
            for (uint32_t x = x0; x < std::min(x1, n); ++x) add(x, y, q(z0), q(z1), closed);
    }
    DualDepthMap build() const {
        DualDepthMap m;
        m.resolution = n;
        m.enter.assign(size_t(n) * n, kDepthEmpty);
        m.exit.assign(size_t(n) * n, kDepthEmpty);
        for (size_t i = 0; i < texels.size(); ++i) {
            auto s = texels[i];
            if (s.empty()) continue;
            std::sort(s.begin(), s.end(), [](const Surface& l, const Surface& r) {
                return l.a != r.a ? l.a < r.a : l.closed < r.closed; // an open surface first on a tie
            });
            m.enter[i] = s[0].a;
            uint32_t end = s[0].a;
            if (s[0].closed) {
                end = s[0].b;
                for (const auto& t : s)
                    if (t.closed && t.a <= end) end = std::max(end, t.b);
            }
            m.exit[i] = end;
        }
        return m;
    }
};

struct Rng {
    std::mt19937 g;
    explicit Rng(uint32_t seed) : g(seed) {}
    uint32_t below(uint32_t k) { return uint32_t(g() % k); }
    float uniform(float lo, float hi) { return lo + (hi - lo) * float(g() % 1000000u) / 1000000.0f; }
};

float logDepth(Rng& r) {
    return kNear * std::pow(kFar / kNear, r.uniform(0.0f, 1.0f));
}

DualDepthMap boxesMap(uint32_t n, uint32_t seed, bool allClosed, bool allOpen) {
    MapMaker m(n);
    Rng r(seed);
    m.box(0, 0, n, n, kFar * 0.8f, kFar * 0.9f, !allOpen); // a ground slab
    for (int i = 0; i < 40; ++i) {
        uint32_t x0 = r.below(n), y0 = r.below(n), w = 1 + r.below(n / 4), h = 1 + r.below(n / 4);
        float z0 = logDepth(r), z1 = std::min(kFar, z0 * r.uniform(1.0f, 1.6f));
        bool closed = allClosed ? true : (allOpen ? false : r.below(2) == 0);
        m.box(x0, y0, x0 + w, y0 + h, z0, z1, closed);
    }
    return m.build();
}

DualDepthMap slopesMap(uint32_t n) {
    MapMaker m(n);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            float u = float(x) / float(n), v = float(y) / float(n);
            if (u + v < 1.2f) m.add(x, y, m.q(0.5f + 6.0f * u + 2.0f * v), 0, false); // open tilted plane
            float z = 2.0f + 10.0f * v * v;
            m.add(x, y, m.q(z), m.q(z + 0.5f + u), true); // closed slab, curved
        }
    return m.build();
}

DualDepthMap noiseMap(uint32_t n, uint32_t seed) {
    MapMaker m(n);
    Rng r(seed);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            uint32_t k = r.below(8);
            if (k == 0) continue; // empty
            float z = logDepth(r);
            m.add(x, y, m.q(z), m.q(z * r.uniform(1.0f, 3.0f)), k < 5);
        }
    return m.build();
}

DualDepthMap islandsMap(uint32_t n, uint32_t seed) {
    MapMaker m(n);
    Rng r(seed);
    for (uint32_t i = 0; i < n * 2; ++i) {
        uint32_t x = r.below(n), y = r.below(n);
        float z = logDepth(r);
        m.add(x, y, m.q(z), m.q(z * 1.3f), r.below(2) == 0);
    }
    return m.build();
}

DualDepthMap uniformMap(uint32_t n, uint32_t enter, uint32_t exit) {
    DualDepthMap m;
    m.resolution = n;
    m.enter.assign(size_t(n) * n, enter);
    m.exit.assign(size_t(n) * n, exit);
    return m;
}

// Casters touching and crossing the near plane, at exact slice thresholds, at and past far, and a texel
// whose closed object never exits (exit = kDepthEmpty).
DualDepthMap nearPlaneMap(uint32_t n) {
    auto space = makeCpvsSpace(n, kNear, kFar);
    MapMaker m(n);
    m.box(0, 0, n / 2, n, kNear, kNear * 3.0f, true);               // closed, touching near
    m.box(n / 2, 0, n, n / 2, kNear, kNear, false);                 // open, at near exactly
    m.box(n / 2, n / 2, 3 * n / 4, n, 0.0f, kNear * 0.5f, true);    // starts in front of near (depth 0)
    m.box(3 * n / 4, n / 2, n, 3 * n / 4, kFar, kFar * 2.0f, true); // at and beyond far
    DualDepthMap d = m.build();
    for (uint32_t x = 0; x < n; ++x) { // rows of exact thresholds, +-1
        uint32_t s = x % n;
        d.enter[size_t(n - 1) * n + x] = space->thresholds[s];
        d.exit[size_t(n - 1) * n + x] = space->thresholds[std::min(n, s + 3)];
        d.enter[size_t(n - 2) * n + x] = space->thresholds[s] - 1;
        d.exit[size_t(n - 2) * n + x] = space->thresholds[s] - 1;
        d.enter[size_t(n - 3) * n + x] = space->thresholds[s] + 1;
        d.exit[size_t(n - 3) * n + x] = kDepthEmpty;
    }
    return d;
}

CpvsBake bakeOrDie(const DualDepthMap& map, uint32_t n, uint32_t gridLog2 = 4,
                   CpvsCompression c = CpvsCompression::BottomUp) {
    CpvsParams p;
    p.resolution = n;
    p.nearPlane = kNear;
    p.farPlane = kFar;
    p.gridLog2 = gridLog2;
    p.compression = c;
    auto b = bakeCpvs(map, p);
    EXPECT_TRUE(b.ok()) << b.error();
    return b.ok() ? std::move(*b) : CpvsBake{};
}

void printSize(const char* name, uint32_t n, const CpvsBake& b) {
    const auto& s = b.stats;
    std::printf(
        "  [cpvs] %-12s %5u^3: %9llu B (grid %llu, nodes %llu, leaves %llu, thresholds %llu) = 1/%.1f "
        "of a 16-bit %u^2 map; nodes %llu -> %llu, leaves %llu -> %llu; pre %.2f ins %.2f cmp %.2f ms\n",
        name, n, (unsigned long long)s.bytes.total, (unsigned long long)s.bytes.grid,
        (unsigned long long)s.bytes.innerNodes, (unsigned long long)s.bytes.leafMasks,
        (unsigned long long)s.bytes.thresholds, 2.0 * n * n / double(s.bytes.total), n,
        (unsigned long long)s.nodesInserted, (unsigned long long)s.nodesFinal,
        (unsigned long long)s.leavesInserted, (unsigned long long)s.leavesFinal, s.precomputeMs, s.insertMs,
        s.compressMs);
}

// Every voxel: the DAG lookup against the direct voxelisation (undefined skipped) and against the
// resolved state (nothing skipped); verifyCpvs must agree on the counts.
void exhaustive(const char* name, const DualDepthMap& map, uint32_t n, uint32_t gridLog2 = 4,
                CpvsCompression c = CpvsCompression::BottomUp) {
    SCOPED_TRACE(std::string(name) + " at " + std::to_string(n));
    CpvsBake b = bakeOrDie(map, n, gridLog2, c);
    ASSERT_FALSE(b.data.empty());
    auto ok = validateCpvs(b.data.data(), b.data.size());
    ASSERT_TRUE(ok.ok()) << ok.error();
    auto space = makeCpvsSpace(n, kNear, kFar);
    auto pre = cpvsPrecompute(*space, map, 8);
    ASSERT_TRUE(pre.ok());
    uint64_t checked = 0, undefinedCount = 0, wrong = 0, unresolved = 0;
    for (uint32_t s = 0; s < n; ++s)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                bool got = cpvsShadowedVoxel(b.data.data(), 0, int32_t(x), int32_t(y), int32_t(s));
                CpvsVoxel ref = cpvsReferenceVoxel(*space, map, x, y, s);
                if (ref == CpvsVoxel::Undefined)
                    ++undefinedCount;
                else {
                    ++checked;
                    wrong += got != (ref == CpvsVoxel::Shadowed);
                }
                unresolved += got != cpvsResolvedShadowed(*pre, x, y, s);
            }
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(unresolved, 0u);
    CpvsVerifyReport v = verifyCpvs(b.data.data(), map);
    EXPECT_EQ(v.mismatches, 0u);
    EXPECT_EQ(v.checked, checked);
    EXPECT_EQ(v.undefined, undefinedCount);
    printSize(name, n, b);
}

TEST(CpvsSpace, SliceIndexMonotoneAndMatchesEquation1) {
    for (uint32_t n : {64u, 1024u, 8192u}) {
        auto space = makeCpvsSpace(n, kNear, kFar);
        ASSERT_TRUE(space.ok());
        const auto& t = space->thresholds;
        for (uint32_t s = 1; s <= n; ++s) ASSERT_LT(t[s - 1], t[s]) << s;
        uint32_t prev = 0;
        for (uint64_t d = 0; d <= 0xFFFFFFFFull; d += 0xFFFFFFFFull / 100003) { // monotone
            uint32_t s = cpvsSliceOf(*space, uint32_t(d));
            ASSERT_GE(s, prev);
            ASSERT_LT(s, n);
            prev = s;
        }
        for (uint32_t s = 0; s < n; ++s) { // each slice holds exactly (T[s], T[s+1]]
            if (s > 0) {
                ASSERT_EQ(cpvsSliceOf(*space, t[s] + 1), s);
            }
            if (s + 1 < n) {
                ASSERT_EQ(cpvsSliceOf(*space, t[s + 1]), s);
            }
        }
        Rng r(7);
        const double quantum = double(kFar) / 4294967294.0;
        int compared = 0;
        for (int i = 0; i < 200000; ++i) {
            double z = kNear * std::pow(double(kFar) / kNear, double(r.uniform(-0.01f, 1.01f)));
            int64_t k = cpvsEquation1(z, n, kNear, kFar);
            int64_t expect = std::clamp<int64_t>(k - 1, 0, n - 1);
            double t = z / kFar;
            uint32_t d = t >= 1.0 ? 0xFFFFFFFEu : uint32_t(t * 4294967294.0);
            uint32_t got = cpvsSliceOf(*space, d);
            // a depth within two quanta of a slice boundary may fall either way
            double frac = double(n) * std::log(z / kNear) / std::log(double(kFar) / kNear);
            double zb = kNear * std::pow(double(kFar) / kNear, std::round(frac) / n);
            if (std::fabs(z - zb) < 2.0 * quantum) continue;
            ++compared;
            ASSERT_EQ(int64_t(got), expect) << "z " << z << " n " << n;
        }
        EXPECT_GT(compared, 199000);
    }
    EXPECT_FALSE(makeCpvsSpace(100, kNear, kFar).ok());
    EXPECT_FALSE(makeCpvsSpace(32, kNear, kFar).ok());
    EXPECT_FALSE(makeCpvsSpace(64, 0.0f, kFar).ok());
    EXPECT_FALSE(makeCpvsSpace(64, 2.0f, 1.0f).ok());
}

TEST(CpvsSpace, ColumnMatchesPerVoxelReferenceAndLookupSlice) {
    const uint32_t n = 256;
    DualDepthMap map = nearPlaneMap(n);
    DualDepthMap noise = noiseMap(n, 3);
    auto space = makeCpvsSpace(n, kNear, kFar);
    for (const DualDepthMap* m : {&map, &noise})
        for (uint32_t y = 0; y < n; y += 3)
            for (uint32_t x = 0; x < n; ++x) {
                size_t i = size_t(y) * n + x;
                CpvsColumn c = cpvsReferenceColumn(*space, m->enter[i], m->exit[i]);
                for (uint32_t s = 0; s < n; ++s) {
                    CpvsVoxel expect = s < c.litEnd
                                           ? CpvsVoxel::Lit
                                           : (s < c.shadowBegin ? CpvsVoxel::Undefined : CpvsVoxel::Shadowed);
                    ASSERT_EQ(cpvsReferenceVoxel(*space, *m, x, y, s), expect) << x << "," << y << "," << s;
                }
            }
    CpvsBake b = bakeOrDie(noise, n);
    for (uint32_t s = 0; s <= n; ++s)
        for (int64_t dd = -1; dd <= 1; ++dd) {
            uint32_t d = uint32_t(int64_t(space->thresholds[s]) + dd);
            ASSERT_EQ(cpvsSliceOfDepth(b.data.data(), 0, d), cpvsSliceOf(*space, d));
        }
    EXPECT_EQ(cpvsSliceOfDepth(b.data.data(), 0, 0u), 0u);
    EXPECT_EQ(cpvsSliceOfDepth(b.data.data(), 0, kDepthEmpty), n - 1);
}

TEST(CpvsExhaustive, BoxesClosedOpenMixed) {
    for (uint32_t n : {64u, 128u}) {
        exhaustive("boxes-mixed", boxesMap(n, 11, false, false), n);
        exhaustive("boxes-closed", boxesMap(n, 12, true, false), n);
        exhaustive("boxes-open", boxesMap(n, 13, false, true), n);
    }
    exhaustive("boxes-mixed", boxesMap(256, 14, false, false), 256);
    exhaustive("boxes-closed", boxesMap(256, 15, true, false), 256);
}

TEST(CpvsExhaustive, SlopesNoiseIslands) {
    for (uint32_t n : {64u, 128u}) {
        exhaustive("slopes", slopesMap(n), n);
        exhaustive("noise", noiseMap(n, 21), n);
        exhaustive("islands", islandsMap(n, 22), n);
    }
    exhaustive("slopes", slopesMap(256), 256);
    exhaustive("islands", islandsMap(256, 23), 256);
}

TEST(CpvsExhaustive, EmptyAllCasterNearPlane) {
    const uint32_t n = 128;
    exhaustive("empty", uniformMap(n, kDepthEmpty, kDepthEmpty), n);
    exhaustive("all-open", uniformMap(n, MapMaker::q(5.0f), MapMaker::q(5.0f)), n);
    exhaustive("all-closed", uniformMap(n, MapMaker::q(5.0f), MapMaker::q(7.0f)), n);
    exhaustive("all-at-near", uniformMap(n, MapMaker::q(kNear), MapMaker::q(kNear)), n);
    exhaustive("all-depth-0", uniformMap(n, 0, MapMaker::q(kNear)), n);
    exhaustive("near-plane", nearPlaneMap(n), n);
    exhaustive("near-plane", nearPlaneMap(256), 256);
    // an empty light is a few hundred bytes beyond the thresholds
    CpvsBake b = bakeOrDie(uniformMap(n, kDepthEmpty, kDepthEmpty), n);
    EXPECT_EQ(b.stats.nodesFinal, 0u);
    EXPECT_EQ(b.stats.leavesFinal, 0u);
}

TEST(CpvsExhaustive, GridSizesAndUncompressed) {
    DualDepthMap m = boxesMap(128, 31, false, false);
    for (uint32_t g : {0u, 1u, 2u, 3u, 4u, 9u}) exhaustive("grid", m, 128, g);
    exhaustive("insert-only", m, 128, 4, CpvsCompression::None);
}

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

// ---------------------------------------------------------------------------------------------------
// Region build (section 4.3): sub-DAGs per block of grid columns, merged layer by layer. The merged DAG
// is canonical (every level = the sorted distinct subtrees), so it must equal the global bottom-up DAG
// node for node and byte for byte, for every region count.

CpvsBake bakeRegions(const DualDepthMap& map, uint32_t n, uint32_t gridLog2, uint32_t regionLog2) {
    CpvsParams p;
    p.resolution = n;
    p.nearPlane = kNear;
    p.farPlane = kFar;
    p.gridLog2 = gridLog2;
    p.compression = CpvsCompression::Regions;
    p.regionLog2 = regionLog2;
    auto b = bakeCpvs(map, p);
    EXPECT_TRUE(b.ok()) << b.error();
    return b.ok() ? std::move(*b) : CpvsBake{};
}

// The region bake against the global bottom-up bake: same bytes, same nodes per level, same insertion.
void sameAsGlobal(const CpvsBake& regions, const CpvsBake& global, uint32_t expectRegions) {
    ASSERT_TRUE(validateCpvs(regions.data.data(), regions.data.size()).ok());
    EXPECT_EQ(regions.stats.regions, expectRegions);
    EXPECT_EQ(regions.stats.nodesPerLevel, global.stats.nodesPerLevel);
    EXPECT_EQ(regions.stats.leavesFinal, global.stats.leavesFinal);
    // insertion re-uses nodes only along z inside one x, y footprint: regions insert the same nodes
    EXPECT_EQ(regions.stats.nodesInserted, global.stats.nodesInserted);
    EXPECT_EQ(regions.stats.leavesInserted, global.stats.leavesInserted);
    EXPECT_LE(regions.stats.regionNodesPeak, global.stats.nodesInserted);
    EXPECT_LE(regions.stats.mergeMs, regions.stats.compressMs);
    EXPECT_TRUE(regions.data == global.data) << "region build differs from the global bottom-up bytes";
}

// Every voxel of two bakes through the lookup.
uint64_t voxelDifferences(const CpvsBake& a, const CpvsBake& b, uint32_t n) {
    uint64_t differ = 0;
    for (int32_t s = 0; s < int32_t(n); ++s)
        for (int32_t y = 0; y < int32_t(n); ++y)
            for (int32_t x = 0; x < int32_t(n); ++x)
                differ += cpvsShadowedVoxel(a.data.data(), 0, x, y, s) !=
                          cpvsShadowedVoxel(b.data.data(), 0, x, y, s);
    return differ;
}

TEST(CpvsRegions, SyntheticMapsEqualGlobalBottomUp) {
    struct Case {
        const char* name;
        DualDepthMap map;
        uint32_t n;
    };
    std::vector<Case> cases;
    for (uint32_t n : {64u, 128u}) {
        cases.push_back({"boxes-mixed", boxesMap(n, 91, false, false), n});
        cases.push_back({"boxes-closed", boxesMap(n, 92, true, false), n});
        cases.push_back({"boxes-open", boxesMap(n, 93, false, true), n});
        cases.push_back({"slopes", slopesMap(n), n});
        cases.push_back({"noise", noiseMap(n, 94), n});
        cases.push_back({"islands", islandsMap(n, 95), n});
        cases.push_back({"near-plane", nearPlaneMap(n), n});
    }
    cases.push_back({"empty", uniformMap(128, kDepthEmpty, kDepthEmpty), 128});
    cases.push_back({"all-closed", uniformMap(128, MapMaker::q(5.0f), MapMaker::q(7.0f)), 128});
    for (const auto& c : cases) {
        SCOPED_TRACE(std::string(c.name) + " at " + std::to_string(c.n));
        const uint32_t maxGrid = std::countr_zero(c.n) - 3;
        for (uint32_t g : {0u, 2u, 4u}) {
            CpvsBake global = bakeOrDie(c.map, c.n, g, CpvsCompression::BottomUp);
            const uint32_t gl = std::min(g, maxGrid);
            for (uint32_t r : {0u, 1u, 2u, 9u}) {
                SCOPED_TRACE("grid " + std::to_string(g) + " regions 2^" + std::to_string(r));
                CpvsBake reg = bakeRegions(c.map, c.n, g, r);
                sameAsGlobal(reg, global, 1u << (2 * std::min(r, gl)));
            }
        }
    }
}

// Exhaustive at 64^3 .. 256^3: the region bake against the direct voxelisation at every voxel (via the
// shared exhaustive() helper), and against the global bake's lookup at every voxel.
TEST(CpvsRegions, ExhaustiveAgainstVoxelisationAndGlobal) {
    for (uint32_t n : {64u, 128u, 256u}) {
        DualDepthMap boxes = boxesMap(n, 96, false, false), noise = noiseMap(n, 97);
        exhaustive("regions-boxes", boxes, n, 4, CpvsCompression::Regions);
        exhaustive("regions-noise", noise, n, 4, CpvsCompression::Regions);
        for (const DualDepthMap* m : {&boxes, &noise}) {
            CpvsBake global = bakeOrDie(*m, n, 4, CpvsCompression::BottomUp);
            CpvsBake reg = bakeRegions(*m, n, 4, 3);
            EXPECT_EQ(voxelDifferences(reg, global, n), 0u) << n;
            sameAsGlobal(reg, global, 64);
        }
    }
    exhaustive("regions-slopes", slopesMap(256), 256, 4, CpvsCompression::Regions);
    exhaustive("regions-near", nearPlaneMap(256), 256, 4, CpvsCompression::Regions);
}

TEST(CpvsRegions, DeterministicAndDefault) {
    DualDepthMap m = boxesMap(256, 98, false, false);
    CpvsParams p;
    p.resolution = 256;
    p.nearPlane = kNear;
    p.farPlane = kFar;
    EXPECT_EQ(p.compression, CpvsCompression::Regions); // the default build
    std::vector<float> seen;
    p.progress = [&](float f) { seen.push_back(f); };
    auto a = bakeCpvs(m, p);
    ASSERT_TRUE(a.ok());
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end())); // monotone through the regions
    EXPECT_GT(seen.size(), size_t(1u << (2 * p.regionLog2)));
    EXPECT_EQ(seen.back(), 1.0f);
    auto b = bakeCpvs(m, p);
    ASSERT_TRUE(b.ok());
    EXPECT_EQ(a->data, b->data);
    EXPECT_EQ(a->stats.regions, 1u << (2 * p.regionLog2));
    EXPECT_GT(a->stats.liveBytesPeak, 0u);
    EXPECT_GT(a->stats.regionNodesPeak, 0u);
    EXPECT_LT(a->stats.regionNodesPeak, a->stats.nodesInserted);
}

// Real geometry: night-city spotlights from the CPU rasteriser, every voxel at 256^3 against the global
// bake, bytes equal at 256^3 and 512^3 for several region counts.
TEST(CpvsRegions, NightCityEqualsGlobal) {
    auto scene = loadScene("night-city", 64, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    CasterTriangles casters = castersFromScene(*scene);
    std::vector<Light> spots;
    for (const Light& l : scene->lights)
        if (l.type == LightKind::Spot && !l.dynamic && spots.size() < 2) spots.push_back(l);
    ASSERT_FALSE(spots.empty());
    for (size_t li = 0; li < spots.size(); ++li) {
        LightFrustum f = spotLightFrustum(spots[li]);
        for (uint32_t n : {256u, 512u}) {
            SCOPED_TRACE("light " + std::to_string(li) + " at " + std::to_string(n));
            DualDepthMap map = rasterizeDual(casters, f, n);
            CpvsParams p;
            p.resolution = n;
            p.nearPlane = f.nearPlane;
            p.farPlane = f.farPlane;
            p.compression = CpvsCompression::BottomUp;
            auto global = bakeCpvs(map, p);
            ASSERT_TRUE(global.ok());
            p.compression = CpvsCompression::Regions;
            for (uint32_t r : {1u, 2u, 4u}) {
                p.regionLog2 = r;
                auto reg = bakeCpvs(map, p);
                ASSERT_TRUE(reg.ok());
                sameAsGlobal(*reg, *global, 1u << (2 * r));
                if (n == 256 && r == 2) {
                    EXPECT_EQ(voxelDifferences(*reg, *global, n), 0u);
                }
                if (r == 2)
                    std::printf(
                        "  [cpvs] night-city light %zu %u^3: %u regions, peak nodes per region %llu of "
                        "%llu, peak live %.1f KB vs %.1f KB global\n",
                        li, n, reg->stats.regions, (unsigned long long)reg->stats.regionNodesPeak,
                        (unsigned long long)reg->stats.nodesInserted, reg->stats.liveBytesPeak / 1024.0,
                        global->stats.liveBytesPeak / 1024.0);
            }
            CpvsVerifyReport v = verifyCpvs(global->data.data(), map);
            EXPECT_EQ(v.mismatches, 0u);
        }
    }
}

// ---------------------------------------------------------------------------------------------------
// Determinism, validation, lookup helpers

TEST(CpvsBake, DeterministicAndProgress) {
    DualDepthMap m = boxesMap(128, 51, false, false);
    CpvsParams p;
    p.resolution = 128;
    p.nearPlane = kNear;
    p.farPlane = kFar;
    std::vector<float> seen;
    p.progress = [&](float f) { seen.push_back(f); };
    auto a = bakeCpvs(m, p);
    auto b = bakeCpvs(m, p);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->data, b->data);
    ASSERT_FALSE(seen.empty());
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.begin() + seen.size() / 2));
    EXPECT_EQ(seen.back(), 1.0f);
    DualDepthMap wrong = m;
    wrong.exit.pop_back();
    EXPECT_FALSE(bakeCpvs(wrong, p).ok());
    p.resolution = 256;
    EXPECT_FALSE(bakeCpvs(m, p).ok());
}

// Data placed right before an inaccessible page: a read past the end faults instead of passing silently.
struct GuardedWords {
    size_t pages = 0, page = 0;
    uint8_t* base = nullptr;
    uint32_t* words = nullptr;
    explicit GuardedWords(const std::vector<uint32_t>& w) {
        page = size_t(sysconf(_SC_PAGESIZE));
        size_t bytes = w.size() * 4, dataPages = (bytes + page - 1) / page;
        pages = dataPages + 2;
        base = static_cast<uint8_t*>(
            mmap(nullptr, pages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
        mprotect(base, page, PROT_NONE);
        mprotect(base + (dataPages + 1) * page, page, PROT_NONE);
        words = reinterpret_cast<uint32_t*>(base + (dataPages + 1) * page - bytes);
        std::memcpy(words, w.data(), bytes);
    }
    ~GuardedWords() { munmap(base, pages * page); }
};

TEST(CpvsValidate, RejectsTruncatedAndBitFlippedData) {
    const uint32_t n = 64;
    DualDepthMap m = boxesMap(n, 61, false, false);
    CpvsBake b = bakeOrDie(m, n, 2);
    const std::vector<uint32_t>& d = b.data;
    ASSERT_TRUE(validateCpvs(d.data(), d.size()).ok());
    EXPECT_FALSE(validateCpvs(nullptr, 0).ok());
    for (size_t len = 0; len < d.size(); ++len) ASSERT_FALSE(validateCpvs(d.data(), len).ok()) << len;
    // truncated and re-declared (header says the shorter size, checksum re-signed): offsets disagree
    for (size_t len = kCpvsHeaderWords; len < d.size(); len += 7) {
        std::vector<uint32_t> t(d.begin(), d.begin() + len);
        t[kCpvsHTotalWords] = uint32_t(len);
        t[kCpvsHChecksum] = cpvsChecksum(t.data(), t.size());
        ASSERT_FALSE(validateCpvs(t.data(), t.size()).ok()) << len;
    }
    // every single bit flip is caught (the checksum sees any change within one word)
    std::vector<uint32_t> c = d;
    for (size_t i = 0; i < c.size(); ++i)
        for (uint32_t bit = 0; bit < 32; bit += (i < 64 ? 1 : 11)) {
            c[i] ^= 1u << bit;
            ASSERT_FALSE(validateCpvs(c.data(), c.size()).ok()) << i << ":" << bit;
            c[i] ^= 1u << bit;
        }
    // flips with a re-signed checksum: the structural checks alone. Either rejected, or every lookup stays
    // inside the data (guard pages) and terminates.
    uint64_t rejected = 0, accepted = 0;
    for (size_t i = 0; i < c.size(); ++i)
        for (uint32_t bit = 0; bit < 32; bit += 5) {
            if (i == kCpvsHChecksum) continue;
            c[i] ^= 1u << bit;
            c[kCpvsHChecksum] = cpvsChecksum(c.data(), c.size());
            if (!validateCpvs(c.data(), c.size()).ok()) {
                ++rejected;
            } else {
                ++accepted;
                GuardedWords g(c);
                for (int32_t s = 0; s < int32_t(n); s += 3)
                    for (int32_t y = 0; y < int32_t(n); y += 2)
                        for (int32_t x = 0; x < int32_t(n); ++x) (void)cpvsShadowedVoxel(g.words, 0, x, y, s);
                (void)verifyCpvs(g.words, m);
            }
            c[i] ^= 1u << bit;
            c[kCpvsHChecksum] = d[kCpvsHChecksum];
        }
    std::printf("  [cpvs] re-signed flips: %llu rejected, %llu accepted (lookups stayed in bounds)\n",
                (unsigned long long)rejected, (unsigned long long)accepted);
    EXPECT_GT(rejected, 0u);
}

TEST(CpvsLookup, BaseOffsetPcfAndNormalBias) {
    const uint32_t n = 128;
    DualDepthMap m = boxesMap(n, 71, false, false);
    CpvsBake b = bakeOrDie(m, n);
    const uint32_t base = 1234;
    std::vector<uint32_t> big(base, 0xDEADBEEFu);
    big.insert(big.end(), b.data.begin(), b.data.end());
    Rng r(5);
    for (int i = 0; i < 20000; ++i) {
        int32_t x = int32_t(r.below(n + 20)) - 10, y = int32_t(r.below(n + 20)) - 10,
                s = int32_t(r.below(n + 20)) - 10;
        bool a = cpvsShadowedVoxel(b.data.data(), 0, x, y, s);
        ASSERT_EQ(a, cpvsShadowedVoxel(big.data(), base, x, y, s));
        if (x < 0 || y < 0 || x >= int32_t(n) || y >= int32_t(n)) {
            ASSERT_FALSE(a);
        }
        int32_t nq[3] = {int32_t(r.below(2049)) - 1024, int32_t(r.below(2049)) - 1024,
                         int32_t(r.below(2049)) - 1024};
        int32_t radius = int32_t(r.below(5)), o[3];
        cpvsNormalOffset(nq, radius, o);
        uint32_t lit = 0;
        for (int32_t dy = -radius; dy <= radius; ++dy)
            for (int32_t dx = -radius; dx <= radius; ++dx)
                lit += !cpvsShadowedVoxel(b.data.data(), 0, x + o[0] + dx, y + o[1] + dy, s + o[2]);
        ASSERT_EQ(cpvsPcfLitCount(big.data(), base, x, y, s, nq, radius), lit);
        ASSERT_LE(lit, uint32_t((2 * radius + 1) * (2 * radius + 1)));
    }
    int32_t o[3];
    int32_t up[3] = {0, 0, -1024};
    cpvsNormalOffset(up, 4, o);
    EXPECT_EQ(o[0], 0);
    EXPECT_EQ(o[2], -5);
    int32_t diag[3] = {512, -1024, 0};
    cpvsNormalOffset(diag, 0, o);
    EXPECT_EQ(o[0], 1); // 0.5 rounds away from zero
    EXPECT_EQ(o[1], -1);
    int32_t zero[3] = {0, 0, 0};
    cpvsNormalOffset(zero, 3, o);
    EXPECT_EQ(o[0] | o[1] | o[2], 0);
    // a light-facing normal (toward the light: +z in view space) moves toward the near slices
    float nView[3] = {0.0f, 0.0f, 1.0f};
    int32_t v[3];
    cpvsVoxelNormal(nView, 0.0f, 0.0f, 0.5f, std::log(kFar / kNear), v);
    EXPECT_EQ(v[0], 0);
    EXPECT_EQ(v[2], -1024);
}

// ---------------------------------------------------------------------------------------------------
// Real geometry: dual maps from the CPU rasteriser (shadows/static/raster_dual.h).

std::vector<Light> staticSpots(const Scene& scene, size_t count) {
    std::vector<Light> out;
    for (const Light& l : scene.lights)
        if (l.type == LightKind::Spot && !l.dynamic && out.size() < count) out.push_back(l);
    return out;
}

CpvsBake bakeLight(const DualDepthMap& map, const LightFrustum& f, uint32_t n) {
    CpvsParams p;
    p.resolution = n;
    p.nearPlane = f.nearPlane;
    p.farPlane = f.farPlane;
    auto b = bakeCpvs(map, p);
    EXPECT_TRUE(b.ok()) << b.error();
    return b.ok() ? std::move(*b) : CpvsBake{};
}

// 256^3: every voxel by lookup against cpvsReferenceVoxel; 512^3: every voxel by verifyCpvs's column walk.
void realScene(const char* name, const Scene& scene, size_t lights) {
    CasterTriangles casters = castersFromScene(scene);
    auto spots = staticSpots(scene, lights);
    ASSERT_FALSE(spots.empty());
    for (size_t li = 0; li < spots.size(); ++li) {
        LightFrustum f = spotLightFrustum(spots[li]);
        for (uint32_t n : {256u, 512u}) {
            SCOPED_TRACE(std::string(name) + " light " + std::to_string(li) + " at " + std::to_string(n));
            DualDepthMap map = rasterizeDual(casters, f, n);
            CpvsBake b = bakeLight(map, f, n);
            ASSERT_TRUE(validateCpvs(b.data.data(), b.data.size()).ok());
            CpvsVerifyReport v = verifyCpvs(b.data.data(), map);
            EXPECT_EQ(v.mismatches, 0u);
            EXPECT_EQ(v.checked + v.undefined, uint64_t(n) * n * n);
            if (n == 256) {
                auto space = makeCpvsSpace(n, f.nearPlane, f.farPlane);
                uint64_t wrong = 0, checked = 0;
                for (uint32_t s = 0; s < n; ++s)
                    for (uint32_t y = 0; y < n; ++y)
                        for (uint32_t x = 0; x < n; ++x) {
                            CpvsVoxel r = cpvsReferenceVoxel(*space, map, x, y, s);
                            if (r == CpvsVoxel::Undefined) continue;
                            ++checked;
                            wrong += cpvsShadowedVoxel(b.data.data(), 0, int32_t(x), int32_t(y),
                                                       int32_t(s)) != (r == CpvsVoxel::Shadowed);
                        }
                EXPECT_EQ(wrong, 0u);
                EXPECT_EQ(checked, v.checked);
            }
            std::printf("  [cpvs] %s light %zu: %llu voxels checked, %llu undefined\n", name, li,
                        (unsigned long long)v.checked, (unsigned long long)v.undefined);
            printSize(name, n, b);
        }
    }
}

TEST(CpvsScenes, NightCityExhaustive) {
    auto scene = loadScene("night-city", 64, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    realScene("night-city", *scene, 3);
}

TEST(CpvsScenes, FzkHausExhaustive) {
    auto scene = loadScene(std::string(ML_SOURCE_DIR) + "/../shared/scenes/fzk-haus.glb", 8, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    realScene("fzk-haus", *scene, 2);
}

// Lights whose frustum holds no caster, only casters (the light buried inside a closed box), and a caster
// touching the near plane.
TEST(CpvsScenes, EmptyFullAndNearCasterFrusta) {
    Scene scene;
    Mesh box;
    box.closed = true;
    const glm::vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1},
                            {-1, -1, 1},  {1, -1, 1},  {-1, 1, 1},  {1, 1, 1}};
    for (const auto& p : c) box.vertices.push_back({p, glm::vec3(0.0f)});
    box.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    scene.meshes.push_back(box);
    Instance inst;
    inst.transform = glm::mat4(1.0f);
    scene.instances.push_back(inst);
    CasterTriangles casters = castersFromScene(scene);
    struct Case {
        const char* name;
        glm::vec3 pos, dir;
    };
    const Case cases[] = {
        {"no-caster", {0, 10, 0}, {0, 1, 0}},       // looking away from the box
        {"inside-caster", {0, 0, 0}, {0, -1, 0}},   // the light sits inside the closed box
        {"near-caster", {0, 1.05f, 0}, {0, -1, 0}}, // the box's top 5 cm below: at the near plane
        {"box-below", {0, 4.0f, 0}, {0, -1, 0}},
    };
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        Light l;
        l.position = k.pos;
        l.direction = k.dir;
        l.range = 8.0f;
        l.outerAngle = 0.7f;
        LightFrustum f = spotLightFrustum(l);
        const uint32_t n = 128;
        DualDepthMap map = rasterizeDual(casters, f, n);
        CpvsBake b = bakeLight(map, f, n);
        ASSERT_TRUE(validateCpvs(b.data.data(), b.data.size()).ok());
        CpvsVerifyReport v = verifyCpvs(b.data.data(), map);
        EXPECT_EQ(v.mismatches, 0u);
        EXPECT_EQ(v.checked + v.undefined, uint64_t(n) * n * n);
        printSize(k.name, n, b);
    }
}

// The done criterion, 8K^3 per night-city spotlight: bytes <= 1/256 of a 16-bit 8K^2 map, and
// insert + compress no longer than rendering the maps. Minutes of CPU: runs only with ML_CPVS_BENCH=1
// (ML_CPVS_BENCH_RES and ML_CPVS_BENCH_LIGHTS override 8192 and 4).
TEST(CpvsBench, NightCitySpotlights) {
    const char* on = std::getenv("ML_CPVS_BENCH");
    if (!on || std::string(on) != "1") GTEST_SKIP() << "set ML_CPVS_BENCH=1";
    const char* r = std::getenv("ML_CPVS_BENCH_RES");
    const char* c = std::getenv("ML_CPVS_BENCH_LIGHTS");
    const uint32_t n = r ? uint32_t(std::atoi(r)) : 8192u;
    const size_t count = c ? size_t(std::atoi(c)) : 4u;
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    CasterTriangles casters = castersFromScene(*scene);
    auto spots = staticSpots(*scene, count);
    double bytes = 0, renderMs = 0, dagMs = 0, preMs = 0;
    for (size_t i = 0; i < spots.size(); ++i) {
        LightFrustum f = spotLightFrustum(spots[i]);
        auto t0 = std::chrono::steady_clock::now();
        DualDepthMap map = rasterizeDual(casters, f, n);
        double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        CpvsBake b = bakeLight(map, f, n);
        std::printf(
            "  [cpvs-bench] light %zu: render %.0f ms, precompute %.0f, insert %.0f, compress %.0f, layout "
            "%.0f ms; nodes %llu -> %llu, leaves %llu -> %llu\n",
            i, ms, b.stats.precomputeMs, b.stats.insertMs, b.stats.compressMs, b.stats.layoutMs,
            (unsigned long long)b.stats.nodesInserted, (unsigned long long)b.stats.nodesFinal,
            (unsigned long long)b.stats.leavesInserted, (unsigned long long)b.stats.leavesFinal);
        printSize("night-city", n, b);
        bytes += double(b.stats.bytes.total);
        renderMs += ms;
        dagMs += b.stats.insertMs + b.stats.compressMs;
        preMs += b.stats.precomputeMs;
    }
    const double k = double(spots.size()), mapBytes = 2.0 * n * n;
    std::printf(
        "  [cpvs-bench] %u^3, %zu lights: mean %.0f B = 1/%.1f of a 16-bit map (goal 1/256); mean render "
        "%.0f ms, precompute %.0f ms, insert+compress %.0f ms\n",
        n, spots.size(), bytes / k, mapBytes / (bytes / k), renderMs / k, preMs / k, dagMs / k);
    EXPECT_LE(bytes / k, mapBytes / 256.0);
    EXPECT_LE(dagMs, renderMs);
}

// Global bottom-up vs the region build (section 4.3) on night-city spotlights: per-phase times, peak
// nodes per region and live DAG bytes, and byte equality. ML_CPVS_BENCH=1; ML_CPVS_BENCH_RES (default
// 8192) and ML_CPVS_BENCH_LIGHTS (default 2).
TEST(CpvsBench, RegionsVsGlobal) {
    const char* on = std::getenv("ML_CPVS_BENCH");
    if (!on || std::string(on) != "1") GTEST_SKIP() << "set ML_CPVS_BENCH=1";
    const char* r = std::getenv("ML_CPVS_BENCH_RES");
    const char* c = std::getenv("ML_CPVS_BENCH_LIGHTS");
    const uint32_t n = r ? uint32_t(std::atoi(r)) : 8192u;
    const size_t count = c ? size_t(std::atoi(c)) : 2u;
    auto scene = loadScene("night-city", 256, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    CasterTriangles casters = castersFromScene(*scene);
    auto spots = staticSpots(*scene, count);
    std::map<int, double> sum; // -1 global, else regionLog2: insert + compress
    for (size_t i = 0; i < spots.size(); ++i) {
        LightFrustum f = spotLightFrustum(spots[i]);
        DualDepthMap map = rasterizeDual(casters, f, n);
        CpvsParams p;
        p.resolution = n;
        p.nearPlane = f.nearPlane;
        p.farPlane = f.farPlane;
        p.compression = CpvsCompression::BottomUp;
        auto global = bakeCpvs(map, p);
        ASSERT_TRUE(global.ok());
        auto line = [&](const char* name, const CpvsStats& s) {
            std::printf(
                "  [cpvs-bench] light %zu %u^3 %-10s: precompute %6.0f insert %5.0f compress %5.0f (merge "
                "%4.0f) layout %3.0f ms; %4u regions, peak region nodes %8llu of %8llu, peak live "
                "%6.1f MB, final %llu nodes\n",
                i, n, name, s.precomputeMs, s.insertMs, s.compressMs, s.mergeMs, s.layoutMs, s.regions,
                (unsigned long long)s.regionNodesPeak, (unsigned long long)s.nodesInserted,
                s.liveBytesPeak / 1048576.0, (unsigned long long)s.nodesFinal);
        };
        line("global", global->stats);
        sum[-1] += global->stats.insertMs + global->stats.compressMs;
        p.compression = CpvsCompression::Regions;
        for (uint32_t rl : {1u, 2u, 3u, 4u}) {
            p.regionLog2 = rl;
            auto reg = bakeCpvs(map, p);
            ASSERT_TRUE(reg.ok());
            EXPECT_TRUE(reg->data == global->data);
            char name[32];
            std::snprintf(name, sizeof name, "regions %u", rl);
            line(name, reg->stats);
            sum[int(rl)] += reg->stats.insertMs + reg->stats.compressMs;
        }
    }
    for (const auto& [k, v] : sum)
        std::printf("  [cpvs-bench] %u^3 mean insert+compress %s%d: %.0f ms\n", n,
                    k < 0 ? "global" : "regionLog2 ", k < 0 ? 0 : k, v / double(spots.size()));
}

} // namespace
} // namespace ml
