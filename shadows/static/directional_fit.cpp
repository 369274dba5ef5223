// What a fitted directional record spends where (bake_file.h, DirectionalFit): the share of
// its texels inside the box's light-space rectangle, of its depth slices inside the box's slab along
// the light, and of the slices its casters span. Everything is read from the record: the frustum's
// half sides and margin give the rectangle and the slab (directionalLightFrustum), the data the casters.
#include "shadows/static/bake_file.h"

#include <algorithm>
#include <cmath>

namespace ml {

namespace {

// Centres of `count` texels of a grid of n over [-half, half] that lie in [lo, hi].
uint64_t centresInside(uint32_t count, uint32_t n, double half, double lo, double hi) {
    uint64_t in = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const double c = ((double(i) + 0.5) / double(n) * 2.0 - 1.0) * half;
        in += c >= lo && c <= hi;
    }
    return in;
}

// CPVS: the first shadowed slice of column (x, y), n if none (columns are step functions, cpvs.h).
uint32_t firstShadowed(const uint32_t* d, uint32_t n, uint32_t x, uint32_t y) {
    uint32_t lo = 0, hi = n; // answer in [lo, hi]
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (cpvsShadowedVoxel(d, 0, int32_t(x), int32_t(y), int32_t(mid)))
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

} // namespace

Result<DirectionalFit> directionalFit(const BakeRecord& r) {
    const LightFrustum& f = r.frustum;
    if (!f.fitted())
        return fail("record of light " + std::to_string(r.light) + " is not a fitted directional one");
    const uint32_t n = r.resolution;
    if (n == 0 || r.data.empty()) return fail("directional record without data");
    DirectionalFit fit;
    fit.width = n, fit.rows = f.mapRows(n);
    const double h = f.orthoHalf, hy = f.orthoHalfY, m = f.fitMargin;
    fit.extentX = 2.0 * (h - m), fit.extentY = 2.0 * (hy - m);
    fit.slabNear = double(f.nearPlane) + m, fit.slabFar = double(f.farPlane) - m;
    // Rectangle: view x in [-h + m, h - m], y in [-h + m, -h + 2 hy - m]; texel centres are separable.
    const uint64_t inX = centresInside(n, n, h, -h + m, h - m);
    const uint64_t inY = centresInside(fit.rows, n, h, -h + m, -h + 2.0 * hy - m);
    fit.texelsInBox = double(inX) * double(inY) / (double(n) * double(fit.rows));

    const double nearZ = f.nearPlane, farZ = f.farPlane, depth = farZ - nearZ;
    const uint32_t* d = r.data.data();
    if (r.method == StaticMethod::CPVS) {
        // The stored thresholds: slice s holds (T[s], T[s+1]] (cpvs.h).
        const uint32_t* t = d + d[kCpvsHThresholds];
        const uint32_t qa = quantizeDepth(float(fit.slabNear), f.farPlane),
                       qb = quantizeDepth(float(fit.slabFar), f.farPlane);
        uint32_t in = 0;
        for (uint32_t s = 0; s < n; ++s) in += t[s] >= qa && t[s + 1] <= qb;
        fit.depthSlicesInBox = double(in) / n;
        // A column first shadowed at slice t has its caster in slice t - 1 (that voxel's near boundary is
        // not behind it, the next one's is).
        uint32_t lo = n, hi = 0;
        for (uint32_t y = 0; y < fit.rows; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const uint32_t s = firstShadowed(d, n, x, y);
                if (s >= n) continue;
                const uint32_t c = s > 0 ? s - 1 : 0;
                lo = std::min(lo, c), hi = std::max(hi, c);
            }
        fit.casterSlices = lo <= hi ? double(hi - lo + 1) / n : 0.0;
        return fit;
    }
    // Depth methods: N equal parts of [near, far], the stored depth of each texel in the rows.
    uint32_t in = 0;
    for (uint32_t s = 0; s < n; ++s) {
        const double a = nearZ + depth * s / n, b = nearZ + depth * (s + 1) / n;
        in += a >= fit.slabNear && b <= fit.slabFar;
    }
    fit.depthSlicesInBox = double(in) / n;
    auto sliceOf = [&](uint32_t q) {
        const double z = double(q) / 4294967294.0 * farZ;
        return uint32_t(std::clamp(std::floor((z - nearZ) / depth * n), 0.0, double(n - 1)));
    };
    uint32_t lo = n, hi = 0;
    for (uint32_t y = 0; y < fit.rows; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const uint32_t q = lookupStaticDepth(r.method, d, 0, x, y);
            if (q == kDepthEmpty) continue;
            lo = std::min(lo, sliceOf(q)), hi = std::max(hi, sliceOf(q));
        }
    fit.casterSlices = lo <= hi ? double(hi - lo + 1) / n : 0.0;
    return fit;
}

} // namespace ml
