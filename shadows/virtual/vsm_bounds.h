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

// The part of a world box [lo, hi] (a cluster's receivers) that light L reaches (lightReachesPoint:
// the range sphere and, for a spot, the cone), as a box: the per-pixel pass marks only receivers L
// reaches, so the pages of this box hold theirs. Empty (lo > hi on an axis) when no receiver is reached.
// Sphere: lightReachesPoint's d2 < r * r bounds each rounded square, fl(vx * vx) < fl(r * r), so |vx| < r
// (monotonic) and the real x - p.x < r. Spot (cone of half-angle A, 0.01 < cos A and sin A, every light
// of the scenes): a point v of the sector has v.e <= |v| cos(max(theta - A, 0)) along an axis e at angle
// theta from the axis d, i.e. per axis r * (d.e >= cos A ? 1 : max(d.e cos A + |d x e| sin A, 0)). The
// rounding of the cone test (its cosine off by under 1e-6) widens A by under 4e-6 rad at sin A >= 0.01;
// 1e-3 rad is added (the support grows by at most the added angle). The positional slack, |p| * 1e-5 +
// 1e-4 m, holds the rounding of x - p and of the sums here. Exact where the light is directional.
ML_STRUCT(VsmBox) {
    vec3 lo;
    vec3 hi;
};
ML_FN vec2 vsmReachAxis(float p, float r, float d, float cosA, float sinA, bool cone, float lo, float hi) {
    ML_PRECISE float s = sqrt(max(1.0f - d * d, 0.0f));
    ML_PRECISE float up = (!cone || d >= cosA) ? 1.0f : max(d * cosA + s * sinA, 0.0f);
    ML_PRECISE float down = (!cone || -d >= cosA) ? 1.0f : max(s * sinA - d * cosA, 0.0f);
    ML_PRECISE float slack = abs(p) * 1e-5f + 1e-4f;
    ML_PRECISE float a = p - (r * (down + 1e-3f) + slack);
    ML_PRECISE float b = p + (r * (up + 1e-3f) + slack);
    return vec2(max(lo, a), min(hi, b));
}
ML_FN VsmBox vsmReachBox(GpuLight L, vec3 lo, vec3 hi) {
    VsmBox b;
    b.lo = lo;
    b.hi = hi;
    if (L.info.x == ML_LIGHT_DIRECTIONAL) return b;
    ML_PRECISE float cosA = L.directionCosOuter.w, sinA = L.colorSinOuter.w;
    bool cone = L.info.x == ML_LIGHT_SPOT && cosA > 0.01f && sinA > 0.01f;
    ML_PRECISE float r = L.positionRange.w;
    vec2 x = vsmReachAxis(L.positionRange.x, r, L.directionCosOuter.x, cosA, sinA, cone, lo.x, hi.x);
    vec2 y = vsmReachAxis(L.positionRange.y, r, L.directionCosOuter.y, cosA, sinA, cone, lo.y, hi.y);
    vec2 z = vsmReachAxis(L.positionRange.z, r, L.directionCosOuter.z, cosA, sinA, cone, lo.z, hi.z);
    b.lo = vec3(x.x, y.x, z.x);
    b.hi = vec3(x.y, y.y, z.y);
    return b;
}
ML_FN bool vsmBoxEmpty(VsmBox b) {
    return !(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z);
}

