// CPU reference dual depth rasteriser; the rules (clipping, fixed point, tie rule, hit walk) are in
// raster_dual.h.
#include "shadows/static/raster_dual.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <unordered_map>
#include <cmath>

namespace ml {

namespace {

constexpr int64_t kSub = 256;  // sub-texel steps per texel
constexpr double kGuard = 2.0; // guard band, NDC units

using V3 = glm::dvec3;

bool lexLess(const V3& a, const V3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

// Clips a convex polygon against f(v) >= 0. The intersection point of an edge is computed from its
// end points in lexicographic order, so both triangles that share the edge get the same point.
template <class F> void clipPolygon(std::vector<V3>& poly, std::vector<V3>& tmp, F f) {
    tmp.clear();
    size_t n = poly.size();
    for (size_t i = 0; i < n; ++i) {
        V3 a = poly[i], b = poly[(i + 1) % n];
        double fa = f(a), fb = f(b);
        if (fa >= 0.0) tmp.push_back(a);
        if ((fa >= 0.0) != (fb >= 0.0)) {
            if (lexLess(b, a)) std::swap(a, b), std::swap(fa, fb);
            double t = fa / (fa - fb);
            tmp.push_back(a + (b - a) * t);
        }
    }
    poly.swap(tmp);
}

int64_t floorDiv(int64_t a, int64_t b) {
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// raster_dual.h step 4, orthographic maps: the plane through the triangle's three light-space points
// (texel coordinates u, v with texel centres at integers, quantised depth D), in double from the world
// positions, so parallel triangles get the same slopes. False when the triangle is edge-on, steeper than
// 2^25 units a texel (|Dx| < 2^31, DAG-MH's int32 slope words) or its plane at texel (0, 0) lies past
// 2^60 units (a vertex far outside the map); Tri::depth's int64 sum then stays below 2^61.
bool orthoDepthPlane(const glm::mat4& view, const glm::vec3* p, double orthoHalf, uint32_t res, double far,
                     int64_t& A, int64_t& Dx, int64_t& Dy) {
    const glm::dmat4 v(view);
    double u[3], w[3], D[3];
    for (int k = 0; k < 3; ++k) {
        const glm::dvec4 q = v * glm::dvec4(glm::dvec3(p[k]), 1.0);
        u[k] = (q.x / orthoHalf + 1.0) * 0.5 * double(res) - 0.5;
        w[k] = (q.y / orthoHalf + 1.0) * 0.5 * double(res) - 0.5;
        D[k] = -q.z / far * 4294967294.0;
    }
    const double du1 = u[1] - u[0], dw1 = w[1] - w[0], du2 = u[2] - u[0], dw2 = w[2] - w[0];
    const double det = du1 * dw2 - du2 * dw1;
    if (!(std::abs(det) > 1e-9)) return false;
    const double dD1 = D[1] - D[0], dD2 = D[2] - D[0];
    const double sx = (dD1 * dw2 - dD2 * dw1) / det, sy = (dD2 * du1 - dD1 * du2) / det;
    constexpr double kMaxSlope = 33554432.0; // 2^25 units a texel
    if (!(std::abs(sx) < kMaxSlope && std::abs(sy) < kMaxSlope)) return false;
    const double a = D[0] - sx * u[0] - sy * w[0];
    if (!(std::abs(a) < 1152921504606846976.0)) return false; // 2^60
    A = std::llround(a);
    constexpr double kFraction = double(1u << kOrthoSlopeFractionBits);
    Dx = std::llround(sx * kFraction), Dy = std::llround(sy * kFraction);
    return std::abs(Dx) <= INT32_MAX && std::abs(Dy) <= INT32_MAX;
}

struct PlaneHash {
    size_t operator()(const DepthPlane& p) const {
        uint64_t h = uint64_t(p.a) * 0x9E3779B97F4A7C15ull;
        h ^= (uint64_t(uint32_t(p.dx)) << 32 | uint32_t(p.dy)) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
        return size_t(h ^ (h >> 29));
    }
};

} // namespace

uint32_t DualRasterizer::Tri::depth(int64_t x, int64_t y, const int64_t e[3], double invArea, bool ortho,
                                    float far, uint32_t* onPlane) const {
    if (plane) {
        const int64_t q = planeA + depthPlaneSlopeAt(planeDx, planeDy, x, y);
        if (q <= 0) return 0u;
        if (q >= int64_t(0xFFFFFFFEu)) return 0xFFFFFFFEu;
        if (onPlane) *onPlane = planeId; // unclamped: the depth is the plane's value
        return uint32_t(q);
    }
    const double invd =
        (double(e[0]) * invDepth[0] + double(e[1]) * invDepth[1] + double(e[2]) * invDepth[2]) * invArea;
    return quantizeDepth(float(ortho ? invd : 1.0 / invd), far);
}

LightFrustum spotLightFrustum(const LightShape& light, float nearPlane) {
    LightFrustum f;
    glm::vec3 dir = glm::normalize(light.direction);
    glm::vec3 up = std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    f.view = glm::lookAt(light.position, light.position + dir, up);
    f.fov = 2.0f * light.outerAngle;
    f.nearPlane = std::min(nearPlane, light.range * 0.01f);
    f.farPlane = light.range;
    return f;
}

LightFrustum pointLightFaceFrustum(const LightShape& light, uint32_t face, float nearPlane) {
    static const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const glm::vec3 axis = axes[face % 6];
    const glm::vec3 up = face == 2 || face == 3 ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    LightFrustum f;
    f.view = glm::lookAt(light.position, light.position + axis, up);
    f.fov = 1.57079633f;
    f.nearPlane = std::min(nearPlane, light.range * 0.01f);
    f.farPlane = light.range;
    return f;
}

LightFrustum directionalLightFrustum(glm::vec3 direction, glm::vec3 lo, glm::vec3 hi) {
    const glm::vec3 dir = glm::normalize(direction);
    glm::vec3 up = std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    const glm::vec3 centre = (lo + hi) * 0.5f;
    const float radius = glm::length(hi - lo) * 0.5f;
    // The stated margin: 1/1024 of the box's diagonal (at least 0.1 mm) on every side and along the
    // light, so float rounding of the view transform keeps every corner inside the volume.
    const float margin = std::max(radius / 512.0f, 1e-4f);
    // The eye 1 m + 2 margins beyond the bounding sphere: the box's nearest corner is >= 1 m + 2 margins
    // deep, so near = that depth - margin stays >= 1 m.
    glm::vec3 eye = centre - dir * (radius + 1.0f + 2.0f * margin);
    auto extents = [&](const glm::mat4& view, glm::vec3& vmin, glm::vec3& vmax) {
        vmin = glm::vec3(1e30f), vmax = glm::vec3(-1e30f);
        for (int i = 0; i < 8; ++i) {
            glm::vec3 c(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
            glm::vec3 v = glm::vec3(view * glm::vec4(c, 1.0f));
            vmin = glm::min(vmin, v), vmax = glm::max(vmax, v);
        }
    };
    glm::mat4 view = glm::lookAt(eye, eye + dir, up);
    glm::vec3 vmin, vmax;
    extents(view, vmin, vmax);
    // The longer light-space extent goes along x (the map's full width): turn the view a quarter turn
    // about the light when y is longer.
    if (vmax.y - vmin.y > vmax.x - vmin.x) {
        up = glm::vec3(view[0][0], view[1][0], view[2][0]); // the old right axis becomes up
        view = glm::lookAt(eye, eye + dir, up);
        extents(view, vmin, vmax);
    }
    LightFrustum f;
    f.fitMargin = margin;
    f.orthoHalf = std::max((vmax.x - vmin.x) * 0.5f + margin, 1e-3f);
    f.orthoHalfY = std::min((vmax.y - vmin.y) * 0.5f + margin, f.orthoHalf);
    // Sideways: the rectangle's x centre onto the axis, its bottom edge (less the margin) onto view
    // y = -orthoHalf, so it fills rows [0, mapRows) of the square texel grid.
    const glm::vec3 right(view[0][0], view[1][0], view[2][0]), upAxis(view[0][1], view[1][1], view[2][1]);
    eye += right * ((vmin.x + vmax.x) * 0.5f) + upAxis * (vmin.y - margin + f.orthoHalf);
    f.view = glm::lookAt(eye, eye + dir, up);
    f.fov = 0.0f;
    // Depth: the box's slab along the light, [nearest corner, deepest corner], plus the margin.
    f.nearPlane = -vmax.z - margin;
    f.farPlane = -vmin.z + margin;
    return f;
}

std::vector<LightFrustum> lightFrustums(const LightShape& light) {
    if (light.type == LightKind::Spot) return {spotLightFrustum(light)};
    if (light.type != LightKind::Point) return {};
    std::vector<LightFrustum> out;
    for (uint32_t face = 0; face < 6; ++face) out.push_back(pointLightFaceFrustum(light, face));
    return out;
}

DualRasterizer::DualRasterizer(const CasterTriangles& casters, const LightFrustum& frustum,
                               uint32_t resolution)
    : res_(resolution), rows_(frustum.mapRows(resolution)), far_(frustum.farPlane),
      ortho_(frustum.orthographic()) {
    // Perspective: NDC = x / (d tan); orthographic: NDC = x / orthoHalf. The side clip planes are
    // kGuard * g(d) -+ x with g(d) = tan * d or orthoHalf.
    const double t = ortho_ ? 0.0 : std::tan(double(frustum.fov) * 0.5);
    const double oh = frustum.orthoHalf;
    auto side = [&](const V3& v) {
        return ortho_ ? kGuard * oh : kGuard * t * v.z;
    }; // perspective: as before
    // A fitted directional map clips casters at kDirectionalClipNear, not at its near plane (the box's
    // slab): casters between the light and the box within its bounding sphere still shadow it, at depths
    // below near (CPVS slice 0 and the depth maps take them as any nearer caster).
    const double n = frustum.fitted() ? std::min(double(frustum.nearPlane), double(kDirectionalClipNear))
                                      : double(frustum.nearPlane);
    const double fa = frustum.farPlane;
    std::vector<V3> poly, tmp;
    size_t count = std::min(casters.closed.size(), casters.positions.size() / 3);
    std::unordered_map<DepthPlane, uint32_t, PlaneHash> planeIds;
    for (size_t tri = 0; tri < count; ++tri) {
        int64_t planeA = 0, planeDx = 0, planeDy = 0;
        const bool plane = ortho_ && orthoDepthPlane(frustum.view, &casters.positions[tri * 3], oh, res_,
                                                     double(far_), planeA, planeDx, planeDy);
        uint32_t planeId = 0; // stays 0 past kMaxDepthPlanes distinct planes: the texels name no plane
        if (plane) {
            const DepthPlane key{planeA, int32_t(planeDx), int32_t(planeDy)};
            auto it = planeIds.find(key);
            if (it != planeIds.end()) {
                planeId = it->second;
            } else if (planes_.size() < kMaxDepthPlanes) {
                planes_.push_back(key);
                planeId = uint32_t(planes_.size());
                planeIds.emplace(key, planeId);
            }
        }
        poly.clear();
        for (int k = 0; k < 3; ++k) {
            glm::vec4 v = frustum.view * glm::vec4(casters.positions[tri * 3 + k], 1.0f);
            poly.push_back(V3(v.x, v.y, -double(v.z))); // z holds the depth d = -Z
        }
        clipPolygon(poly, tmp, [&](const V3& v) { return v.z - n; });
        if (poly.size() >= 3) clipPolygon(poly, tmp, [&](const V3& v) { return fa - v.z; });
        if (poly.size() >= 3) clipPolygon(poly, tmp, [&](const V3& v) { return side(v) - v.x; });
        if (poly.size() >= 3) clipPolygon(poly, tmp, [&](const V3& v) { return side(v) + v.x; });
        if (poly.size() >= 3) clipPolygon(poly, tmp, [&](const V3& v) { return side(v) - v.y; });
        if (poly.size() >= 3) clipPolygon(poly, tmp, [&](const V3& v) { return side(v) + v.y; });
        if (poly.size() < 3) continue;
        // Project: NDC = x / (d tan), pixel = (NDC + 1) / 2 * res, fixed = round(pixel * 256).
        std::vector<int64_t> fx(poly.size()), fy(poly.size());
        std::vector<double> inv(poly.size());
        for (size_t k = 0; k < poly.size(); ++k) {
            double d = std::max(poly[k].z, n);
            const double s = ortho_ ? oh : d * t;
            fx[k] = std::llround((poly[k].x / s + 1.0) * 0.5 * double(res_) * double(kSub));
            fy[k] = std::llround((poly[k].y / s + 1.0) * 0.5 * double(res_) * double(kSub));
            inv[k] = ortho_ ? d : 1.0 / d; // orthographic depth is linear in screen space
        }
        for (size_t k = 1; k + 1 < poly.size(); ++k) {
            size_t id[3] = {0, k, k + 1};
            Tri tr;
            for (int j = 0; j < 3; ++j) tr.x[j] = fx[id[j]], tr.y[j] = fy[id[j]], tr.invDepth[j] = inv[id[j]];
            int64_t area =
                (tr.x[1] - tr.x[0]) * (tr.y[2] - tr.y[0]) - (tr.x[2] - tr.x[0]) * (tr.y[1] - tr.y[0]);
            if (area == 0) continue;
            bool front = area > 0;
            if (!front)
                std::swap(tr.x[1], tr.x[2]), std::swap(tr.y[1], tr.y[2]),
                    std::swap(tr.invDepth[1], tr.invDepth[2]);
            tr.kind = casters.closed[tri] ? (front ? 0 : 2) : 1;
            tr.plane = plane, tr.planeA = planeA, tr.planeDx = planeDx, tr.planeDy = planeDy;
            tr.planeId = planeId;
            int64_t ymin = std::min({tr.y[0], tr.y[1], tr.y[2]}),
                    ymax = std::max({tr.y[0], tr.y[1], tr.y[2]});
            // Rows whose centre y*256+128 lies in [ymin, ymax].
            int64_t r0 = floorDiv(ymin - kSub / 2 + kSub - 1, kSub), r1 = floorDiv(ymax - kSub / 2, kSub);
            // Rows from rows_ on lie outside a fitted directional light's volume: never covered.
            r0 = std::max<int64_t>(r0, 0), r1 = std::min<int64_t>(r1, int64_t(rows_) - 1);
            if (r0 > r1) continue;
            tr.yMin = int32_t(r0), tr.yMax = int32_t(r1);
            tris_.push_back(tr);
        }
    }
    std::stable_sort(tris_.begin(), tris_.end(), [](const Tri& a, const Tri& b) { return a.yMin < b.yMin; });
}

void DualRasterizer::renderRows(uint32_t y0, uint32_t y1, uint32_t* enter, uint32_t* exit,
                                uint32_t* enterPlane) const {
    renderRect(0, y0, res_, y1 - y0, enter, exit, enterPlane);
}

bool DualRasterizer::blockEmpty(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) const {
    const uint32_t y1 = y0 + h;
    for (const Tri& tr : tris_) { // renderRect's row and column bounds, without the coverage
        if (tr.yMin >= int32_t(y1)) break;
        if (tr.yMax < int32_t(y0)) continue;
        int64_t xmin = std::min({tr.x[0], tr.x[1], tr.x[2]}), xmax = std::max({tr.x[0], tr.x[1], tr.x[2]});
        int64_t c0 = floorDiv(xmin - kSub / 2 + kSub - 1, kSub), c1 = floorDiv(xmax - kSub / 2, kSub);
        c0 = std::max<int64_t>(c0, x0), c1 = std::min<int64_t>(c1, int64_t(x0) + w - 1);
        if (c0 <= c1) return false;
    }
    return true;
}

namespace {

// renderRect's per-thread scratch, kept from call to call: a 512^2 tile's slots are 16 MiB, and
// allocating them for every tile cost page faults and clears. render() frees it when the whole map is
// done, so a host thread that bakes does not keep a band's slots (64 MiB at 1M texels) afterwards.
struct HitSlots {
    std::vector<uint32_t> count;                         // hits per local texel
    std::vector<uint64_t> slots;                         // kHitSlots planes of one key (hitKey) a texel
    std::vector<std::pair<uint64_t, uint64_t>> overflow; // (local texel, key): the hits past a texel's slots
    std::vector<uint64_t> texel; // the keys of a texel past kHitSlots hits while it is resolved
};
thread_local HitSlots tHits;

// Hits a texel holds without the overflow list (64 B a texel). The closed night city seen from the moon
// has 2-6 hits a texel (ground slab, roof, floor, foliage) and up to 8.
constexpr uint32_t kHitSlots = 8;

// A hit's sort key: depth (32 bits) | kind (2 bits: 0 closed front, 1 open, 2 closed back) | plane id
// (30 bits, 0: none), so a texel's hits sort by depth, then kind (step 5), and the first one names the
// plane its enter depth lies on.
constexpr uint64_t kHitPlaneMask = (uint64_t(1) << 30) - 1u;
inline uint64_t hitKey(uint32_t depth, uint32_t kind, uint32_t plane) {
    return uint64_t(depth) << 32 | uint64_t(kind) << 30 | plane;
}
inline uint32_t hitKind(uint64_t key) {
    return uint32_t(key >> 30) & 3u;
}

int64_t ceilDivPositive(int64_t a, int64_t b) { // a > 0, b > 0
    return (a + b - 1) / b;
}

// A projected triangle's edge functions, tie rule and covered columns within [x0, x0 + w): edge i is
// opposite vertex i, from v[i+1] to v[i+2], E = A (px - ax) + B (py - ay); a centre on it is covered
// when bias_i is 0 (raster_dual.h step 3). False when no column is covered.
struct Edges {
    int64_t A[3], B[3], bias[3];
    int64_t c0, c1;
    double invArea;
};
bool triangleEdges(const int64_t x[3], const int64_t y[3], uint32_t x0, uint32_t w, Edges& out) {
    const int64_t xmin = std::min({x[0], x[1], x[2]}), xmax = std::max({x[0], x[1], x[2]});
    out.c0 = std::max<int64_t>(floorDiv(xmin - kSub / 2 + kSub - 1, kSub), x0);
    out.c1 = std::min<int64_t>(floorDiv(xmax - kSub / 2, kSub), int64_t(x0) + w - 1);
    if (out.c0 > out.c1) return false;
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        const int64_t dx = x[b] - x[a], dy = y[b] - y[a];
        out.A[i] = -dy, out.B[i] = dx;
        out.bias[i] = dy < 0 || (dy == 0 && dx > 0) ? 0 : 1;
    }
    const int64_t area = out.B[0] * (y[0] - y[1]) + out.A[0] * (x[0] - x[1]);
    out.invArea = 1.0 / double(area);
    return true;
}

} // namespace

size_t DualRasterizer::threadScratchBytes() {
    return tHits.count.capacity() * sizeof(uint32_t) +
           (tHits.slots.capacity() + 2 * tHits.overflow.capacity() + tHits.texel.capacity()) *
               sizeof(uint64_t);
}

void DualRasterizer::renderRect(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* enter,
                                uint32_t* exit, uint32_t* enterPlane) const {
    const uint32_t y1 = y0 + h;
    const uint64_t tileTexels = uint64_t(h) * w;
    HitSlots& hs = tHits;
    hs.count.assign(tileTexels, 0u);
    if (hs.slots.size() < tileTexels * kHitSlots) hs.slots.resize(tileTexels * kHitSlots);
    hs.overflow.clear();
    for (const Tri& tr : tris_) {
        if (tr.yMin >= int32_t(y1)) break;
        if (tr.yMax < int32_t(y0)) continue;
        Edges ed;
        if (!triangleEdges(tr.x, tr.y, x0, w, ed)) continue;
        const int64_t *A = ed.A, *B = ed.B, *bias = ed.bias, c0 = ed.c0, c1 = ed.c1;
        const double invArea = ed.invArea;
        int32_t ys = std::max(tr.yMin, int32_t(y0)), ye = std::min(tr.yMax, int32_t(y1) - 1);
        for (int32_t y = ys; y <= ye; ++y) {
            int64_t py = int64_t(y) * kSub + kSub / 2, px = c0 * kSub + kSub / 2;
            int64_t e[3];
            // The covered span of the row, solved exactly from the edge functions: e_i(x) =
            // e_i(c0) + A_i 256 (x - c0) >= bias_i for every i, instead of testing every column.
            int64_t lo = c0, hi = c1;
            for (int i = 0; i < 3; ++i) {
                int a = (i + 1) % 3;
                e[i] = A[i] * (px - tr.x[a]) + B[i] * (py - tr.y[a]);
                const int64_t v = e[i] - bias[i], s = A[i] * kSub;
                if (s > 0 && v < 0)
                    lo = std::max(lo, c0 + ceilDivPositive(-v, s));
                else if (s < 0)
                    hi = v < 0 ? c0 - 1 : std::min(hi, c0 + v / -s);
                else if (s == 0 && v < 0)
                    hi = c0 - 1;
            }
            if (lo > hi) continue;
            for (int i = 0; i < 3; ++i) e[i] += A[i] * kSub * (lo - c0);
            uint32_t* count = hs.count.data() + uint64_t(y - int32_t(y0)) * w;
            uint64_t* slots = hs.slots.data() + uint64_t(y - int32_t(y0)) * w;
            for (int64_t x = lo; x <= hi; ++x) {
                uint32_t plane = 0;
                const uint32_t depth = tr.depth(x, y, e, invArea, ortho_, far_, &plane);
                const uint64_t key = hitKey(depth, tr.kind, plane), lx = uint64_t(x - int64_t(x0));
                const uint32_t n = count[lx]++;
                if (n < kHitSlots)
                    slots[n * tileTexels + lx] = key; // plane n: a row's span writes one run
                else
                    hs.overflow.emplace_back(uint64_t(y - int32_t(y0)) * w + lx, key);
                for (int i = 0; i < 3; ++i) e[i] += A[i] * kSub;
            }
        }
    }
    // Each texel's hits in key order (depth, then closed front < open < closed back), then the walk of
    // raster_dual.h step 5.
    std::sort(hs.overflow.begin(), hs.overflow.end());
    size_t ov = 0;
    std::vector<uint64_t>& more = hs.texel;
    uint64_t buf[kHitSlots];
    for (uint64_t t = 0; t < tileTexels; ++t) {
        const uint32_t n = hs.count[t];
        if (n == 0) {
            enter[t] = exit[t] = kDepthEmpty;
            if (enterPlane) enterPlane[t] = 0u;
            continue;
        }
        uint64_t* k = buf; // the texel's keys: in registers and the stack unless it overflowed
        if (n <= kHitSlots) {
            for (uint32_t j = 0; j < n; ++j) buf[j] = hs.slots[j * tileTexels + t];
        } else {
            more.clear();
            for (uint32_t j = 0; j < kHitSlots; ++j) more.push_back(hs.slots[j * tileTexels + t]);
            for (; ov < hs.overflow.size() && hs.overflow[ov].first == t; ++ov)
                more.push_back(hs.overflow[ov].second);
            k = more.data();
        }
        if (n > 32) {
            std::sort(k, k + n);
        } else {
            // Insertion sort, a texel holds a few hits. The key is held in a register while the larger
            // ones move up: swapping in memory made each step wait on the store before it (half of
            // renderRect's time on the closed city's 6-hit texels).
            for (uint32_t a = 1; a < n; ++a) {
                const uint64_t v = k[a];
                uint32_t b = a;
                for (; b > 0 && v < k[b - 1]; --b) k[b] = k[b - 1];
                k[b] = v;
            }
        }
        const uint32_t first = uint32_t(k[0] >> 32);
        uint32_t out = first;
        if (hitKind(k[0]) == 0u) { // entered a closed mesh: walk until outside all closed geometry
            int depthCount = 0;
            out = 0xFFFFFFFEu;
            for (uint32_t j = 0; j < n; ++j) {
                const uint32_t kind = hitKind(k[j]);
                depthCount += kind == 0 ? 1 : kind == 2 ? -1 : 0;
                if (depthCount <= 0) {
                    out = uint32_t(k[j] >> 32);
                    break;
                }
            }
        }
        enter[t] = first;
        exit[t] = out;
        if (enterPlane) enterPlane[t] = uint32_t(k[0] & kHitPlaneMask);
    }
}

void DualRasterizer::renderRectReference(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* enter,
                                         uint32_t* exit) const {
    const uint32_t y1 = y0 + h;
    const uint64_t rowTexels = w;
    const uint64_t tileTexels = uint64_t(h) * rowTexels;
    // Hit key: local texel (30 bits) | depth (32 bits) | kind (2 bits); sorting orders hits per texel
    // by depth, then closed front < open < closed back.
    std::vector<uint64_t> hits;
    for (const Tri& tr : tris_) {
        if (tr.yMin >= int32_t(y1)) break;
        if (tr.yMax < int32_t(y0)) continue;
        Edges ed;
        if (!triangleEdges(tr.x, tr.y, x0, w, ed)) continue;
        const int64_t *A = ed.A, *B = ed.B, *bias = ed.bias, c0 = ed.c0, c1 = ed.c1;
        const double invArea = ed.invArea;
        int32_t ys = std::max(tr.yMin, int32_t(y0)), ye = std::min(tr.yMax, int32_t(y1) - 1);
        for (int32_t y = ys; y <= ye; ++y) {
            int64_t py = int64_t(y) * kSub + kSub / 2, px = c0 * kSub + kSub / 2;
            int64_t e[3];
            for (int i = 0; i < 3; ++i) {
                int a = (i + 1) % 3;
                e[i] = A[i] * (px - tr.x[a]) + B[i] * (py - tr.y[a]);
            }
            for (int64_t x = c0; x <= c1; ++x) {
                if (e[0] - bias[0] >= 0 && e[1] - bias[1] >= 0 && e[2] - bias[2] >= 0) {
                    const uint32_t depth = tr.depth(x, y, e, invArea, ortho_, far_);
                    uint64_t local = uint64_t(y - int32_t(y0)) * rowTexels + uint64_t(x - int64_t(x0));
                    hits.push_back(local << 34 | uint64_t(depth) << 2 | tr.kind);
                }
                for (int i = 0; i < 3; ++i) e[i] += A[i] * kSub;
            }
        }
    }
    // Hits ordered by key: a counting sort by texel (linear in the hits, where sorting the whole list is
    // n log n), then each texel's few hits by depth and kind. Equal keys are the same hit, so the order
    // is the full key's sort.
    {
        std::vector<uint32_t> start(tileTexels + 1, 0u);
        for (uint64_t h : hits) ++start[(h >> 34) + 1];
        for (uint64_t t = 0; t < tileTexels; ++t) start[t + 1] += start[t];
        std::vector<uint64_t> sorted(hits.size());
        for (uint64_t h : hits) sorted[start[h >> 34]++] = h; // start[t] ends at texel t's end
        hits.swap(sorted);
        uint32_t begin = 0;
        for (uint64_t t = 0; t < tileTexels; ++t) {
            const uint32_t end = start[t];
            if (end - begin > 32) {
                std::sort(hits.begin() + begin, hits.begin() + end);
            } else if (end - begin > 1) {
                for (uint32_t a = begin + 1; a < end; ++a) // insertion sort: a texel holds a few hits
                    for (uint32_t b = a; b > begin && hits[b] < hits[b - 1]; --b)
                        std::swap(hits[b], hits[b - 1]);
            }
            begin = end;
        }
    }
    std::fill(enter, enter + tileTexels, kDepthEmpty);
    std::fill(exit, exit + tileTexels, kDepthEmpty);
    size_t i = 0;
    while (i < hits.size()) {
        uint64_t texel = hits[i] >> 34;
        size_t j = i;
        while (j < hits.size() && (hits[j] >> 34) == texel) ++j;
        uint32_t first = uint32_t(hits[i] >> 2);
        uint32_t out = first;
        if ((hits[i] & 3u) == 0u) { // entered a closed mesh: walk until outside all closed geometry
            int count = 0;
            out = 0xFFFFFFFEu;
            for (size_t k = i; k < j; ++k) {
                uint32_t kind = uint32_t(hits[k] & 3u);
                count += kind == 0 ? 1 : kind == 2 ? -1 : 0;
                if (count <= 0) {
                    out = uint32_t(hits[k] >> 2);
                    break;
                }
            }
        }
        enter[texel] = first;
        exit[texel] = out;
        i = j;
    }
}

DualDepthMap DualRasterizer::blankMap() const {
    DualDepthMap map;
    map.resolution = res_;
    map.rows = rows_ < res_ ? rows_ : 0u;
    map.orthographic = ortho_;
    map.enter.assign(size_t(res_) * res_, kDepthEmpty);
    map.exit.assign(size_t(res_) * res_, kDepthEmpty);
    if (ortho_) map.enterPlane.assign(size_t(res_) * res_, 0u), map.planes = planes_;
    return map;
}

DualDepthMap DualRasterizer::render(uint64_t tileTexels) const {
    DualDepthMap map = blankMap();
    uint32_t rows = uint32_t(std::clamp<uint64_t>(tileTexels / std::max<uint32_t>(res_, 1), 1, res_));
    for (uint32_t y0 = 0; y0 < res_; y0 += rows) {
        uint32_t y1 = std::min(res_, y0 + rows);
        renderRows(y0, y1, map.enter.data() + size_t(y0) * res_, map.exit.data() + size_t(y0) * res_,
                   map.enterPlane.empty() ? nullptr : map.enterPlane.data() + size_t(y0) * res_);
    }
    tHits = HitSlots{}; // the map is done: give the band's scratch back
    return map;
}

DualDepthMap rasterizeDual(const CasterTriangles& casters, const LightFrustum& frustum, uint32_t resolution) {
    return DualRasterizer(casters, frustum, resolution).render();
}

} // namespace ml
