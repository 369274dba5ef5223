#include "bake/need.h"
#include "bake/scene_casters.h"

#include "bake/bake.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ml {

namespace {

// Grid points per triangle and light at most (a 400 m ground quad under a 20 m lamp is clipped to the
// lamp's disc first; this only bounds pathological inputs, where the spacing grows instead).
constexpr double kMaxGridPoints = 1 << 20;
// Spacing of the receiver grid as a share of the light's range (range / 40: 0.5 m under a 20 m lamp).
constexpr float kSpacingPerRange = 1.0f / 40.0f;

struct Point {
    glm::vec3 p, n;
};

// Samples the part of triangle (a, b, c) inside the sphere (centre, radius) on a square grid of spacing
// `s` in the triangle's plane; tiny triangles (no grid point inside) contribute their centroid.
void sampleTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& centre,
                    float radius, float s, std::vector<Point>& out) {
    glm::vec3 n = glm::cross(b - a, c - a);
    const float len = glm::length(n);
    if (!(len > 0.0f)) return;
    n /= len;
    const float dist = glm::dot(centre - a, n);
    if (std::abs(dist) > radius) return;
    const glm::vec3 q = centre - dist * n; // centre of the disc the sphere cuts from the plane
    const float rr = std::sqrt(std::max(0.0f, radius * radius - dist * dist));
    const glm::vec3 u = glm::normalize(b - a), v = glm::cross(n, u);
    const glm::vec2 A(glm::dot(a - q, u), glm::dot(a - q, v)), B(glm::dot(b - q, u), glm::dot(b - q, v)),
        C(glm::dot(c - q, u), glm::dot(c - q, v));
    const glm::vec2 lo = glm::max(glm::min(A, glm::min(B, C)), glm::vec2(-rr)),
                    hi = glm::min(glm::max(A, glm::max(B, C)), glm::vec2(rr));
    if (lo.x > hi.x || lo.y > hi.y) return;
    const double cells = double((hi.x - lo.x) / s + 1) * double((hi.y - lo.y) / s + 1);
    if (cells > kMaxGridPoints) s *= float(std::sqrt(cells / kMaxGridPoints));
    auto edge = [](glm::vec2 p0, glm::vec2 p1, glm::vec2 p) {
        return (p1.x - p0.x) * (p.y - p0.y) - (p1.y - p0.y) * (p.x - p0.x);
    };
    const float area = edge(A, B, C);
    const size_t before = out.size();
    // Grid aligned to multiples of s around the disc centre, so neighbouring triangles share a lattice.
    for (float y = std::ceil(lo.y / s) * s; y <= hi.y; y += s)
        for (float x = std::ceil(lo.x / s) * s; x <= hi.x; x += s) {
            const glm::vec2 p(x, y);
            if (x * x + y * y > rr * rr) continue;
            const float w0 = edge(B, C, p) / area, w1 = edge(C, A, p) / area, w2 = edge(A, B, p) / area;
            if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
            out.push_back({q + x * u + y * v, n});
        }
    if (out.size() == before) {
        const glm::vec3 g = (a + b + c) / 3.0f;
        if (glm::length(g - centre) <= radius) out.push_back({g, n});
    }
}

// The world width the map spans at p (0: p is outside this frustum).
float mapWidthAt(const LightFrustum& f, const glm::vec3& p) {
    const glm::vec3 v = glm::vec3(f.view * glm::vec4(p, 1.0f));
    const float z = -v.z;
    if (!(z >= f.nearPlane && z <= f.farPlane)) return 0.0f;
    if (f.orthographic())
        return std::abs(v.x) <= f.orthoHalf && std::abs(v.y) <= f.orthoHalf &&
                       (!f.fitted() || v.y <= 2.0f * f.orthoHalfY - f.orthoHalf)
                   ? 2.0f * f.orthoHalf
                   : 0.0f;
    const float t = std::tan(0.5f * f.fov) * z;
    return std::abs(v.x) <= t && std::abs(v.y) <= t ? 2.0f * t : 0.0f;
}

