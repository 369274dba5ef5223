// Page marking per cluster (vsm_mark_cluster.comp, its CPU twin vsmMarkClusterReference): bounds of
// what the lookups of every receiver inside a world box [lo, hi] can read in one map. One source for
// GLSL and C++, like vsm_math.h, whose per-receiver functions these bound.
//
// Why the bounds need no margin: the per-receiver functions (vsmPoint, vsmFootprint, vsmPickMip,
// vsmLocate) are chains of `precise` +, -, *, /, sqrt and floor, each correctly rounded (lavapipe, and
// the C++ build with -ffp-contract=off), and a correctly rounded operation is monotonic in each argument:
// a <= a' gives fl(a + b) <= fl(a' + b), fl(m * a) <= fl(m * a') for m >= 0, and so on. Evaluating the
// same chain, in the same order, at the argument that makes each operand smallest (largest) therefore
// bounds the value every receiver of the box computes, exactly. The normal too: the cluster's normal
// bounds (shaders/shared/cluster_receivers.h) give each light-view component of vsmDirection's result a
// range (vsmNormalViewBox, the same argument), and the offset's length factor is bounded by its value at
// the box's far end, with 1/1000 to spare; the texel rectangle is then still widened by one texel, so that a
// device whose division is not correctly rounded (GLSL allows 2.5 ulp) cannot step past it.
#ifndef ML_VSM_BOUNDS_H
#define ML_VSM_BOUNDS_H

#include "shaders/shared/cluster_receivers.h"
#include "shadows/virtual/vsm_math.h"

// A cluster-light pair whose bounds reach more pages than this (lookups and fallback reservations, before
// the coverage test) marks from its receivers one by one instead (vsm_mark_cluster.comp), so that a box
// straddling a cube's faces or grazing a spot's near plane does not mark whole mips. Refinement walks the
// tile's 64 pixels in one invocation, so a low threshold costs more than the pages it saves: on the
// night city at 640x360, 4 and 2 made the mark pass 2-5x slower than 16, and with the receiver and normal
// bounds 4 doubled it indoors; 8 marks 1-3 % fewer pages than 16 at no measured cost
// (docs/virtual-shadow-maps.md, "Receiver bounds and normal bounds"; docs/results/log.md, "Virtual
// shadow maps: marking per cluster").
#define ML_VSM_CLUSTER_PAGES 8u