// Half `side` (0 low, 1 high) of a box cut across its longest axis at its midpoint. Every point of the
// box lies in one half or in both (each half is closed at the cut, wherever the midpoint rounds to), so
// the pages of both halves hold every receiver's. The bounds of a half are tighter where the light's
// projection couples the axes (a box long in light depth: vsmBoxTaps pairs its nearest depth with its
// widest offsets), and a half may face away from the light where the whole does not.
ML_FN VsmBox vsmHalfBox(VsmBox b, uint side) {
    ML_PRECISE float ex = b.hi.x - b.lo.x, ey = b.hi.y - b.lo.y, ez = b.hi.z - b.lo.z;
    VsmBox h = b;
    if (ex >= ey && ex >= ez) {
        ML_PRECISE float m = b.lo.x + ex * 0.5f;
        if (side == 0u)
            h.hi.x = m;
        else
            h.lo.x = m;
    } else if (ey >= ez) {
        ML_PRECISE float m = b.lo.y + ey * 0.5f;
        if (side == 0u)
            h.hi.y = m;
        else
            h.lo.y = m;
    } else {
        ML_PRECISE float m = b.lo.z + ez * 0.5f;
        if (side == 0u)
            h.hi.z = m;
        else
            h.lo.z = m;
    }
    return h;
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

// The light-view box vb of a perspective map narrowed in depth to the receivers that pick `mip`
// (vsmPickMip of texel0 = 2 z params.x / R against footprints in [fp.x, fp.y]). A pick of mip m > 0 needs
// fl(fp / t0) >= 2^m, so fp / t0 >= 2^m (1 - 2^-24) and z <= fp.y R / (2^(m+1) params.x) (1 + 4e-7); a
// pick of m < mips - 1 needs fp / t0 < 2^(m+1), so z > fp.x R / (2^(m+2) params.x) (1 - 3e-7). The
// factors 1.0001 and 0.9999 hold those and the rounding here. Receivers far from the light pick fine
// mips, near ones coarse mips: the fine mips, the most pages per side, lose the near receivers, whose
// taps spread widest. Empty (lo.z > hi.z) when no receiver of the box picks `mip`.
ML_FN VsmViewBox vsmMipBox(GpuVsmMap map, VsmViewBox vb, vec2 fp, uint resolution, uint mip, uint mips) {
    VsmViewBox b = vb;
    ML_PRECISE float k = float(resolution) / (2.0f * map.params.x); // light depth per metre of texel0
    if (mip > 0u) {
        ML_PRECISE float zMax = fp.y * k / float(1u << mip) * 1.0001f;
        b.lo.z = max(b.lo.z, -zMax);
    }
    if (mip + 1u < mips) {
        ML_PRECISE float zMin = fp.x * k / float(2u << mip) * 0.9999f;
        b.hi.z = min(b.hi.z, -zMin);
    }
    return b;
}

// The part of a world box [lo, hi] where a receiver's footprint (vsmFootprint) can lie below fpMax:
// fl(fl(sqrt(S)) * perMetre) < fpMax needs |P - camera| < fpMax / perMetre (1 + 4e-7), so on each axis
// |P.x - camera.x| is below that too. The 1.0001 and the positional slack |camera| * 1e-5 + 1e-4 m hold
// it and the rounding of P - camera. A mip (clip level) m below the last is picked only where the
// footprint is under 2^(m+1) texel0, so its taps come from this box with fpMax = 2^(m+1) texel0max:
// the fine mips take the receivers near the camera only.
ML_FN VsmBox vsmNearBox(vec3 camera, vec3 lo, vec3 hi, float fpMax, float perMetre) {
    ML_PRECISE float d = fpMax / perMetre * 1.0001f;
    ML_PRECISE float sx = d + (abs(camera.x) * 1e-5f + 1e-4f);
    ML_PRECISE float sy = d + (abs(camera.y) * 1e-5f + 1e-4f);
    ML_PRECISE float sz = d + (abs(camera.z) * 1e-5f + 1e-4f);
    VsmBox b;
    b.lo = vec3(max(lo.x, camera.x - sx), max(lo.y, camera.y - sy), max(lo.z, camera.z - sz));
    b.hi = vec3(min(hi.x, camera.x + sx), min(hi.y, camera.y + sy), min(hi.z, camera.z + sz));
    return b;
}

// A directional light's clip level `level` below the last is taken only by receivers whose matched
// level (vsmPickLevel) is that one or finer, whose footprint is under 2^(level+1) times level 0's texel
// (vsmPickLevel's operations): vsmNearBox of that. The whole box at the last level.
ML_FN VsmBox vsmLevelBox(GpuVsmMap level0, vec3 camera, vec3 lo, vec3 hi, float perMetre, uint resolution,
                         uint level, uint levels) {
    VsmBox b;
    b.lo = lo;
    b.hi = hi;
    if (level + 1u >= levels) return b;
    ML_PRECISE float t = 2.0f * level0.params.x / float(resolution);
    ML_PRECISE float fpMax = t * float(2u << level);
    return vsmNearBox(camera, lo, hi, fpMax, perMetre);
}

// The receivers of a perspective map's box that pick `mip`: vsmMipBox's depth range, then, below the
// last mip, the part of the world box [lo, hi] near enough to the camera (vsmNearBox with the largest
// texel0 of that depth range, vsmTexel0's operations), in the light's view. Empty (some lo > hi) when
// no receiver picks `mip`.
ML_FN VsmViewBox vsmMipView(GpuVsmMap map, VsmViewBox vb, vec3 lo, vec3 hi, vec3 camera, vec2 fp,
                            float perMetre, uint resolution, uint mip, uint mips) {
    VsmViewBox b = vsmMipBox(map, vb, fp, resolution, mip, mips);
    if (mip + 1u >= mips || !(b.lo.z <= b.hi.z)) return b;
    ML_PRECISE float zFar = -b.lo.z;
    ML_PRECISE float t0Far = 2.0f * (zFar * map.params.x) / float(resolution);
    ML_PRECISE float fpMax = t0Far * float(2u << mip);
    VsmBox w = vsmNearBox(camera, lo, hi, fpMax, perMetre);
    if (vsmBoxEmpty(w)) {
        b.lo.z = 1.0f; // no receiver: lo.z > hi.z
        b.hi.z = 0.0f;
        return b;
    }
    VsmViewBox n = vsmViewBox(map.view, w.lo, w.hi);
    b.lo = vec3(max(b.lo.x, n.lo.x), max(b.lo.y, n.lo.y), max(b.lo.z, n.lo.z));
    b.hi = vec3(min(b.hi.x, n.hi.x), min(b.hi.y, n.hi.y), min(b.hi.z, n.hi.z));
    return b;
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