// Conservative: false only when the triangle lies wholly outside one plane of the frustum (then it
// cannot cover a texel of the map); a triangle that passes may still miss it.
bool triangleTouchesFrustum(const LightFrustum& f, const glm::vec3& a, const glm::vec3& b,
                            const glm::vec3& c) {
    glm::vec3 v[3] = {glm::vec3(f.view * glm::vec4(a, 1.0f)), glm::vec3(f.view * glm::vec4(b, 1.0f)),
                      glm::vec3(f.view * glm::vec4(c, 1.0f))};
    const float t = f.orthographic() ? 0.0f : std::tan(0.5f * f.fov);
    auto allOutside = [&](auto outside) { return outside(v[0]) && outside(v[1]) && outside(v[2]); };
    // A fitted directional map rasterises casters from kDirectionalClipNear on (raster_dual.h).
    const float clipNear = f.fitted() ? std::min(f.nearPlane, kDirectionalClipNear) : f.nearPlane;
    if (allOutside([&](glm::vec3 p) { return -p.z < clipNear; }) ||
        allOutside([&](glm::vec3 p) { return -p.z > f.farPlane; }))
        return false;
    for (int axis = 0; axis < 2; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
            auto outside = [&](glm::vec3 p) {
                const float e = f.orthographic() ? f.orthoHalf : t * -p.z;
                return sign * p[axis] > e;
            };
            if (allOutside(outside)) return false;
        }
    return true;
}

uint32_t nextPow2(double v) {
    uint32_t r = 1;
    while (r < v && r < (1u << 30)) r <<= 1;
    return r;
}

} // namespace

std::vector<NeedCamera> boxCameras(glm::vec3 lo, glm::vec3 hi, uint32_t n, float fovY, float nearPlane,
                                   float farPlane) {
    std::vector<NeedCamera> out;
    n = std::max(n, 1u);
    for (uint32_t k = 0; k < n; ++k)
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const glm::vec3 t = n == 1 ? glm::vec3(0.5f) : glm::vec3(i, j, k) / float(n - 1);
                NeedCamera c;
                c.position = glm::mix(lo, hi, t);
                c.fovY = fovY, c.nearPlane = nearPlane, c.farPlane = farPlane, c.anyDirection = true;
                out.push_back(c);
            }
    return out;
}

