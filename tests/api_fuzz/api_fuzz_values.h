// Values for the API-sequence fuzzer (tests/api_fuzz/api_fuzz.cpp): seeded random lights, cameras, meshes
// and transforms, each valid, at an edge of its range, or broken in one way the module must refuse. A
// broken value says so (`certain`): the fuzzer then requires the module to refuse it, whatever
// validateLight / validateCamera say, so that a validator that lets it through fails the run too.
#pragma once
#include "manylights/glm.h"
#include "manylights/manylights.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace ml::fuzz {

class Rng {
  public:
    explicit Rng(uint64_t seed) : g_(seed) {}
    uint32_t below(uint32_t n) { return n ? uint32_t(g_() % n) : 0; }
    float uniform(float a, float b) { return a + (b - a) * float(double(g_() >> 11) * 0x1.0p-53); }
    bool chance(double p) { return double(g_() >> 11) * 0x1.0p-53 < p; }
    uint32_t bits() { return uint32_t(g_()); }
    template <class T> const T& pick(const std::vector<T>& v) { return v[below(uint32_t(v.size()))]; }

  private:
    std::mt19937_64 g_;
};

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// A value and whether it is broken on purpose (the module must refuse it).
template <class T> struct Candidate {
    T value;
    bool broken = false;
    std::string what = "valid";
};

inline Candidate<LightDesc> randomLight(Rng& r) {
    LightDesc l;
    const uint32_t k = r.below(10);
    l.kind = k < 6 ? LightKind::Spot : k < 9 ? LightKind::Point : LightKind::Directional;
    l.position = {r.uniform(-6, 6), r.uniform(0.5f, 6), r.uniform(-6, 6)};
    l.direction = {r.uniform(-0.6f, 0.6f), -1.0f, r.uniform(-0.6f, 0.6f)};
    l.color = {r.uniform(0, 1), r.uniform(0, 1), r.uniform(0, 1)};
    l.intensity = r.uniform(0.1f, 20);
    l.range = r.uniform(1, 15);
    l.outerAngle = r.uniform(0.05f, 1.5f);
    l.innerAngle = r.uniform(0, l.outerAngle);
    l.dynamic = r.chance(0.4);
    l.castsShadows = r.chance(0.7);
    l.unit = l.kind != LightKind::Directional && r.chance(0.2) ? LightUnit::Lumen : LightUnit::Candela;
    l.shadowDepthBias = r.uniform(0, 4);
    l.shadowNormalBias = r.uniform(0, 3);
    l.shadowResolution = r.chance(0.2) ? 8 + r.below(120) : 0;
    l.shadowTexelScale = r.chance(0.2) ? 0.25f * float(1u << r.below(6)) : 1.0f; // 1/4..8
    Candidate<LightDesc> c{l};
    if (r.chance(0.25)) { // edges of the valid ranges
        switch (r.below(6)) {
        case 0:
            c.value.outerAngle = 1.5707f, c.value.innerAngle = 1.5707f;
            break;
        case 1:
            c.value.innerAngle = 0.0f, c.value.outerAngle = 1e-4f;
            break;
        case 2:
            c.value.intensity = 0.0f, c.value.color = Float3(0.0f);
            break;
        case 3:
            c.value.range = 1e-3f;
            break;
        case 4:
            c.value.shadowDepthBias = kMaxShadowBias, c.value.shadowNormalBias = 0.0f;
            break;
        default:
            c.value.range = 1e4f, c.value.intensity = 1e6f;
            break;
        }
        c.what = "edge";
    }
    return c;
}

