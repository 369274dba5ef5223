// Helpers of the CPVS tests (tests/static/cpvs_*_test.cpp): synthetic dual depth maps (per texel a list of
// closed intervals and open surfaces), the bake wrapper and the exhaustive voxel check of a baked DAG against
// the voxelisation derived directly from the map. See shadows/static/cpvs.h.
#pragma once
#include "shadows/static/cpvs.h"
#include "shadows/static/raster_dual.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace ml::ctest {

inline constexpr float kNear = 0.1f, kFar = 20.0f;
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

inline float logDepth(Rng& r) {
    return kNear * std::pow(kFar / kNear, r.uniform(0.0f, 1.0f));
}

inline DualDepthMap boxesMap(uint32_t n, uint32_t seed, bool allClosed, bool allOpen) {
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

inline DualDepthMap slopesMap(uint32_t n) {
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

inline DualDepthMap noiseMap(uint32_t n, uint32_t seed) {
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

inline DualDepthMap islandsMap(uint32_t n, uint32_t seed) {
    MapMaker m(n);
    Rng r(seed);
    for (uint32_t i = 0; i < n * 2; ++i) {
        uint32_t x = r.below(n), y = r.below(n);
        float z = logDepth(r);
        m.add(x, y, m.q(z), m.q(z * 1.3f), r.below(2) == 0);
    }
    return m.build();
}

inline DualDepthMap uniformMap(uint32_t n, uint32_t enter, uint32_t exit) {
    DualDepthMap m;
    m.resolution = n;
    m.enter.assign(size_t(n) * n, enter);
    m.exit.assign(size_t(n) * n, exit);
    return m;
}

// Casters touching and crossing the near plane, at exact slice thresholds, at and past far, and a texel
// whose closed object never exits (exit = kDepthEmpty).
inline DualDepthMap nearPlaneMap(uint32_t n) {
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

inline CpvsBake bakeOrDie(const DualDepthMap& map, uint32_t n, uint32_t gridLog2 = 4,
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

inline void printSize(const char* name, uint32_t n, const CpvsBake& b) {
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
inline void exhaustive(const char* name, const DualDepthMap& map, uint32_t n, uint32_t gridLog2 = 4,
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

} // namespace ml::ctest
