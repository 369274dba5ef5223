// Virtual shadow map addressing, one source for GLSL (vsm_mark.comp, the lookup in the evaluation pass,
// vsm_probe.comp) and the C++ references (shadows/virtual/vsm_reference.cpp): which map, mip and texel
// a receiver reads, and the depth it compares. Marking and lookup call the same functions, so every page
// a lookup touches was marked (fallback reservations excepted: vsmCoarserTap). As in
// shaders/shared/light_math.h, only +, -, *, /, sqrt, floor, min and max appear, every intermediate is
// `precise` in GLSL and the C++ build uses -ffp-contract=off, so the CPU reference picks the same pages bit
// for bit.
//
// Resolution matching (RMVSM, Sakmary & Bittner 2025, section 3; clustered marking is its future work):
// a pixel at distance d from the camera covers footprint = d * 2 tan(fovY/2) / height metres. A
// perspective map's mip-m texel at light depth z covers 2 z tan(fov/2) / (R >> m) metres; the lookup
// takes the coarsest mip whose texel is still no larger than the pixel (mip 0 when even that is larger).
// A directional light's clip level L covers a square of half extent h0 * 2^L around the camera; the
// lookup takes the coarsest level whose texel is no larger than the pixel and which holds the point.
//
// Bias (the same as the static methods, shaders/static/static_pcf.h): the receiver moves along
// its normal by one texel of the chosen mip, and compares with a further half texel of depth; per light
// (GpuVsmMap.bias, LightDesc::shadowNormalBias / shadowDepthBias) the offset is scaled and the depth
// bias set (the defaults 1 and 0.5 give these values exactly).
#ifndef ML_VSM_MATH_H
#define ML_VSM_MATH_H

#include "shaders/shared/light_math.h"
#include "shadows/virtual/vsm_types.h"

