// CPVS voxel space, the direct voxelisation of the dual depth maps, and the precompute of the paper's
// section 3.4 / 6.1 (per-tile visibility masks with re-use depths, min-max hierarchy). See cpvs.h.
#include "shadows/static/cpvs.h"
#include "shadows/static/cpvs_internal.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

namespace ml {

namespace {

// Upper bound of the depths a slice holds (its far boundary); the last slice takes every depth.
inline uint32_t sliceHi(const CpvsSpace& space, uint32_t s) {
    return s + 1 < space.resolution ? space.thresholds[s + 1] : 0xFFFFFFFEu;
}

} // namespace

Result<CpvsSpace> makeCpvsSpace(uint32_t resolution, float nearPlane, float farPlane, CpvsSlicing slicing) {
    if (resolution < kCpvsMinResolution || resolution > kCpvsMaxResolution ||
        !std::has_single_bit(resolution))
        return fail("cpvs: resolution " + std::to_string(resolution) + " is not a power of two in [64, " +
                    std::to_string(kCpvsMaxResolution) + "]");
    if (!(nearPlane > 0.0f) || !(farPlane > nearPlane) || !std::isfinite(farPlane))
        return fail("cpvs: need 0 < near < far, got near " + std::to_string(nearPlane) + " far " +
                    std::to_string(farPlane));
    CpvsSpace space;
    space.resolution = resolution;
    space.log2Resolution = uint32_t(std::countr_zero(resolution));
    space.nearPlane = nearPlane;
    space.farPlane = farPlane;
    space.slicing = slicing;
    if (slicing != CpvsSlicing::Log && slicing != CpvsSlicing::Linear)
        return fail("cpvs: unknown slicing " + std::to_string(uint32_t(slicing)));
    space.thresholds.resize(resolution + 1);
    // z_s = near * (far/near)^(s/N), quantised like quantizeDepth but from the double value, so T does
    // not inherit float rounding of z_s. Only ratio far/near and N matter: lights sharing both could
    // share the table.
    const double n = nearPlane, f = farPlane, logRatio = std::log(f / n);
    for (uint32_t s = 0; s <= resolution; ++s) {
        // Linear: z_s = near + (far - near) s / N (directional lights); log: eq. 1.
        double z = slicing == CpvsSlicing::Linear ? n + (f - n) * double(s) / double(resolution)
                                                  : n * std::exp(logRatio * double(s) / double(resolution));
        double t = z / f;
        uint32_t q = t >= 1.0 ? 0xFFFFFFFEu : (t > 0.0 ? uint32_t(t * 4294967294.0) : 0u);
        space.thresholds[s] = s == resolution ? 0xFFFFFFFEu : q;
    }
    for (uint32_t s = 1; s <= resolution; ++s) // guard against exp() rounding: keep T non-decreasing
        space.thresholds[s] = std::max(space.thresholds[s], space.thresholds[s - 1]);
    return space;
}

uint32_t cpvsSliceOf(const CpvsSpace& space, uint32_t depth) {
    const auto& t = space.thresholds;
    // first s in [1, N) with T[s] >= depth; the slice is one less (N - 1 when none)
    auto it = std::lower_bound(t.begin() + 1, t.begin() + space.resolution, depth);
    return uint32_t(it - t.begin()) - 1u;
}

int64_t cpvsEquation1(double z, uint32_t resolution, double nearPlane, double farPlane) {
    return int64_t(std::ceil(double(resolution) * std::log(z / nearPlane) / std::log(farPlane / nearPlane)));
}

CpvsVoxel cpvsReferenceVoxel(const CpvsSpace& space, const DualDepthMap& map, uint32_t x, uint32_t y,
                             uint32_t s) {
    size_t i = size_t(y) * map.resolution + x;
    uint32_t enter = map.enter[i], exit = std::max(map.exit[i], enter);
    if (space.thresholds[s] <= enter) return CpvsVoxel::Lit;   // representative depth not behind the caster
    if (sliceHi(space, s) < exit) return CpvsVoxel::Undefined; // every receiver inside closed geometry
    return CpvsVoxel::Shadowed;
}

CpvsColumn cpvsReferenceColumn(const CpvsSpace& space, uint32_t enter, uint32_t exit) {
    const auto& t = space.thresholds;
    const uint32_t n = space.resolution;
    exit = std::max(exit, enter);
    CpvsColumn c;
    c.litEnd = uint32_t(std::upper_bound(t.begin(), t.begin() + n, enter) - t.begin()); // first T[s] > enter
    if (c.litEnd == n) {
        c.shadowBegin = n;
        return c;
    }
    // first s with sliceHi(s) >= exit: T[s + 1] >= exit for s < N - 1, the last slice takes any depth
    uint32_t j = uint32_t(std::lower_bound(t.begin() + 1, t.begin() + n, exit) - t.begin());
    uint32_t s = j < n ? j - 1 : (exit <= 0xFFFFFFFEu ? n - 1 : n);
    c.shadowBegin = std::max(c.litEnd, s);
    return c;
}

namespace cpvs_detail {

void precomputeBlock(const CpvsSpace& space, const uint32_t* enter, const uint32_t* exit, uint32_t width,
                     uint32_t height, size_t stride, CpvsPrecompute& pre) {
    const uint32_t n = space.resolution;
    uint32_t a[64], b[64];
    for (uint32_t ty = 0; ty < height / 8; ++ty) {
        for (uint32_t tx = 0; tx < width / 8; ++tx) {
            pre.stepFirst.push_back(uint32_t(pre.stepStart.size()));
            const size_t first = pre.stepStart.size();
            for (uint32_t ly = 0; ly < 8; ++ly) {
                size_t row = size_t(ty * 8 + ly) * stride + tx * 8;
                for (uint32_t lx = 0; lx < 8; ++lx) {
                    CpvsColumn c = cpvsReferenceColumn(space, enter[row + lx], exit[row + lx]);
                    a[ly * 8 + lx] = c.litEnd;
                    b[ly * 8 + lx] = c.shadowBegin;
                }
            }
            // Section 3.4: all lit up to the nearest slice where some cell must be shadowed; there take
            // the mask shadowing every cell that may be shadowed (a <= s), re-use it until a cell outside
            // it must be shadowed, repeat. Each step adds the cell that forced it, so <= 64 steps, and the
            // number of masks is minimal (greedy interval cover).
            uint64_t cur = 0;
            uint32_t lastStart = n;
            for (;;) {
                uint32_t s = n;
                for (uint32_t i = 0; i < 64; ++i)
                    if (!((cur >> i) & 1u)) s = std::min(s, b[i]);
                if (s >= n) break;
                uint64_t m = cur;
                for (uint32_t i = 0; i < 64; ++i)
                    if (a[i] <= s) m |= uint64_t(1) << i;
                pre.stepStart.push_back(s);
                pre.stepMask.push_back(m);
                cur = m;
                lastStart = s;
                if (cur == ~uint64_t(0)) break;
            }
            bool any = pre.stepStart.size() > first;
            pre.minT[0].push_back(any ? pre.stepStart[first] : n);
            pre.maxT[0].push_back(cur == ~uint64_t(0) ? lastStart : n);
        }
    }
}

void precomputeEmpty(const CpvsSpace& space, size_t tiles, CpvsPrecompute& pre) {
    // an empty texel is lit in every slice (enter = kDepthEmpty is past every threshold): no step
    pre.stepFirst.insert(pre.stepFirst.end(), tiles, uint32_t(pre.stepStart.size()));
    pre.minT[0].insert(pre.minT[0].end(), tiles, space.resolution);
    pre.maxT[0].insert(pre.maxT[0].end(), tiles, space.resolution);
}

void precomputeAppend(CpvsPrecompute& pre, const CpvsPrecompute& part) {
    const uint32_t base = uint32_t(pre.stepStart.size());
    for (uint32_t f : part.stepFirst) pre.stepFirst.push_back(base + f);
    pre.stepStart.insert(pre.stepStart.end(), part.stepStart.begin(), part.stepStart.end());
    pre.stepMask.insert(pre.stepMask.end(), part.stepMask.begin(), part.stepMask.end());
    pre.minT[0].insert(pre.minT[0].end(), part.minT[0].begin(), part.minT[0].end());
    pre.maxT[0].insert(pre.maxT[0].end(), part.maxT[0].begin(), part.maxT[0].end());
}

void precomputeFinish(CpvsPrecompute& pre, uint32_t topSize) {
    const uint32_t tiles = pre.tiles;
    pre.stepFirst.push_back(uint32_t(pre.stepStart.size()));
    for (uint32_t size = 16, k = 1; size <= topSize; size *= 2, ++k) {
        uint32_t w = tiles >> k, pw = tiles >> (k - 1);
        pre.minT.emplace_back(size_t(w) * w);
        pre.maxT.emplace_back(size_t(w) * w);
        const auto &pmin = pre.minT[k - 1], &pmax = pre.maxT[k - 1];
        for (uint32_t y = 0; y < w; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                size_t p0 = size_t(2 * y) * pw + 2 * x, p1 = p0 + pw;
                pre.minT[k][size_t(y) * w + x] = std::min({pmin[p0], pmin[p0 + 1], pmin[p1], pmin[p1 + 1]});
                pre.maxT[k][size_t(y) * w + x] = std::max({pmax[p0], pmax[p0 + 1], pmax[p1], pmax[p1 + 1]});
            }
    }
}

} // namespace cpvs_detail

Result<CpvsPrecompute> cpvsPrecompute(const CpvsSpace& space, const DualDepthMap& map, uint32_t topSize) {
    const uint32_t n = space.resolution;
    if (map.resolution != n || map.enter.size() != size_t(n) * n || map.exit.size() != size_t(n) * n)
        return fail("cpvs: dual depth map is " + std::to_string(map.resolution) + "^2 with " +
                    std::to_string(map.enter.size()) + " enter / " + std::to_string(map.exit.size()) +
                    " exit texels, expected " + std::to_string(n) + "^2");
    if (topSize < 8 || topSize > n || !std::has_single_bit(topSize))
        return fail("cpvs: hierarchy top size " + std::to_string(topSize) + " invalid");
    CpvsPrecompute pre;
    pre.resolution = n;
    pre.tiles = n / 8;
    const size_t tiles = size_t(pre.tiles) * pre.tiles;
    pre.stepFirst.reserve(tiles + 1);
    pre.minT.emplace_back();
    pre.maxT.emplace_back();
    pre.minT[0].reserve(tiles);
    pre.maxT[0].reserve(tiles);
    pre.stepStart.reserve(tiles);
    pre.stepMask.reserve(tiles);
    cpvs_detail::precomputeBlock(space, map.enter.data(), map.exit.data(), n, n, n, pre);
    cpvs_detail::precomputeFinish(pre, topSize);
    return pre;
}

bool cpvsResolvedShadowed(const CpvsPrecompute& pre, uint32_t x, uint32_t y, uint32_t s) {
    size_t tile = size_t(y / 8) * pre.tiles + x / 8;
    uint32_t bit = (x & 7u) + 8u * (y & 7u);
    uint64_t mask = 0;
    for (uint32_t j = pre.stepFirst[tile]; j < pre.stepFirst[tile + 1] && pre.stepStart[j] <= s; ++j)
        mask = pre.stepMask[j];
    return (mask >> bit) & 1u;
}

} // namespace ml