// One way to break a light, each refused by the module's contract (manylights/lights.h).
inline Candidate<LightDesc> brokenLight(Rng& r) {
    Candidate<LightDesc> c = randomLight(r);
    LightDesc& l = c.value;
    c.broken = true;
    switch (r.below(13)) {
    case 0:
        l.position.x = kNaN, c.what = "NaN position";
        break;
    case 1:
        l.position.z = kInf, c.what = "infinite position";
        break;
    case 2:
        l.kind = LightKind::Spot, l.direction = Float3(0.0f), c.what = "zero spot direction";
        break;
    case 3:
        l.kind = LightKind::Spot, l.outerAngle = 0.0f, l.innerAngle = 0.0f, c.what = "zero cone";
        break;
    case 4:
        l.kind = LightKind::Spot, l.outerAngle = 1.6f, c.what = "cone past pi/2";
        break;
    case 5:
        l.kind = LightKind::Spot, l.outerAngle = 0.3f, l.innerAngle = 0.5f, c.what = "inner > outer";
        break;
    case 6: // a directional light has no range
        l.kind = LightKind::Point, l.unit = LightUnit::Candela;
        l.range = r.chance(0.5) ? -1.0f : kNaN, c.what = "bad range";
        break;
    case 7:
        l.intensity = r.chance(0.5) ? -2.0f : kInf, c.what = "bad intensity";
        break;
    case 8:
        l.color = {1.0f, -0.5f, 1.0f}, c.what = "negative colour";
        break;
    case 9:
        l.shadowDepthBias = kMaxShadowBias * 2, c.what = "bias over the maximum";
        break;
    case 10:
        l.shadowResolution = r.chance(0.5) ? 3u : 1u << 20, c.what = "shadowResolution out of range";
        break;
    case 11:
        l.shadowTexelScale = r.chance(0.5) ? 3.0f : kNaN, c.what = "shadowTexelScale not a power of two";
        break;
    default:
        l.kind = LightKind(3 + r.below(100)), c.what = "unknown kind";
        break;
    }
    return c;
}

inline Candidate<CameraDesc> randomCamera(Rng& r) {
    CameraDesc c;
    c.position = {r.uniform(-10, 10), r.uniform(1, 12), r.uniform(4, 14)};
    c.target = {r.uniform(-2, 2), r.uniform(-1, 1), r.uniform(-2, 2)};
    c.fovY = r.uniform(0.3f, 2.0f);
    c.nearPlane = r.uniform(0.05f, 0.5f);
    c.farPlane = c.nearPlane + r.uniform(5, 300);
    if (r.chance(0.3)) c.jitter = {r.uniform(-1, 1), r.uniform(-1, 1)};
    Candidate<CameraDesc> k{c};
    if (r.chance(0.5)) return k;
    k.broken = true;
    switch (r.below(7)) {
    case 0:
        k.value.position.y = kNaN, k.what = "NaN position";
        break;
    case 1:
        k.value.target = k.value.position, k.what = "target at the position";
        break;
    case 2:
        k.value.target = {k.value.position.x, k.value.position.y - 3, k.value.position.z};
        k.value.up = {0, 1, 0};
        k.what = "up parallel to the view";
        break;
    case 3:
        k.value.fovY = r.chance(0.5) ? 0.0f : 3.2f, k.what = "fovY out of (0, pi)";
        break;
    case 4:
        k.value.farPlane = k.value.nearPlane * 0.5f, k.what = "far before near";
        break;
    case 5:
        k.value.farPlane = kInf, k.what = "infinite far";
        break;
    default:
        k.value.position.x = 2e6f, k.what = "huge position";
        break;
    }
    return k;
}