#ifdef __cplusplus
namespace ml::gpu {
using ivec2 = glm::ivec2;
using std::floor;
#endif

// Pages per side of mip m, and the first entry of mip m inside a map (mips stacked finest first).
ML_FN uint vsmPagesPerSide(uint s0, uint mip) {
    return s0 >> mip;
}
ML_FN uint vsmMipOffset(uint s0, uint mip) {
    uint offset = 0u;
    for (uint m = 0u; m < mip; ++m) offset += (s0 >> m) * (s0 >> m);
    return offset;
}
ML_FN uint vsmEntry(uint entriesPerMap, uint s0, uint map, uint mip, uint px, uint py) {
    return map * entriesPerMap + vsmMipOffset(s0, mip) + py * (s0 >> mip) + px;
}

// Hierarchical page buffer (RMVSM section 4.3, Fig. 9): for each mip m of a map, levels l = 1..log2(S_m)
// of (S_m >> l)^2 cells, each the OR of the DIRTY bits of the 2^l x 2^l pages under it. Stored as bits in
// one buffer (vsm_hpb.comp sets them from the request list), VsmConstants.order.w words per map slot, so
// the number of maps is bounded by memory only (an image array would be bounded by maxImageArrayLayers).
// Inside a map, level l is a grid of width S_0 >> (l - 1) and height S_0 >> l, levels one after another;
// the mips of a map lie side by side: mip m's cells of level l start at column vsmHpbColumn(S_0, m) >> l,
// row 0. Bits outside every mip's cells stay 0.
ML_FN uint vsmHpbColumn(uint s0, uint mip) {
    uint column = 0u;
    for (uint m = 0u; m < mip; ++m) column += s0 >> m;
    return column;
}
// First bit of level l inside a map's HPB bits (level 1 at 0); vsmHpbLevelOffset(s0, log2(s0) + 1) bits
// in all.
ML_FN uint vsmHpbLevelOffset(uint s0, uint level) {
    uint offset = 0u;
    for (uint k = 1u; k < level; ++k) offset += (s0 >> (k - 1u)) * (s0 >> k);
    return offset;
}
// Bit of cell (cx, cy) of level l of mip m, inside its map's HPB bits.
ML_FN uint vsmHpbBit(uint s0, uint mip, uint level, uint cx, uint cy) {
    return vsmHpbLevelOffset(s0, level) + cy * (s0 >> (level - 1u)) + (vsmHpbColumn(s0, mip) >> level) + cx;
}

// Written out so both languages sum in the same order.
ML_FN vec3 vsmPoint(mat4 m, vec3 p) {
    ML_PRECISE float x = m[0][0] * p.x + m[1][0] * p.y + m[2][0] * p.z + m[3][0];
    ML_PRECISE float y = m[0][1] * p.x + m[1][1] * p.y + m[2][1] * p.z + m[3][1];
    ML_PRECISE float z = m[0][2] * p.x + m[1][2] * p.y + m[2][2] * p.z + m[3][2];
    return vec3(x, y, z);
}
ML_FN vec3 vsmDirection(mat4 m, vec3 d) {
    ML_PRECISE float x = m[0][0] * d.x + m[1][0] * d.y + m[2][0] * d.z;
    ML_PRECISE float y = m[0][1] * d.x + m[1][1] * d.y + m[2][1] * d.z;
    ML_PRECISE float z = m[0][2] * d.x + m[1][2] * d.y + m[2][2] * d.z;
    return vec3(x, y, z);
}
ML_FN vec3 vsmNormalize(vec3 n) {
    ML_PRECISE float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (!(len > 0.0f)) return vec3(0.0f, 0.0f, 0.0f);
    ML_PRECISE float x = n.x / len, y = n.y / len, z = n.z / len;
    return vec3(x, y, z);
}
// A light's pixel footprint per metre of distance: VsmConstants.camera.x (2 tan(fovY/2)
// / height / VsmSettings::texelsPerPixel) halved e times, e = int(GpuVsmMap.info.z) of the light's first
// map, log2 of LightDesc::shadowTexelScale (-2..3; 0 in a map built without one). Halving and doubling are
// exact, so the lookup, the per-pixel marks and the cluster bounds all see this one value.
ML_FN float vsmPerMetre(float perMetre, GpuVsmMap first) {
    int e = int(first.info.z);
    ML_PRECISE float f = perMetre;
    for (int i = 0; i < e; ++i) f = f * 0.5f;
    for (int i = 0; i > e; --i) f = f * 2.0f;
    return f;
}
// Pixel footprint in metres at world point P (perMetre: vsmPerMetre's).
ML_FN float vsmFootprint(vec3 cameraPosition, vec3 P, float perMetre) {
    ML_PRECISE float dx = P.x - cameraPosition.x, dy = P.y - cameraPosition.y, dz = P.z - cameraPosition.z;
    ML_PRECISE float f = sqrt(dx * dx + dy * dy + dz * dz) * perMetre;
    return f;
}

// Whether a receiver (unit normal N, or 0 when the stored normal was degenerate) faces light L closely
// enough that the evaluation may look its shadow up. Both shading models (shading.h, brdf.h) return zero
// for n.l <= 0 and the evaluation then skips the lookup, so pages wanted only by back-facing receivers
// are never read: marking skips them (vsm_mark, its CPU twin, the probe). The rule keeps a margin: a
// receiver is skipped only when n.l < -1e-3 (0.06 degrees past grazing), so the evaluation's own
// rounding of n.l (not `precise`) never finds an unmarked page; squared to stay exact on both sides.
ML_FN bool vsmFacesLight(GpuLight L, vec3 P, vec3 N) {
    ML_PRECISE float dx, dy, dz;
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        dx = -L.directionCosOuter.x, dy = -L.directionCosOuter.y, dz = -L.directionCosOuter.z;
    } else {
        dx = L.positionRange.x - P.x, dy = L.positionRange.y - P.y, dz = L.positionRange.z - P.z;
    }
    ML_PRECISE float nd = N.x * dx + N.y * dy + N.z * dz;
    if (nd >= 0.0f) return true;
    ML_PRECISE float d2 = dx * dx + dy * dy + dz * dz;
    ML_PRECISE float margin = 1e-6f * d2;
    ML_PRECISE float nd2 = nd * nd;
    return nd2 < margin;
}

// The float quantisation of shaders/static/static_pcf.h (staticQuantize) and vsm_draw.frag: linear depth over
// [0, far] to 32 bits (4294967040 is the largest float below 2^32).
ML_FN uint vsmQuantize(float z, float farPlane) {
    ML_PRECISE float t = min(max(z / farPlane, 0.0f), 1.0f);
    if (t >= 1.0f) return 0xFFFFFFFEu;
    ML_PRECISE float s = t * 4294967040.0f;
    return uint(s);
}

// One lookup position: texel of the mip and the depth to compare (ok = false: outside the map, lit).
ML_STRUCT(VsmTap) {
    ivec2 texel;
    uint depth;
    uint ok;
};