#ifdef __cplusplus
namespace ml::gpu {
using ivec4 = glm::ivec4;
#endif

// The light-view box of a world box: per row of vsmPoint, each term at the corner coordinate that makes
// it smallest (lo) or largest (hi), summed in vsmPoint's order.
ML_STRUCT(VsmViewBox) {
    vec3 lo;
    vec3 hi;
};
ML_FN vec2 vsmRowRange(float m0, float m1, float m2, float m3, vec3 lo, vec3 hi) {
    ML_PRECISE float a = m0 * (m0 >= 0.0f ? lo.x : hi.x) + m1 * (m1 >= 0.0f ? lo.y : hi.y) +
                         m2 * (m2 >= 0.0f ? lo.z : hi.z) + m3;
    ML_PRECISE float b = m0 * (m0 >= 0.0f ? hi.x : lo.x) + m1 * (m1 >= 0.0f ? hi.y : lo.y) +
                         m2 * (m2 >= 0.0f ? hi.z : lo.z) + m3;
    return vec2(a, b);
}
ML_FN VsmViewBox vsmViewBox(mat4 m, vec3 lo, vec3 hi) {
    vec2 x = vsmRowRange(m[0][0], m[1][0], m[2][0], m[3][0], lo, hi);
    vec2 y = vsmRowRange(m[0][1], m[1][1], m[2][1], m[3][1], lo, hi);
    vec2 z = vsmRowRange(m[0][2], m[1][2], m[2][2], m[3][2], lo, hi);
    VsmViewBox b;
    b.lo = vec3(x.x, y.x, z.x);
    b.hi = vec3(x.y, y.y, z.y);
    return b;
}

// vsmFootprint's smallest and largest value over the box: per axis the smallest and largest |P - camera|.
ML_FN vec2 vsmFootprintRange(vec3 camera, vec3 lo, vec3 hi, float perMetre) {
    ML_PRECISE float lx = lo.x - camera.x, ly = lo.y - camera.y, lz = lo.z - camera.z;
    ML_PRECISE float hx = hi.x - camera.x, hy = hi.y - camera.y, hz = hi.z - camera.z;
    ML_PRECISE float nx = lx > 0.0f ? lx : (hx < 0.0f ? -hx : 0.0f);
    ML_PRECISE float ny = ly > 0.0f ? ly : (hy < 0.0f ? -hy : 0.0f);
    ML_PRECISE float nz = lz > 0.0f ? lz : (hz < 0.0f ? -hz : 0.0f);
    ML_PRECISE float fx = max(-lx, hx), fy = max(-ly, hy), fz = max(-lz, hz);
    ML_PRECISE float fNear = sqrt(nx * nx + ny * ny + nz * nz) * perMetre;
    ML_PRECISE float fFar = sqrt(fx * fx + fy * fy + fz * fz) * perMetre;
    return vec2(fNear, fFar);
}

// The range of vsmDirection(m, N) over unit normals N in [nlo, nhi]: vsmRowRange with no translation
// (adding m3 = 0 changes no sum).
ML_FN VsmViewBox vsmNormalViewBox(mat4 m, vec3 nlo, vec3 nhi) {
    vec2 x = vsmRowRange(m[0][0], m[1][0], m[2][0], 0.0f, nlo, nhi);
    vec2 y = vsmRowRange(m[0][1], m[1][1], m[2][1], 0.0f, nlo, nhi);
    vec2 z = vsmRowRange(m[0][2], m[1][2], m[2][2], 0.0f, nlo, nhi);
    VsmViewBox b;
    b.lo = vec3(x.x, y.x, z.x);
    b.hi = vec3(x.y, y.y, z.y);
    return b;
}

// The mips a perspective map's lookups of the box pick (vsmPickMip over the box; x > y: none, when no
// receiver lies beyond the near plane, where vsmChoose finds no tap). Receivers with a tap have
// light depth z in (near, -vb.lo.z]: texel0 is smallest at the near plane and largest at the far end.
ML_FN uvec2 vsmBoxMips(GpuVsmMap map, VsmViewBox vb, vec2 footprint, uint resolution, uint mips) {
    ML_PRECISE float zFar = -vb.lo.z;
    if (!(zFar > map.params.y)) return uvec2(1u, 0u);
    ML_PRECISE float zNear = max(-vb.hi.z, map.params.y);
    ML_PRECISE float t0Near = 2.0f * (zNear * map.params.x) / float(resolution);
    ML_PRECISE float t0Far = 2.0f * (zFar * map.params.x) / float(resolution);
    return uvec2(vsmPickMip(t0Far, footprint.x, mips), vsmPickMip(t0Near, footprint.y, mips));
}

// The taps (vsmLocate's texel, before the PCF kernel) of the box's receivers at `mip` of `map`, widened
// by one texel: texels lo = (x, y), hi = (z, w). ok = 0 when no receiver of the box has a tap there
// (all outside the map or before its near plane); held = 1 when every receiver has one (vsmChoose stops
// at such a clip level).
ML_STRUCT(VsmTapRect) {
    ivec4 texels;
    uint ok;
    uint held;
};
ML_FN VsmTapRect vsmBoxTaps(GpuVsmMap map, uint resolution, uint mip, VsmViewBox vb, VsmViewBox nb) {
    VsmTapRect r;
    r.texels = ivec4(0, 0, -1, -1);
    r.ok = 0u;
    r.held = 0u;
    uint res = resolution >> mip;
    bool ortho = map.info.x == ML_VSM_ORTHOGRAPHIC;
    // The normal offset: vn * texelWorld * bias.y, texelWorld that of the mip at the receiver's depth, at
    // most that of the box's far end (+ rounding: the 1.001); vn's light-view components lie in nb. The
    // factor texelWorld * bias.y lies in [0, offset] (bias.y >= 0) or [-offset, 0], so per axis the
    // offset lies in [min(v.lo, 0), max(v.hi, 0)] * offset, v = nb or -nb.
    ML_PRECISE float zFar = ortho ? 0.0f : -vb.lo.z;
    if (!ortho && !(zFar > map.params.y)) return r;
    ML_PRECISE float extent = ortho ? map.params.x : zFar * map.params.x;
    ML_PRECISE float texelWorld = 2.0f * extent / float(res);
    ML_PRECISE float offset = texelWorld * abs(map.bias.y) * 1.001f;
    bool flip = map.bias.y < 0.0f;
    ML_PRECISE float vxLo = flip ? -nb.hi.x : nb.lo.x, vxHi = flip ? -nb.lo.x : nb.hi.x;
    ML_PRECISE float vyLo = flip ? -nb.hi.y : nb.lo.y, vyHi = flip ? -nb.lo.y : nb.hi.y;
    ML_PRECISE float vzLo = flip ? -nb.hi.z : nb.lo.z, vzHi = flip ? -nb.lo.z : nb.hi.z;
    ML_PRECISE float oxLo = min(vxLo, 0.0f) * offset, oxHi = max(vxHi, 0.0f) * offset;
    ML_PRECISE float oyLo = min(vyLo, 0.0f) * offset, oyHi = max(vyHi, 0.0f) * offset;
    ML_PRECISE float ozLo = min(vzLo, 0.0f) * offset, ozHi = max(vzHi, 0.0f) * offset;
    ML_PRECISE float qxLo = vb.lo.x + oxLo, qxHi = vb.hi.x + oxHi;
    ML_PRECISE float qyLo = vb.lo.y + oyLo, qyHi = vb.hi.y + oyHi;
    // zq = -(vp.z + vn.z * offset) > near for a tap (perspective).
    ML_PRECISE float zqFar = -(vb.lo.z + ozLo);
    if (!ortho && !(zqFar > map.params.y)) return r;
    ML_PRECISE float zqNear = max(-(vb.hi.z + ozHi), map.params.y);
    ML_PRECISE float sNear = ortho ? map.params.x : zqNear * map.params.x;
    ML_PRECISE float sFar = ortho ? map.params.x : zqFar * map.params.x;
    // q / scale over q in [qLo, qHi] and scale in [sNear, sFar] (both > 0): the extremes are at the corners.
    ML_PRECISE float nxLo = min(qxLo / sNear, qxLo / sFar), nxHi = max(qxHi / sNear, qxHi / sFar);
    ML_PRECISE float nyLo = min(qyLo / sNear, qyLo / sFar), nyHi = max(qyHi / sNear, qyHi / sFar);
    ML_PRECISE float fxLo = (nxLo * 0.5f + 0.5f) * float(res), fxHi = (nxHi * 0.5f + 0.5f) * float(res);
    ML_PRECISE float fyLo = (nyLo * 0.5f + 0.5f) * float(res), fyHi = (nyHi * 0.5f + 0.5f) * float(res);
    // vsmLocate keeps taps with 0 <= f < res only.
    if (!(fxHi >= 0.0f && fyHi >= 0.0f && fxLo < float(res) && fyLo < float(res))) return r;
    ML_PRECISE float cx0 = max(fxLo, -1.0f), cy0 = max(fyLo, -1.0f);
    ML_PRECISE float cx1 = min(fxHi, float(res)), cy1 = min(fyHi, float(res));
    r.texels = ivec4(int(floor(cx0)) - 1, int(floor(cy0)) - 1, int(floor(cx1)) + 1, int(floor(cy1)) + 1);
    r.ok = 1u;
    r.held = (fxLo >= 1.0f && fyLo >= 1.0f && fxHi < float(res) - 1.0f && fyHi < float(res) - 1.0f) ? 1u : 0u;
    return r;
}

// Pages (lo = (x, y), hi = (z, w); pages per side of the mip: s0 >> mip) under the tap texels shifted
// `levels` mips coarser (vsmCoarserTap) and widened by `radius` texels, clamped to the map.
ML_FN ivec4 vsmRectPages(ivec4 texels, uint levels, int radius, uint resolution, uint mip, uint pageShift) {
    int res = int(resolution >> mip);
    int x0 = (texels.x < 0 ? 0 : (texels.x >> int(levels))) - radius;
    int y0 = (texels.y < 0 ? 0 : (texels.y >> int(levels))) - radius;
    int x1 = (texels.z >> int(levels)) + radius, y1 = (texels.w >> int(levels)) + radius;
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > res - 1 ? res - 1 : x1;
    y1 = y1 > res - 1 ? res - 1 : y1;
    int s = int(pageShift);
    return ivec4(x0 >> s, y0 >> s, x1 >> s, y1 >> s);
}
ML_FN uint vsmRectPageCount(ivec4 pages) {
    if (pages.z < pages.x || pages.w < pages.y) return 0u;
    return uint(pages.z - pages.x + 1) * uint(pages.w - pages.y + 1);
}

// Whether no receiver of the world box [lo, hi] whose unit normal lies in the box [nlo, nhi] (a cluster's
// ClusterReceivers) faces light L by vsmFacesLight's rule, so that the cluster marks nothing for L. Per
// receiver, vsmFacesLight takes d = L - P (rounded: monotonic, so each component lies in
// [fl(L - hi), fl(L - lo)]) or the directional d, and N (vsmNormalize: inside [nlo, nhi]). u below is
// the largest N.d over both boxes (per axis the largest of the four corner products), off by at most
// 3.1e-7 * |d|max from its rounding; vsmFacesLight's own n.d is off by as little. So when u < -2e-3 *
// |d|max, every receiver's computed n.d is below -1.99e-3 |d|, its square past the rule's 1e-6 |d|^2
// (with 4x to spare), and vsmFacesLight returns false: the per-pixel pass marks nothing for L there.
ML_FN bool vsmBoxFacesAway(GpuLight L, vec3 lo, vec3 hi, vec3 nlo, vec3 nhi) {
    ML_PRECISE float ax, ay, az, bx, by, bz; // d's range per axis
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        ax = -L.directionCosOuter.x, ay = -L.directionCosOuter.y, az = -L.directionCosOuter.z;
        bx = ax, by = ay, bz = az;
    } else {
        ax = L.positionRange.x - hi.x, ay = L.positionRange.y - hi.y, az = L.positionRange.z - hi.z;
        bx = L.positionRange.x - lo.x, by = L.positionRange.y - lo.y, bz = L.positionRange.z - lo.z;
    }
    ML_PRECISE float ux = max(max(nlo.x * ax, nlo.x * bx), max(nhi.x * ax, nhi.x * bx));
    ML_PRECISE float uy = max(max(nlo.y * ay, nlo.y * by), max(nhi.y * ay, nhi.y * by));
    ML_PRECISE float uz = max(max(nlo.z * az, nlo.z * bz), max(nhi.z * az, nhi.z * bz));
    ML_PRECISE float u = ux + uy + uz;
    ML_PRECISE float mx = max(abs(ax), abs(bx)), my = max(abs(ay), abs(by)), mz = max(abs(az), abs(bz));
    ML_PRECISE float dmax = sqrt(mx * mx + my * my + mz * mz);
    return u < -2e-3f * dmax;
}

// The normal bounds of a cluster's receivers (cluster_receivers.h codes), for vsmBoxFacesAway.
ML_FN vec3 vsmNormalLo(ClusterReceivers r) {
    return vec3(clusterNormalBound(r.normalLo, 0u), clusterNormalBound(r.normalLo, 1u),
                clusterNormalBound(r.normalLo, 2u));
}
ML_FN vec3 vsmNormalHi(ClusterReceivers r) {
    return vec3(clusterNormalBound(r.normalHi, 0u), clusterNormalBound(r.normalHi, 1u),
                clusterNormalBound(r.normalHi, 2u));
}

#ifdef __cplusplus
} // namespace ml::gpu
#endif

#endif
