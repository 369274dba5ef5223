// Light bounds tests and pixel reconstruction, one source for GLSL and the C++ references.
//
// The culling reference (cullReference in culling/culling.cpp) compiles these very functions, so CPU and GPU
// agree bit for bit as long as both evaluate the same IEEE operations in the same order: every
// intermediate is `precise` in GLSL (no contraction to fma, no reassociation) and the C++ build uses
// -ffp-contract=off. Only +, -, *, /, sqrt, min and max appear: all correctly rounded on both sides.
#ifndef ML_LIGHT_MATH_H
#define ML_LIGHT_MATH_H

#include "shaders/shared/gpu_types.h"

#ifdef __cplusplus
#include <cmath>
namespace ml::gpu {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
#define ML_FN inline
#define ML_PRECISE
using std::abs;
using std::floor;
using std::sqrt;
inline float max(float a, float b) {
    return a > b ? a : b;
}
inline float min(float a, float b) {
    return a < b ? a : b;
}
#else
#define ML_FN
#define ML_PRECISE precise
#endif

// Squared distance from p to the box [lo, hi] (0 inside).
ML_FN float boxDistanceSq(vec3 lo, vec3 hi, vec3 p) {
    ML_PRECISE float dx = max(max(lo.x - p.x, p.x - hi.x), 0.0f);
    ML_PRECISE float dy = max(max(lo.y - p.y, p.y - hi.y), 0.0f);
    ML_PRECISE float dz = max(max(lo.z - p.z, p.z - hi.z), 0.0f);
    ML_PRECISE float d2 = dx * dx + dy * dy + dz * dz;
    return d2;
}

// The 8 planes of an octagonal pyramid circumscribing a spot light's cone (lightTouchesBox): through
// the apex, each tangent to the cone along a generator (normal n = sin(a) d - cos(a) u for a unit u
// perpendicular to d). They depend on the light only, so the assignment passes compute them once per
// light; lightTouchesBox computes them per call, with the same operations, so the results are equal.
ML_STRUCT(ConePlanes) {
    vec3 n[8];
};

ML_FN ConePlanes conePlanes(GpuLight L) {
    ConePlanes planes;
    ML_PRECISE float cosA = L.directionCosOuter.w, sinA = L.colorSinOuter.w;
    ML_PRECISE float dx = L.directionCosOuter.x, dy = L.directionCosOuter.y, dz = L.directionCosOuter.z;
    // e1 = normalize(cross(ref, d)), ref the world axis least aligned with d; e2 = cross(d, e1).
    bool useX = dx * dx < 0.5f;
    ML_PRECISE float cx = useX ? 0.0f : -dz, cy = useX ? -dz : 0.0f, cz = useX ? dy : dx;
    ML_PRECISE float cinv = 1.0f / sqrt(cx * cx + cy * cy + cz * cz);
    ML_PRECISE float e1x = cx * cinv, e1y = cy * cinv, e1z = cz * cinv;
    ML_PRECISE float e2x = dy * e1z - dz * e1y, e2y = dz * e1x - dx * e1z, e2z = dx * e1y - dy * e1x;
    for (int k = 0; k < 8; ++k) {
        // cos and sin of k * 45 degrees, as literals so both languages use the same values.
        float ck = (k == 0)             ? 1.0f
                   : (k == 4)           ? -1.0f
                   : (k == 2 || k == 6) ? 0.0f
                   : (k == 1 || k == 7) ? 0.70710678f
                                        : -0.70710678f;
        float sk = (k == 2)             ? 1.0f
                   : (k == 6)           ? -1.0f
                   : (k == 0 || k == 4) ? 0.0f
                   : (k == 1 || k == 3) ? 0.70710678f
                                        : -0.70710678f;
        ML_PRECISE float nx = sinA * dx - cosA * (ck * e1x + sk * e2x);
        ML_PRECISE float ny = sinA * dy - cosA * (ck * e1y + sk * e2y);
        ML_PRECISE float nz = sinA * dz - cosA * (ck * e1z + sk * e2z);
        planes.n[k] = vec3(nx, ny, nz);
    }
    return planes;
}

// Conservative: false only when no point of the box [lo, hi] can receive light from L (planes =
// conePlanes(L)). Range: exact sphere-box distance. Spot cone: cone against the box's bounding sphere
// (the closest-point form of the cone-sphere test: the sphere is outside when its centre lies farther
// than its radius from the cone's surface, or wholly behind the apex), then the octagonal pyramid:
// the box is outside when its farthest corner along some plane normal is behind that plane. Much
// tighter than the bounding sphere for the flat, wide boxes of ground clusters.
ML_FN bool lightTouchesBoxWith(GpuLight L, ConePlanes planes, vec3 lo, vec3 hi) {
    if (L.info.x == ML_LIGHT_DIRECTIONAL) return true;
    vec3 p = vec3(L.positionRange.x, L.positionRange.y, L.positionRange.z);
    ML_PRECISE float r = L.positionRange.w;
    if (boxDistanceSq(lo, hi, p) > r * r) return false;
    if (L.info.x != ML_LIGHT_SPOT) return true;
    ML_PRECISE float ex = (hi.x - lo.x) * 0.5f, ey = (hi.y - lo.y) * 0.5f, ez = (hi.z - lo.z) * 0.5f;
    // A little slack so rounding in the test can never cull a box that a pixel test would accept.
    ML_PRECISE float radius = sqrt(ex * ex + ey * ey + ez * ez) * 1.0001f + 1e-4f;
    ML_PRECISE float vx = lo.x + ex - p.x, vy = lo.y + ey - p.y, vz = lo.z + ez - p.z;
    ML_PRECISE float vlen2 = vx * vx + vy * vy + vz * vz;
    ML_PRECISE float v1 =
        vx * L.directionCosOuter.x + vy * L.directionCosOuter.y + vz * L.directionCosOuter.z;
    ML_PRECISE float cosA = L.directionCosOuter.w, sinA = L.colorSinOuter.w;
    ML_PRECISE float distToCone = cosA * sqrt(max(vlen2 - v1 * v1, 0.0f)) - v1 * sinA;
    if (distToCone > radius) return false;
    if (cosA >= 0.0f && v1 < -radius) return false;
    for (int k = 0; k < 8; ++k) {
        ML_PRECISE float nx = planes.n[k].x, ny = planes.n[k].y, nz = planes.n[k].z;
        ML_PRECISE float far = nx * ((nx > 0.0f ? hi.x : lo.x) - p.x) +
                               ny * ((ny > 0.0f ? hi.y : lo.y) - p.y) +
                               nz * ((nz > 0.0f ? hi.z : lo.z) - p.z);
        if (far < -1e-3f) return false; // 1 mm of slack against rounding
    }
    return true;
}

ML_FN bool lightTouchesBox(GpuLight L, vec3 lo, vec3 hi) {
    return lightTouchesBoxWith(L, conePlanes(L), lo, hi);
}

// A light's footprint in the cluster grid: tiles [x0, x1] x [y0, y1] (tiles = x0, y0, x1, y1; empty
// when x0 > x1) and the linear view depths [depth.x, depth.y] of every point the light can reach
// (lightReachesPoint), conservatively. Directional lights cover the whole grid.
ML_STRUCT(LightFootprint) {
    uvec4 tiles;
    vec4 depth;
};

// The light's volume (range sphere; for a spot also the cone capped flat at the range: apex plus a disk
// of radius r tan(outer) at distance r along the axis, which holds the spherical sector) is bounded in
// the affine coordinates (x_clip, y_clip, w) = rows 0, 1, 3 of viewProj, where w is the linear view
// depth. Clipping that box at w = near keeps it a box (camera inside the volume included), and x/w,
// y/w are extreme at its corners. Slack: 1e-4 of the magnitudes on the box, one pixel on the
// rectangle (a pixel's reconstructed point projects within far less than 0.5 px of its centre), 0.1 %
// on depth (pixels' linear depth and the point's w differ by rounding only). The same function runs in
// the shader and in the CPU reference, so both visit the same clusters.
ML_FN LightFootprint lightFootprint(GpuLight L, mat4 vp, uvec4 size, uint tileSize, float nearPlane) {
    LightFootprint f;
    f.tiles = uvec4(0u, 0u, size.z - 1u, size.w - 1u);
    f.depth = vec4(0.0f, 3.0e38f, 0.0f, 0.0f);
    if (L.info.x == ML_LIGHT_DIRECTIONAL) return f;
    ML_PRECISE float px = L.positionRange.x, py = L.positionRange.y, pz = L.positionRange.z;
    ML_PRECISE float r = L.positionRange.w;
    ML_PRECISE float dx = L.directionCosOuter.x, dy = L.directionCosOuter.y, dz = L.directionCosOuter.z;
    ML_PRECISE float cosA = L.directionCosOuter.w, sinA = L.colorSinOuter.w;
    bool cone = L.info.x == ML_LIGHT_SPOT && cosA > 0.01f;
    ML_PRECISE float disk = cone ? r * sinA / cosA : 0.0f;
    ML_PRECISE float lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        int row = k == 2 ? 3 : k;
        ML_PRECISE float mx = vp[0][row], my = vp[1][row], mz = vp[2][row], mt = vp[3][row];
        ML_PRECISE float c = mx * px + my * py + mz * pz + mt;
        ML_PRECISE float m2 = mx * mx + my * my + mz * mz;
        ML_PRECISE float mlen = sqrt(m2);
        ML_PRECISE float slack = 1e-4f * (mlen * (abs(px) + abs(py) + abs(pz) + r) + abs(mt));
        ML_PRECISE float a = c - r * mlen - slack;
        ML_PRECISE float b = c + r * mlen + slack;
        if (cone) {
            ML_PRECISE float md = mx * dx + my * dy + mz * dz;
            ML_PRECISE float dc = c + r * md;
            ML_PRECISE float ext = disk * sqrt(max(m2 - md * md, 0.0f));
            a = max(a, min(c, dc - ext) - slack);
            b = min(b, max(c, dc + ext) + slack);
        }
        lo[k] = a;
        hi[k] = b;
    }
    ML_PRECISE float wNear = max(lo[2], nearPlane);
    ML_PRECISE float wFar = hi[2];
    if (wFar < nearPlane) {
        f.tiles = uvec4(1u, 1u, 0u, 0u);
        return f;
    }
    f.depth = vec4(wNear * 0.999f, wFar * 1.001f, 0.0f, 0.0f);
    ML_PRECISE float x0 = lo[0] / (lo[0] < 0.0f ? wNear : wFar);
    ML_PRECISE float x1 = hi[0] / (hi[0] > 0.0f ? wNear : wFar);
    ML_PRECISE float y0 = lo[1] / (lo[1] < 0.0f ? wNear : wFar);
    ML_PRECISE float y1 = hi[1] / (hi[1] > 0.0f ? wNear : wFar);
    // Pixel i's centre is at NDC (i + 0.5) / W * 2 - 1 (worldFromPixel).
    ML_PRECISE float W = float(size.x), H = float(size.y), T = float(tileSize);
    ML_PRECISE float tx0 = floor(((x0 + 1.0f) * 0.5f * W - 1.0f) / T);
    ML_PRECISE float tx1 = floor(((x1 + 1.0f) * 0.5f * W + 1.0f) / T);
    ML_PRECISE float ty0 = floor(((y0 + 1.0f) * 0.5f * H - 1.0f) / T);
    ML_PRECISE float ty1 = floor(((y1 + 1.0f) * 0.5f * H + 1.0f) / T);
    ML_PRECISE float maxX = float(size.z - 1u), maxY = float(size.w - 1u);
    if (!(tx1 >= 0.0f && ty1 >= 0.0f && tx0 <= maxX && ty0 <= maxY)) {
        f.tiles = uvec4(1u, 1u, 0u, 0u);
        return f;
    }
    f.tiles = uvec4(uint(max(tx0, 0.0f)), uint(max(ty0, 0.0f)), uint(min(tx1, maxX)), uint(min(ty1, maxY)));
    return f;
}

