// Mesh builders and geometry helpers for the scene sources (see mesh_utils.h).
#include "scenes/mesh_utils.h"

#include <cmath>

namespace ml::detail {
namespace {

// Appends triangle (a, b, c) with a flat normal, reordering it so that its geometric normal agrees with
// `outward`. Deciding the order from the intended side (instead of trusting each call site's corner
// order) is what keeps every builder consistently counter-clockwise-outward.
void addTriangle(Mesh& m, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 outward) {
    glm::vec3 n = glm::cross(b - a, c - a);
    if (glm::dot(n, outward) < 0.0f) {
        std::swap(b, c);
        n = -n;
    }
    float len = glm::length(n);
    n = len > 0.0f ? n / len : glm::normalize(outward);
    auto base = uint32_t(m.vertices.size());
    m.vertices.push_back({a, n});
    m.vertices.push_back({b, n});
    m.vertices.push_back({c, n});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

// Convex quad a-b-c-d (in order around its boundary), split along a-c.
void addQuad(Mesh& m, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 outward) {
    addTriangle(m, a, b, c, outward);
    addTriangle(m, a, c, d, outward);
}

// Vertical walls of a prism over the closed footprint polygon `poly` (x, z), from y0 to y1. The
// polygon may be in either orientation; its signed area decides which side is outside.
void addWalls(Mesh& m, const std::vector<glm::vec2>& poly, float y0, float y1) {
    float area2 = 0.0f;
    for (size_t i = 0; i < poly.size(); ++i) {
        const glm::vec2& p = poly[i];
        const glm::vec2& q = poly[(i + 1) % poly.size()];
        area2 += p.x * q.y - q.x * p.y;
    }
    for (size_t i = 0; i < poly.size(); ++i) {
        const glm::vec2& p = poly[i];
        const glm::vec2& q = poly[(i + 1) % poly.size()];
        glm::vec2 d = q - p;
        glm::vec2 out2 = area2 > 0.0f ? glm::vec2(d.y, -d.x) : glm::vec2(-d.y, d.x);
        glm::vec3 out(out2.x, 0.0f, out2.y);
        addQuad(m, {p.x, y0, p.y}, {q.x, y0, q.y}, {q.x, y1, q.y}, {p.x, y1, p.y}, out);
    }
}

// Horizontal cap as a fan from poly[apex]; valid when that vertex sees every other vertex (any vertex
// of a convex polygon, the reflex vertex of an L).
void addCap(Mesh& m, const std::vector<glm::vec2>& poly, size_t apex, float y, glm::vec3 outward) {
    size_t n = poly.size();
    glm::vec3 a(poly[apex].x, y, poly[apex].y);
    for (size_t k = 1; k + 1 < n; ++k) {
        const glm::vec2& p = poly[(apex + k) % n];
        const glm::vec2& q = poly[(apex + k + 1) % n];
        addTriangle(m, a, {p.x, y, p.y}, {q.x, y, q.y}, outward);
    }
}

std::vector<glm::vec2> rect(glm::vec4 r) {
    return {{r.x, r.y}, {r.z, r.y}, {r.z, r.w}, {r.x, r.w}};
}

const glm::vec3 kUp(0.0f, 1.0f, 0.0f);

// Axis-aligned box [lo, hi] appended to m as 12 outward triangles: the closed variants' sheets.
void addBox(Mesh& m, glm::vec3 lo, glm::vec3 hi) {
    auto poly = rect({lo.x, lo.z, hi.x, hi.z});
    addWalls(m, poly, lo.y, hi.y);
    addCap(m, poly, 0, hi.y, kUp);
    addCap(m, poly, 0, lo.y, -kUp);
}

} // namespace

Mesh makeUnitBox() {
    Mesh m;
    m.name = "unit-box";
    auto poly = rect({-0.5f, -0.5f, 0.5f, 0.5f});
    addWalls(m, poly, 0.0f, 1.0f);
    addCap(m, poly, 0, 1.0f, kUp);
    addCap(m, poly, 0, 0.0f, -kUp);
    m.closed = true;
    return m;
}

Mesh makeLPrism(float notchX, float notchZ, const char* name) {
    Mesh m;
    m.name = name;
    float xc = 0.5f - notchX, zc = 0.5f - notchZ;
    std::vector<glm::vec2> poly = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, zc},
                                   {xc, zc},       {xc, 0.5f},    {-0.5f, 0.5f}};
    addWalls(m, poly, 0.0f, 1.0f);
    addCap(m, poly, 3, 1.0f, kUp); // index 3 is the reflex corner
    addCap(m, poly, 3, 0.0f, -kUp);
    m.closed = true;
    return m;
}