Result<std::vector<LightNeed>> estimateNeed(const Scene& scene, const std::vector<uint32_t>& lights,
                                            const std::vector<NeedCamera>& cameras, const NeedOptions& o) {
    if (cameras.empty()) return fail("need: no camera sample");
    if (o.width == 0 || o.height == 0) return fail("need: image size is zero");
    if (o.minRes == 0 || o.minRes > o.maxRes)
        return fail("need: resolution range " + std::to_string(o.minRes) + ".." + std::to_string(o.maxRes) +
                    " is empty");
    for (const NeedCamera& c : cameras)
        if (!(c.fovY > 0.0f && c.fovY < 3.1f && c.aspect > 0.0f && c.nearPlane > 0.0f &&
              c.farPlane > c.nearPlane))
            return fail("need: a camera sample has a field of view, aspect or depth range out of range");
    const CasterTriangles tris = castersFromScene(scene);
    std::vector<LightNeed> out;
    for (uint32_t li : lights) {
        if (li >= scene.lights.size())
            return fail("need: light " + std::to_string(li) + " is not below the scene's " +
                        std::to_string(scene.lights.size()) + " lights");
        const Light& l = scene.lights[li];
        const std::vector<LightFrustum> frustums = bakeFrustums(scene, l);
        const bool directional = l.type == LightKind::Directional;
        glm::vec3 centre = l.position;
        float radius = l.range;
        if (directional) {
            centre = 0.5f * (scene.boundsMin + scene.boundsMax);
            radius = 0.5f * glm::length(scene.boundsMax - scene.boundsMin) + 1e-3f;
        }
        const float spacing = std::max(radius * kSpacingPerRange, 1e-4f);
        LightNeed need;
        need.light = li;

        // Receivers: grid points on triangles in the light's volume, each with the map width there.
        std::vector<Point> tri;
        bool anyCaster = false;
        std::vector<std::pair<Point, float>> receivers; // point, map width
        for (size_t t = 0; t < tris.triangleCount(); ++t) {
            const glm::vec3 &a = tris.positions[3 * t], &b = tris.positions[3 * t + 1],
                            &c = tris.positions[3 * t + 2];
            // Bounding-box reject against the sphere first (most triangles of a city are far away).
            const glm::vec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
            const glm::vec3 d = glm::max(glm::max(lo - centre, centre - hi), glm::vec3(0.0f));
            if (glm::dot(d, d) > radius * radius) continue;
            bool touches = false;
            for (const LightFrustum& f : frustums) touches = touches || triangleTouchesFrustum(f, a, b, c);
            if (!touches) continue;
            anyCaster = true; // may still have no receiver point: then it is 'not seen', never 'no caster'
            tri.clear();
            sampleTriangle(a, b, c, centre, radius, spacing, tri);
            for (const Point& p : tri) {
                float w = 0.0f;
                for (const LightFrustum& f : frustums) w = std::max(w, mapWidthAt(f, p.p));
                if (!(w > 0.0f)) continue;
                if (!directional && glm::length(p.p - l.position) > l.range) continue;
                receivers.push_back({p, w});
            }
        }
        if (!anyCaster) {
            need.reason = NeedReason::NoCaster;
            out.push_back(need);
            continue;
        }
        need.receivers = uint32_t(std::min<size_t>(receivers.size(), UINT32_MAX));

        // Per receiver, the camera samples that see it (in frustum, facing on the lit side), by need.
        struct Candidate {
            float need;
            uint32_t sample;
            float depth;
        };
        auto candidatesOf = [&](uint32_t r, std::vector<Candidate>& cs) {
            cs.clear();
            const Point& p = receivers[r].first;
            const glm::vec3 toLight = directional ? -l.direction : l.position - p.p;
            const float lightSide = glm::dot(p.n, toLight);
            for (uint32_t s = 0; s < cameras.size(); ++s) {
                const NeedCamera& c = cameras[s];
                const glm::vec3 v = p.p - c.position;
                const float camSide = -glm::dot(p.n, v);
                // Two-sided: the camera must look at the side the light shines on.
                if (!(camSide * lightSide > 0.0f)) continue;
                float depth = glm::length(v);
                if (!c.anyDirection) {
                    depth = glm::dot(v, c.forward);
                    if (!(depth > c.nearPlane && depth < c.farPlane)) continue;
                    const glm::vec3 right = glm::normalize(glm::cross(c.forward, glm::vec3(0, 1, 0)));
                    const glm::vec3 up = glm::cross(right, c.forward);
                    const float th = std::tan(0.5f * c.fovY) * depth;
                    if (std::abs(glm::dot(v, up)) > th || std::abs(glm::dot(v, right)) > th * c.aspect)
                        continue;
                } else if (!(depth < c.farPlane)) {
                    continue;
                }
                depth = std::max(depth, c.nearPlane);
                const float pixel = 2.0f * depth * std::tan(0.5f * c.fovY) / float(o.height);
                cs.push_back({receivers[r].second / pixel, s, depth});
            }
            // Largest need first, ties to the earlier sample (deterministic).
            std::sort(cs.begin(), cs.end(), [](const Candidate& x, const Candidate& y) {
                return x.need != y.need ? x.need > y.need : x.sample < y.sample;
            });
        };
        // Each receiver's largest need (an upper bound once occlusion is tested), receivers by it.
        std::vector<std::pair<float, uint32_t>> bound;
        std::vector<Candidate> cs;
        for (uint32_t r = 0; r < receivers.size(); ++r) {
            candidatesOf(r, cs);
            if (!cs.empty()) bound.push_back({cs[0].need, r});
        }
        need.seen = uint32_t(bound.size());
        std::sort(bound.begin(), bound.end(), [](const auto& x, const auto& y) {
            return x.first != y.first ? x.first > y.first : x.second < y.second;
        });
        // The first visible candidate in need order decides. A receiver whose bound cannot beat the
        // best found, or not raise its power of two, ends the search; so does a best past the cap. Ray
        // budget spent: the next candidate is taken unoccluded (an upper bound, flagged).
        bool found = false;
        Candidate pick{0.0f, 0, 0.0f};
        uint64_t rays = 0;
        for (const auto& [ub, r] : bound) {
            if (found && (ub <= pick.need ||
                          nextPow2(std::ceil(double(ub))) <= nextPow2(std::ceil(double(pick.need))) ||
                          pick.need >= float(o.maxRes)))
                break;
            candidatesOf(r, cs);
            for (const Candidate& cd : cs) {
                if (found && cd.need <= pick.need) break;
                if (!o.visible || rays >= o.maxRaysPerLight) {
                    need.raysCapped = o.visible && rays >= o.maxRaysPerLight;
                    pick = cd, found = true;
                    break;
                }
                const Point& p = receivers[r].first;
                const glm::vec3 toCam = cameras[cd.sample].position - p.p;
                const glm::vec3 off = p.p + p.n * (glm::dot(p.n, toCam) > 0.0f ? 0.01f : -0.01f);
                ++rays;
                if (o.visible(cameras[cd.sample].position, off)) {
                    pick = cd, found = true;
                    break;
                }
            }
            if (need.raysCapped || !o.visible) break;
        }
        need.rays = uint32_t(std::min<uint64_t>(rays, UINT32_MAX));
        if (!found) {
            need.reason = NeedReason::NotSeen; // no receiver in view, or every one behind something
            need.resolution = o.minRes;
            out.push_back(need);
            continue;
        }
        need.needed = pick.need, need.sample = pick.sample, need.distance = pick.depth;
        const uint32_t r = nextPow2(std::ceil(double(pick.need)));
        need.reason = NeedReason::Footprint;
        need.resolution = r;
        if (r > o.maxRes) need.resolution = o.maxRes, need.reason = NeedReason::Capped;
        if (r < o.minRes) need.resolution = o.minRes, need.reason = NeedReason::Floor;
        out.push_back(need);
    }
    return out;
}