// Exact: does the light's cone and range contain the point x? (The shading is zero outside.)
ML_FN bool lightReachesPoint(GpuLight L, vec3 x) {
    if (L.info.x == ML_LIGHT_DIRECTIONAL) return true;
    ML_PRECISE float vx = x.x - L.positionRange.x, vy = x.y - L.positionRange.y, vz = x.z - L.positionRange.z;
    ML_PRECISE float d2 = vx * vx + vy * vy + vz * vz;
    ML_PRECISE float r = L.positionRange.w;
    if (!(d2 < r * r)) return false;
    if (L.info.x != ML_LIGHT_SPOT) return true;
    ML_PRECISE float c = vx * L.directionCosOuter.x + vy * L.directionCosOuter.y + vz * L.directionCosOuter.z;
    ML_PRECISE float cosA = L.directionCosOuter.w;
    // c / |v| > cosA without a division or square root of d2.
    if (cosA >= 0.0f) return c > 0.0f && c * c > cosA * cosA * d2;
    return c >= 0.0f || c * c < cosA * cosA * d2;
}

// The cube face of a point light that direction d (light -> point) falls in: 0 +X, 1 -X, 2 +Y, 3 -Y,
// 4 +Z, 5 -Z; the largest |component| wins, ties go to the earlier axis. Each face's 90-degree frustum
// (pointLightFaceFrustum) covers exactly its directions.
ML_FN uint pointLightFace(vec3 d) {
    float ax = d.x < 0.0f ? -d.x : d.x, ay = d.y < 0.0f ? -d.y : d.y, az = d.z < 0.0f ? -d.z : d.z;
    if (ax >= ay && ax >= az) return d.x >= 0.0f ? 0u : 1u;
    if (ay >= az) return d.y >= 0.0f ? 2u : 3u;
    return d.z >= 0.0f ? 4u : 5u;
}