// Texel size in metres at mip 0 for a receiver at light-view position vp.
ML_FN float vsmTexel0(GpuVsmMap map, vec3 vp, uint resolution) {
    ML_PRECISE float extent = map.info.x == ML_VSM_ORTHOGRAPHIC ? map.params.x : (-vp.z) * map.params.x;
    ML_PRECISE float t = 2.0f * extent / float(resolution);
    return t;
}

// The resolution-matched mip of a perspective map: the largest m with texel0 * 2^m <= footprint.
ML_FN uint vsmPickMip(float texel0, float footprint, uint mips) {
    ML_PRECISE float ratio = footprint / texel0;
    uint m = 0u;
    while (m + 1u < mips && ratio >= float(1u << (m + 1u))) ++m;
    return m;
}

// Biased lookup position of world point P (unit normal N) in `map` at `mip`.
ML_FN VsmTap vsmLocate(GpuVsmMap map, uint resolution, uint mip, vec3 P, vec3 N) {
    VsmTap tap;
    tap.texel = ivec2(0, 0);
    tap.depth = 0u;
    tap.ok = 0u;
    vec3 vp = vsmPoint(map.view, P);
    vec3 vn = vsmDirection(map.view, N);
    uint res = resolution >> mip;
    bool ortho = map.info.x == ML_VSM_ORTHOGRAPHIC;
    ML_PRECISE float z = -vp.z;
    if (!ortho && !(z > map.params.y)) return tap;
    ML_PRECISE float extent = ortho ? map.params.x : z * map.params.x;
    ML_PRECISE float texelWorld = 2.0f * extent / float(res);
    ML_PRECISE float offset = texelWorld * map.bias.y;
    ML_PRECISE float qx = vp.x + vn.x * offset, qy = vp.y + vn.y * offset, qz = vp.z + vn.z * offset;
    ML_PRECISE float zq = -qz;
    if (!ortho && !(zq > map.params.y)) return tap;
    ML_PRECISE float scale = ortho ? map.params.x : zq * map.params.x;
    ML_PRECISE float nx = qx / scale, ny = qy / scale;
    ML_PRECISE float fx = (nx * 0.5f + 0.5f) * float(res), fy = (ny * 0.5f + 0.5f) * float(res);
    // Outside the map (with the light's cone, nothing there is lit by it anyway): lit.
    if (!(fx >= 0.0f && fy >= 0.0f && fx < float(res) && fy < float(res))) return tap;
    tap.texel = ivec2(int(floor(fx)), int(floor(fy)));
    ML_PRECISE float dz = max(zq - map.bias.x * texelWorld, 0.0f);
    tap.depth = vsmQuantize(dz, map.params.z);
    tap.ok = 1u;
    return tap;
}

// A perspective map's fallback reservation (vsm_common.glsl's vsmMarkReceiver): the tap `levels` mips
// coarser, as the fine tap's texel shifted, without the coarser mip's own normal offset (no second
// projection per receiver and light), with a kernel widened by vsmFallbackSlack so that it holds the
// coarser lookup's own tap. Should a page still differ, the lookup's chain goes on coarser; its last step,
// the coarsest mip, is one page per map, which every reserving receiver of the map reserves.
// Texels the coarser lookup's tap may lie from the shifted one: its normal offset (bias.y texels of
// that mip) rounded up, plus one for the shifted fine offset and the floor.
ML_FN int vsmFallbackSlack(GpuVsmMap map) {
    return int(-floor(-max(map.bias.y, 0.0f))) + 1; // ceil, from the functions listed above
}
ML_FN VsmTap vsmCoarserTap(VsmTap tap, uint levels) {
    VsmTap t = tap;
    t.texel = ivec2(int(uint(tap.texel.x) >> levels), int(uint(tap.texel.y) >> levels));
    return t;
}

// Directional lights: the clip level a receiver wants (before checking that the level holds it). A clip
// level is orthographic, so its texel (vsmTexel0's orthographic case, the same operations) is one size
// over the level: no projection of the receiver.
ML_FN uint vsmPickLevel(GpuVsmMap level0, float footprint, uint resolution, uint levels) {
    ML_PRECISE float t = 2.0f * level0.params.x / float(resolution);
    return vsmPickMip(t, footprint, levels);
}

#ifdef __cplusplus
} // namespace ml::gpu
#endif

#endif