const char* needReasonName(NeedReason r) {
    switch (r) {
    case NeedReason::Footprint:
        return "footprint";
    case NeedReason::Capped:
        return "capped";
    case NeedReason::Floor:
        return "floor";
    case NeedReason::NotSeen:
        return "not-seen";
    case NeedReason::NoCaster:
        return "no-caster";
    }
    return "unknown";
}

std::string needReasonText(const LightNeed& n, uint32_t samples) {
    char b[256];
    const char* occl = n.raysCapped ? " (ray budget spent: the rest taken unoccluded)" : "";
    switch (n.reason) {
    case NeedReason::NoCaster:
        return "no caster in its volume: not baked";
    case NeedReason::NotSeen:
        if (n.seen)
            std::snprintf(b, sizeof b,
                          "%u of its %u receivers in view of the %u camera samples, every one behind "
                          "something: minimum %u",
                          n.seen, n.receivers, samples, n.resolution);
        else
            std::snprintf(b, sizeof b,
                          "none of its %u receivers in view of the %u camera samples: minimum %u",
                          n.receivers, samples, n.resolution);
        return b;
    case NeedReason::Footprint:
        std::snprintf(b, sizeof b, "receiver %.1f m from camera sample %u needs %.0f: %u%s", n.distance,
                      n.sample, n.needed, n.resolution, occl);
        return b;
    case NeedReason::Capped:
        std::snprintf(b, sizeof b, "receiver %.1f m from camera sample %u needs %.0f: capped at %u%s",
                      n.distance, n.sample, n.needed, n.resolution, occl);
        return b;
    case NeedReason::Floor:
        std::snprintf(b, sizeof b,
                      "receiver %.1f m from camera sample %u needs %.0f: raised to the minimum %u%s",
                      n.distance, n.sample, n.needed, n.resolution, occl);
        return b;
    }
    return "unknown reason";
}

} // namespace ml