// Linear view depth from a depth-buffer value of the camera's reversed-Z projection (Vulkan zero-to-one,
// d = 1 at the near plane, 0 at the far plane): d = n (f - z) / (z (f - n)), so z = n f / (n + d (f - n)).
// depthParams = (n, f, n f, f - n). Reversed Z keeps a D32F value's relative precision (2^-24) in
// metres-per-metre at every distance: standard Z (d -> 1 far away) puts centimetres of error on
// receivers 100-200 m from a 0.1 m near plane (docs/accuracy.md, section 1).
ML_FN float linearDepth(float d, vec4 depthParams) {
    ML_PRECISE float z = depthParams.z / (depthParams.x + d * depthParams.w);
    return z;
}

// A depth-buffer value that holds geometry: the reversed-Z buffer is cleared to 0 (the far plane and
// beyond, i.e. the sky).
ML_FN bool hasSurface(float d) {
    return d > 0.0f;
}

// World position of pixel (px, py) at depth-buffer value d (reversed Z: no cancellation near d = 1). The
// matrix product is written out so both languages sum the terms in the same order.
ML_FN vec3 worldFromPixel(uint px, uint py, float d, mat4 invViewProj, uvec4 size) {
    ML_PRECISE float nx = (float(px) + 0.5f) / float(size.x) * 2.0f - 1.0f;
    ML_PRECISE float ny = (float(py) + 0.5f) / float(size.y) * 2.0f - 1.0f;
    ML_PRECISE float X =
        invViewProj[0][0] * nx + invViewProj[1][0] * ny + invViewProj[2][0] * d + invViewProj[3][0];
    ML_PRECISE float Y =
        invViewProj[0][1] * nx + invViewProj[1][1] * ny + invViewProj[2][1] * d + invViewProj[3][1];
    ML_PRECISE float Z =
        invViewProj[0][2] * nx + invViewProj[1][2] * ny + invViewProj[2][2] * d + invViewProj[3][2];
    ML_PRECISE float W =
        invViewProj[0][3] * nx + invViewProj[1][3] * ny + invViewProj[2][3] * d + invViewProj[3][3];
    return vec3(X / W, Y / W, Z / W);
}

#ifdef __cplusplus
} // namespace ml::gpu
#endif
#endif