// The module's conventions for setCameraMatrices: a rigid view, a reversed-Z finite perspective with y
// down. Broken: standard Z (near and far swapped), a NaN entry, a sheared view.
inline Candidate<std::pair<Float4x4, Float4x4>> randomMatrices(Rng& r) {
    const glm::vec3 eye(r.uniform(-8, 8), r.uniform(1, 10), r.uniform(4, 12));
    const glm::mat4 view = glm::lookAt(eye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
    const float nearP = r.uniform(0.05f, 0.5f), farP = nearP + r.uniform(5, 200);
    glm::mat4 proj = glm::perspectiveRH_ZO(r.uniform(0.4f, 1.8f), r.uniform(0.5f, 2.5f), farP, nearP);
    proj[1][1] = -proj[1][1];
    Candidate<std::pair<Float4x4, Float4x4>> c{{view, proj}};
    if (r.chance(0.6)) return c;
    c.broken = true;
    switch (r.below(3)) {
    case 0: {
        glm::mat4 standard = glm::perspectiveRH_ZO(1.0f, 1.5f, nearP, farP);
        standard[1][1] = -standard[1][1];
        c.value.second = standard;
        c.what = "standard Z";
        break;
    }
    case 1:
        c.value.second.m[2][2] = kNaN, c.what = "NaN projection";
        break;
    default:
        c.value.first = glm::scale(view, glm::vec3(1.0f, 2.0f, 1.0f)), c.what = "non-rigid view";
        break;
    }
    return c;
}

struct Geometry {
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
};

// A closed box of half side `s` (CCW faces seen from outside).
inline Geometry box(float s) {
    Geometry m;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
            glm::vec3 n(0.0f), u(0.0f), v(0.0f);
            n[axis] = sign;
            u[(axis + 1) % 3] = 1.0f;
            v[(axis + 2) % 3] = 1.0f;
            if (sign < 0) std::swap(u, v);
            const uint32_t b = uint32_t(m.vertices.size());
            for (glm::vec3 c : {n - u - v, n + u - v, n + u + v, n - u + v})
                m.vertices.push_back({{c.x * s, c.y * s, c.z * s}, {n.x, n.y, n.z}});
            for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(b + k);
        }
    return m;
}

inline Geometry quad(float half) {
    Geometry m;
    for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
        m.vertices.push_back({{c.x * half, 0.0f, c.y * half}, {0.0f, 1.0f, 0.0f}});
    m.indices = {0, 2, 1, 0, 3, 2};
    return m;
}

// A mesh to add, or one broken so that addMesh must refuse it.
inline Candidate<Geometry> randomGeometry(Rng& r) {
    Candidate<Geometry> c{r.chance(0.7) ? box(r.uniform(0.2f, 1.0f)) : quad(r.uniform(4, 10))};
    if (r.chance(0.65)) return c;
    c.broken = true;
    switch (r.below(4)) {
    case 0: // an empty mesh is valid (nothing to draw): an edge, not broken
        c.value.vertices.clear(), c.value.indices.clear(), c.broken = false, c.what = "empty mesh (edge)";
        break;
    case 1:
        c.value.indices.back() = uint32_t(c.value.vertices.size()) + r.below(1000),
        c.what = "index out of range";
        break;
    case 2:
        c.value.indices.pop_back(), c.what = "index count not a multiple of 3";
        break;
    default:
        c.value.vertices[r.below(uint32_t(c.value.vertices.size()))].position[1] = kNaN,
        c.what = "NaN vertex";
        break;
    }
    return c;
}

inline glm::mat4 randomTransform(Rng& r) {
    glm::mat4 t = glm::translate(glm::mat4(1.0f), {r.uniform(-5, 5), r.uniform(0, 3), r.uniform(-5, 5)});
    t = glm::rotate(t, r.uniform(0, 6.28f), glm::normalize(glm::vec3(r.uniform(-1, 1), 1, r.uniform(-1, 1))));
    return glm::scale(t, glm::vec3(r.uniform(0.3f, 1.5f)));
}

inline Candidate<glm::mat4> randomInstanceTransform(Rng& r) {
    Candidate<glm::mat4> c{randomTransform(r)};
    if (r.chance(0.8)) return c;
    c.broken = true;
    switch (r.below(3)) {
    case 0:
        c.value[3][1] = kNaN, c.what = "NaN transform";
        break;
    case 1:
        c.value[0][0] = kInf, c.what = "infinite transform";
        break;
    default:
        c.value = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 0.0f, 1.0f)), c.what = "zero scale";
        break;
    }
    return c;
}

} // namespace ml::fuzz