Mesh makeSteppedBox(glm::vec4 base, float baseHeight, glm::vec4 top, float topHeight, const char* name) {
    Mesh m;
    m.name = name;
    auto outer = rect(base), inner = rect(top);
    addWalls(m, outer, 0.0f, baseHeight);
    addCap(m, outer, 0, 0.0f, -kUp);
    // Podium roof: one trapezoid per side between the outer and the inner rectangle; its edges are
    // exactly the podium's top edges and the tower's bottom edges, so the mesh stays watertight.
    for (size_t i = 0; i < 4; ++i) {
        size_t j = (i + 1) % 4;
        addQuad(m, {outer[i].x, baseHeight, outer[i].y}, {outer[j].x, baseHeight, outer[j].y},
                {inner[j].x, baseHeight, inner[j].y}, {inner[i].x, baseHeight, inner[i].y}, kUp);
    }
    addWalls(m, inner, baseHeight, topHeight);
    addCap(m, inner, 0, topHeight, kUp);
    m.closed = true;
    return m;
}

Mesh makeUnitQuad(float thickness) {
    Mesh m;
    if (thickness > 0.0f) {
        m.name = "unit-slab";
        addBox(m, {-0.5f, -thickness, 0.0f}, {0.5f, 0.0f, 1.0f});
        m.closed = true;
        return m;
    }
    m.name = "unit-quad";
    addQuad(m, {-0.5f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.5f, 0.0f, 1.0f}, {-0.5f, 0.0f, 1.0f}, kUp);
    return m;
}

Mesh makeFence(int pickets, float thickness) {
    Mesh m;
    m.name = thickness > 0.0f ? "fence-closed" : "fence";
    const glm::vec3 front(0.0f, 0.0f, 1.0f);
    float pitch = 1.0f / float(pickets), half = 0.25f * pitch;
    for (int i = 0; i < pickets; ++i) {
        float cx = -0.5f + (float(i) + 0.5f) * pitch;
        if (thickness > 0.0f) {
            addBox(m, {cx - half, 0.0f, -thickness}, {cx + half, 1.0f, 0.0f});
            continue;
        }
        addQuad(m, {cx - half, 0.0f, 0.0f}, {cx + half, 0.0f, 0.0f}, {cx + half, 1.0f, 0.0f},
                {cx - half, 1.0f, 0.0f}, front);
    }
    for (float y : {0.2f, 0.72f}) {
        if (thickness > 0.0f) {
            addBox(m, {-0.5f, y, 0.02f}, {0.5f, y + 0.08f, 0.02f + thickness});
            continue;
        }
        addQuad(m, {-0.5f, y, 0.02f}, {0.5f, y, 0.02f}, {0.5f, y + 0.08f, 0.02f}, {-0.5f, y + 0.08f, 0.02f},
                front);
    }
    m.closed = thickness > 0.0f;
    return m;
}

Mesh makeFoliageCards(float thickness) {
    Mesh m;
    m.name = thickness > 0.0f ? "foliage-slabs" : "foliage-cards";
    if (thickness > 0.0f) {
        // Crossed slabs: two overlapping closed boxes, their union is what the dual depth map sees.
        float h = 0.5f * thickness;
        addBox(m, {-0.5f, 0.0f, -h}, {0.5f, 1.0f, h});
        addBox(m, {-h, 0.0f, -0.5f}, {h, 1.0f, 0.5f});
        m.closed = true;
        return m;
    }
    addQuad(m, {-0.5f, 0.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.5f, 1.0f, 0.0f}, {-0.5f, 1.0f, 0.0f}, {0, 0, 1});
    addQuad(m, {0.0f, 0.0f, -0.5f}, {0.0f, 0.0f, 0.5f}, {0.0f, 1.0f, 0.5f}, {0.0f, 1.0f, -0.5f}, {1, 0, 0});
    return m;
}

glm::mat4 frameMatrix(const glm::vec3& origin, const glm::vec3& xAxis, const glm::vec3& yAxis,
                      const glm::vec3& zAxis) {
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(xAxis, 0.0f);
    m[1] = glm::vec4(yAxis, 0.0f);
    m[2] = glm::vec4(zAxis, 0.0f);
    m[3] = glm::vec4(origin, 1.0f);
    return m;
}

bool meshBounds(const Mesh& mesh, glm::vec3& lo, glm::vec3& hi) {
    if (mesh.vertices.empty()) return false;
    lo = hi = mesh.vertices[0].position;
    for (const Vertex& v : mesh.vertices) {
        lo = glm::min(lo, v.position);
        hi = glm::max(hi, v.position);
    }
    return true;
}

void makeFlatNormals(Mesh& mesh) {
    std::vector<Vertex> verts;
    verts.reserve(mesh.indices.size());
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        glm::vec3 a = mesh.vertices[mesh.indices[t]].position;
        glm::vec3 b = mesh.vertices[mesh.indices[t + 1]].position;
        glm::vec3 c = mesh.vertices[mesh.indices[t + 2]].position;
        glm::vec3 n = glm::cross(b - a, c - a);
        float len = glm::length(n);
        // Degenerate triangles get an arbitrary unit normal: they cover no pixels anyway.
        n = (len > 0.0f && std::isfinite(len)) ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
        verts.push_back({a, n});
        verts.push_back({b, n});
        verts.push_back({c, n});
    }
    mesh.vertices = std::move(verts);
    for (size_t i = 0; i < mesh.indices.size(); ++i) mesh.indices[i] = uint32_t(i);
}

} // namespace ml::detail
