// Tests of the ray-traced visibility reference: analytic occluders whose shadows are known in closed form,
// the bias rules, the batch path against the single-ray path, the accuracy measure, and a timing run on the
// shared glTF house.
#include "bake/reference/raytrace.h"

#include "scenes/scenes.h"
#include "tests/common/shared_scenes.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace ml {
namespace {

Mesh makeMesh(const std::string& name, const std::vector<glm::vec3>& positions,
              std::vector<uint32_t> indices) {
    Mesh m;
    m.name = name;
    for (glm::vec3 p : positions) m.vertices.push_back({p, glm::vec3(0.0f, 1.0f, 0.0f)});
    m.indices = std::move(indices);
    return m;
}

// Closed, outward-facing box.
Mesh boxMesh(glm::vec3 lo, glm::vec3 hi) {
    std::vector<glm::vec3> p;
    for (int i = 0; i < 8; ++i)
        p.push_back(glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z));
    Mesh m = makeMesh("box", p, {0, 2, 1, 1, 2, 3,   // -z
                                 4, 5, 6, 5, 7, 6,   // +z
                                 0, 1, 4, 1, 5, 4,   // -y
                                 2, 6, 3, 3, 6, 7,   // +y
                                 0, 4, 2, 2, 4, 6,   // -x
                                 1, 3, 5, 3, 7, 5}); // +x
    m.closed = true;
    return m;
}

// Open quad in the z = 0 plane, x and y in [-h, h]; its diagonal runs from (-h, -h) to (h, h).
Mesh quadMesh(float h) {
    return makeMesh("quad", {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}}, {0, 1, 2, 0, 2, 3});
}

// n x n cells in the y = 0 plane over [-h, h]^2, facing +y.
Mesh gridMesh(float h, int n) {
    std::vector<glm::vec3> p;
    std::vector<uint32_t> idx;
    for (int z = 0; z <= n; ++z)
        for (int x = 0; x <= n; ++x) p.push_back({-h + 2 * h * x / n, 0.0f, -h + 2 * h * z / n});
    for (int z = 0; z < n; ++z)
        for (int x = 0; x < n; ++x) {
            uint32_t a = z * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
            idx.insert(idx.end(), {a, c, b, b, c, d});
        }
    return makeMesh("grid", p, idx);
}

uint32_t addMesh(Scene& s, Mesh m) {
    s.meshes.push_back(std::move(m));
    return uint32_t(s.meshes.size() - 1);
}

void addInstance(Scene& s, uint32_t mesh, glm::mat4 transform = glm::mat4(1.0f), bool dynamic = false) {
    Instance inst;
    inst.mesh = mesh;
    inst.transform = transform;
    inst.dynamic = dynamic;
    s.instances.push_back(inst);
}

RayReference buildOrDie(const Scene& s, bool staticOnly = true) {
    auto r = RayReference::build(s, staticOnly);
    EXPECT_TRUE(r.ok()) << r.error();
    return std::move(r.value());
}

// --- analytic box shadow ------------------------------------------------------------------------------

using Vec2 = glm::dvec2;

double cross2(Vec2 o, Vec2 a, Vec2 b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Andrew's monotone chain; counter-clockwise hull.
std::vector<Vec2> convexHull(std::vector<Vec2> pts) {
    std::sort(pts.begin(), pts.end(), [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    std::vector<Vec2> h(2 * pts.size());
    size_t k = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        while (k >= 2 && cross2(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
        h[k++] = pts[i];
    }
    for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
        while (k >= t && cross2(h[k - 2], h[k - 1], pts[i - 1]) <= 0) --k;
        h[k++] = pts[i - 1];
    }
    h.resize(k - 1);
    return h;
}

// Signed distance to a convex counter-clockwise polygon: negative inside.
double signedDistance(const std::vector<Vec2>& poly, Vec2 p) {
    double outside = 1e30, inside = -1e30;
    bool in = true;
    for (size_t i = 0; i < poly.size(); ++i) {
        Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        Vec2 e = b - a;
        double side = cross2(a, b, p) / glm::length(e); // > 0: left of the edge, i.e. inside
        if (side < 0) in = false;
        inside = std::max(inside, -side);
        double t = std::clamp(glm::dot(p - a, e) / glm::dot(e, e), 0.0, 1.0);
        outside = std::min(outside, glm::length(p - (a + t * e)));
    }
    return in ? inside : outside;
}

TEST(ReferenceBox, ShadowFootprintMatchesProjectedBox) {
    Scene s;
    addInstance(s, addMesh(s, gridMesh(8.0f, 4)));
    // Unit box floating between the ground and the light.
    const glm::vec3 lo(-0.5f, 1.0f, -0.5f), hi(0.5f, 2.0f, 0.5f);
    addInstance(s, addMesh(s, boxMesh(lo, hi)));
    RayReference ref = buildOrDie(s);
    EXPECT_EQ(ref.triangleCount(), 4u * 4u * 2u + 12u);

    const glm::vec3 lights[] = {{0.3f, 4.0f, 0.2f}, {-1.7f, 3.1f, 0.9f}, {0.0f, 2.5f, 0.0f}};
    for (glm::vec3 L : lights) {
        // The shadow on y = 0 is the convex hull of the box corners projected from the light.
        std::vector<Vec2> proj;
        for (int i = 0; i < 8; ++i) {
            glm::dvec3 c(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
            glm::dvec3 l(L);
            double t = l.y / (l.y - c.y);
            glm::dvec3 q = l + (c - l) * t;
            proj.push_back({q.x, q.z});
        }
        std::vector<Vec2> hull = convexHull(proj);
        ASSERT_GE(hull.size(), 4u);

        const double margin = 0.01;
        std::vector<glm::vec3> receivers;
        std::vector<uint8_t> expected;
        const int n = 160;
        for (int z = 0; z < n; ++z)
            for (int x = 0; x < n; ++x) {
                glm::vec3 p(-7.5f + 15.0f * (x + 0.37f) / n, 0.0f, -7.5f + 15.0f * (z + 0.61f) / n);
                double d = signedDistance(hull, {p.x, p.z});
                if (std::abs(d) < margin) continue; // too close to the penumbra-free edge to call
                receivers.push_back(p);
                expected.push_back(d > 0 ? 1 : 0);
            }
        size_t shadowed = std::count(expected.begin(), expected.end(), uint8_t(0));
        ASSERT_GT(shadowed, 200u) << "light " << L.x << "," << L.y << "," << L.z;
        ASSERT_GT(expected.size() - shadowed, 200u);

        std::vector<glm::vec3> normals(receivers.size(), glm::vec3(0.0f, 1.0f, 0.0f));
        std::vector<uint8_t> batch(receivers.size());
        ref.visibleBatch(receivers.data(), normals.data(), receivers.size(), L, 1e-3f, batch.data());
        size_t wrongSingle = 0, wrongBatch = 0;
        for (size_t i = 0; i < receivers.size(); ++i) {
            wrongSingle += ref.visible(receivers[i], L, 1e-3f) != bool(expected[i]);
            wrongBatch += batch[i] != expected[i];
        }
        EXPECT_EQ(wrongSingle, 0u) << "of " << receivers.size() << ", light " << L.x << "," << L.y << ","
                                   << L.z;
        EXPECT_EQ(wrongBatch, 0u) << "of " << receivers.size() << ", light " << L.x << "," << L.y << ","
                                  << L.z;
    }
}

// --- thin open quad ------------------------------------------------------------------------------------

TEST(ReferenceQuad, ReceiverExactlyBehindThinQuadIsOccluded) {
    Scene s;
    addInstance(s, addMesh(s, quadMesh(1.0f)));
    RayReference ref = buildOrDie(s);
    // Straight through the centre, which lies on the diagonal shared by the quad's two triangles: a
    // non-watertight test could let this ray slip through the crack.
    EXPECT_FALSE(ref.visible({0, 0, -1}, {0, 0, 5}, 1e-3f));
    // Through other points of the shared diagonal, at an angle.
    EXPECT_FALSE(ref.visible({0.5f, 0.5f, -2}, {0.5f, 0.5f, 3}, 1e-3f));
    EXPECT_FALSE(ref.visible({-0.4f, 0.2f, -1}, {1.4f, 0.2f, 2}, 1e-3f)); // crosses z = 0 at (0.2, 0.2)
    // Open geometry blocks from both sides (no back-face culling).
    EXPECT_FALSE(ref.visible({0, 0, 1}, {0, 0, -5}, 1e-3f));
    // Oblique ray crossing z = 0 at x = 0.5: occluded; one crossing at x = 2.08: not.
    EXPECT_FALSE(ref.visible({0, 0, -1}, {3, 0, 5}, 1e-3f));
    EXPECT_TRUE(ref.visible({2.5f, 0, -1}, {0, 0, 5}, 1e-3f));
    // Beside the quad, and in front of it (the quad is behind the light).
    EXPECT_TRUE(ref.visible({1.5f, 0, -1}, {1.5f, 0, 5}, 1e-3f));
    EXPECT_TRUE(ref.visible({0, 0, 1}, {0, 0, 5}, 1e-3f));
    // A receiver on the quad itself, on the side facing the light: the bias keeps it lit.
    EXPECT_TRUE(ref.visible({0.2f, 0.1f, 0}, {0, 0, 5}, 1e-3f));
    // ...and the same point with the light on the other side is lit from that side too.
    EXPECT_TRUE(ref.visible({0.2f, 0.1f, 0}, {0, 0, -5}, 1e-3f));

    // The batch path agrees, with either normal orientation (flipped towards the light).
    glm::vec3 recv[] = {{0, 0, -1}, {0.2f, 0.1f, 0}, {0.2f, 0.1f, 0}, {1.5f, 0, -1}};
    glm::vec3 nrm[] = {{0, 0, -1}, {0, 0, 1}, {0, 0, -1}, {0, 0, 1}};
    uint8_t out[4];
    ref.visibleBatch(recv, nrm, 4, {0, 0, 5}, 1e-3f, out);
    EXPECT_EQ(out[0], 0);
    EXPECT_EQ(out[1], 1);
    EXPECT_EQ(out[2], 1);
    EXPECT_EQ(out[3], 1);
}

// --- light inside a closed box ---------------------------------------------------------------------------

TEST(ReferenceClosedBox, LightInsideSeesNothingOutside) {
    Scene s;
    addInstance(s, addMesh(s, boxMesh(glm::vec3(-1.0f), glm::vec3(1.0f))));
    RayReference ref = buildOrDie(s);
    const glm::vec3 light(0.0f);

    // Directions through the faces, and exactly through every edge midpoint and corner of the box, where a
    // ray meets two or three triangles at their shared boundary.
    std::vector<glm::vec3> dirs;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z)
                if (x || y || z) dirs.push_back(glm::normalize(glm::vec3(x, y, z)));
    std::mt19937 rng(7);
    std::normal_distribution<float> g;
    for (int i = 0; i < 20000; ++i) dirs.push_back(glm::normalize(glm::vec3(g(rng), g(rng), g(rng))));

    std::vector<glm::vec3> receivers;
    for (glm::vec3 d : dirs) receivers.push_back(light + 3.0f * d);
    size_t leaks = 0;
    for (glm::vec3 r : receivers) leaks += ref.visible(r, light, 1e-3f);
    EXPECT_EQ(leaks, 0u);
    std::vector<uint8_t> out(receivers.size());
    ref.visibleBatch(receivers.data(), nullptr, receivers.size(), light, 1e-3f, out.data());
    EXPECT_EQ(std::count(out.begin(), out.end(), uint8_t(1)), 0);
    // A receiver inside the box sees the light.
    EXPECT_TRUE(ref.visible({0.5f, -0.7f, 0.2f}, light, 1e-3f));
}

// --- static only ------------------------------------------------------------------------------------------

TEST(ReferenceStaticOnly, ExcludesDynamicInstances) {
    Scene s;
    uint32_t box = addMesh(s, boxMesh(glm::vec3(-0.5f), glm::vec3(0.5f)));
    addInstance(s, addMesh(s, gridMesh(5.0f, 1)));
    // A car-like dynamic box between the receiver and the light.
    addInstance(s, box, glm::translate(glm::mat4(1.0f), glm::vec3(0, 2, 0)), true);
    const glm::vec3 receiver(0, 0, 0), light(0, 5, 0);

    RayReference staticRef = buildOrDie(s, true);
    EXPECT_EQ(staticRef.geometryCount(), 1u);
    EXPECT_TRUE(staticRef.visible(receiver, light, 1e-3f));
    RayReference allRef = buildOrDie(s, false);
    EXPECT_EQ(allRef.geometryCount(), 2u);
    EXPECT_FALSE(allRef.visible(receiver, light, 1e-3f));

    // The same box made static blocks in both.
    s.instances[1].dynamic = false;
    EXPECT_FALSE(buildOrDie(s, true).visible(receiver, light, 1e-3f));
}

// --- bias -------------------------------------------------------------------------------------------------

TEST(ReferenceBias, PlaneFacingLightIsNotSelfShadowed) {
    Scene s;
    // A finely tessellated plane, tilted and far from the origin so that world coordinates carry float
    // rounding, like a wall of a city block.
    glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(180.0f, 12.0f, -140.0f));
    m = glm::rotate(m, 0.7f, glm::normalize(glm::vec3(1, 0.3f, -0.5f)));
    addInstance(s, addMesh(s, gridMesh(10.0f, 64)), m);
    RayReference ref = buildOrDie(s);
    glm::vec3 normal = glm::normalize(glm::vec3(m * glm::vec4(0, 1, 0, 0)));
    glm::vec3 origin(m * glm::vec4(0, 0, 0, 1));

    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-9.5f, 9.5f);
    std::vector<glm::vec3> receivers, normals;
    for (int i = 0; i < 20000; ++i) {
        receivers.push_back(glm::vec3(m * glm::vec4(u(rng), 0, u(rng), 1)));
        normals.push_back(normal);
    }
    // Lights in front of the plane: head-on, oblique, and grazing (2 to 6 degrees above the plane).
    glm::vec3 tangent = glm::normalize(glm::vec3(m * glm::vec4(1, 0, 0, 0)));
    const glm::vec3 lights[] = {origin + 6.0f * normal, origin + 3.0f * normal + 4.0f * tangent,
                                origin + 1.0f * normal + 19.0f * tangent};
    for (size_t l = 0; l < 3; ++l) {
        size_t single = 0;
        for (glm::vec3 r : receivers) single += !ref.visible(r, lights[l], 1e-3f);
        std::vector<uint8_t> out(receivers.size());
        ref.visibleBatch(receivers.data(), normals.data(), receivers.size(), lights[l], 1e-3f, out.data());
        size_t batch = std::count(out.begin(), out.end(), uint8_t(0));
        // Along the ray the grazing light moves origins only bias * sin(2..6 deg) off the plane: that case is
        // what the normal offset of the batch is for, so only the batch must be perfect there.
        if (l < 2) {
            EXPECT_EQ(single, 0u) << "light " << l;
        }
        EXPECT_EQ(batch, 0u) << "light " << l;
        // Flipped normals (receivers of a two-sided surface seen from behind) give the same answer.
        std::vector<glm::vec3> flipped(normals.size(), -normal);
        ref.visibleBatch(receivers.data(), flipped.data(), receivers.size(), lights[l], 1e-3f, out.data());
        EXPECT_EQ(std::count(out.begin(), out.end(), uint8_t(0)), 0) << "light " << l;
        std::printf("[ reference ] self-shadowed receivers, light %zu: single %zu, batch %zu of %zu\n", l,
                    single, batch, receivers.size());
    }
}

// --- batch against single ------------------------------------------------------------------------------

Scene clutter(uint32_t seed) {
    Scene s;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f), size(0.2f, 2.0f), angle(0.0f, 6.283f);
    addInstance(s, addMesh(s, gridMesh(12.0f, 8)));
    uint32_t box = addMesh(s, boxMesh(glm::vec3(-0.5f), glm::vec3(0.5f)));
    uint32_t quad = addMesh(s, quadMesh(0.5f));
    for (int i = 0; i < 120; ++i) {
        glm::mat4 m = glm::translate(glm::mat4(1.0f), glm::vec3(u(rng), std::abs(u(rng)) * 0.4f, u(rng)));
        m = glm::rotate(m, angle(rng), glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.01f)));
        m = glm::scale(m, glm::vec3(size(rng), size(rng), size(rng)));
        addInstance(s, i % 3 ? box : quad, m, i % 7 == 0);
    }
    return s;
}

TEST(ReferenceBatch, EqualsSingleOnRandomPoints) {
    Scene s = clutter(11);
    RayReference ref = buildOrDie(s);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-11.0f, 11.0f), h(0.0f, 6.0f);
    std::normal_distribution<float> g;
    const size_t n = 20011; // not a multiple of the packet width or of the thread chunk
    std::vector<glm::vec3> receivers(n), normals(n);
    for (size_t i = 0; i < n; ++i) {
        receivers[i] = {u(rng), h(rng), u(rng)};
        normals[i] = {g(rng), g(rng), g(rng)};
    }
    size_t differentWithNormals = 0, shadowed = 0;
    for (int l = 0; l < 4; ++l) {
        glm::vec3 light(u(rng), 2.0f + h(rng), u(rng));
        std::vector<uint8_t> batch(n), batchNormals(n);
        ref.visibleBatch(receivers.data(), nullptr, n, light, 1e-3f, batch.data());
        ref.visibleBatch(receivers.data(), normals.data(), n, light, 1e-3f, batchNormals.data());
        size_t different = 0;
        for (size_t i = 0; i < n; ++i) {
            bool single = ref.visible(receivers[i], light, 1e-3f);
            different += batch[i] != uint8_t(single);
            differentWithNormals += batchNormals[i] != uint8_t(single);
            shadowed += !single;
        }
        EXPECT_EQ(different, 0u) << "light " << l;
        // Single-threaded batches give the same bits.
        ref.setThreads(1);
        std::vector<uint8_t> serial(n);
        ref.visibleBatch(receivers.data(), nullptr, n, light, 1e-3f, serial.data());
        EXPECT_EQ(serial, batch);
        ref.setThreads(2);
    }
    // Points in free space: moving the origin 1 mm along a normal changes the answer only for rays grazing
    // a silhouette within about a millimetre.
    EXPECT_LE(differentWithNormals, 4 * n / 1000);
    EXPECT_GT(shadowed, 4 * n / 20); // the clutter actually casts shadows
    std::printf("[ reference ] packet width %d, %zu of %zu shadowed, %zu differ with normal offset\n",
                ref.packetWidth(), shadowed, 4 * n, differentWithNormals);
}

// --- accuracy measure -------------------------------------------------------------------------------------

TEST(ReferenceCompare, CountsMismatchesAndMeanAbsDiff) {
    std::vector<float> method = {1.0f, 0.0f, 0.6f, 0.4f, 0.5f, 0.49f, NAN, 2.0f};
    std::vector<uint8_t> truth = {1, 0, 0, 1, 1, 1, 1, 1};
    Disagreement d = compareVisibility(method, truth);
    EXPECT_EQ(d.compared, 8u);
    // 0.6 vs 0: mismatch; 0.4 vs 1: mismatch; 0.5 counts as lit; 0.49 vs 1: mismatch; NaN: mismatch.
    EXPECT_EQ(d.mismatches, 4u);
    EXPECT_DOUBLE_EQ(d.rate(), 0.5);
    double expected = (0 + 0 + 0.6 + 0.6 + 0.5 + 0.51 + 1.0 + 0.0) / 8.0;
    EXPECT_NEAR(d.meanAbsDiff, expected, 1e-6);

    std::vector<uint8_t> include = {1, 1, 1, 0, 0, 0, 0, 1};
    Disagreement masked = compareVisibility(method, truth, include);
    EXPECT_EQ(masked.compared, 4u);
    EXPECT_EQ(masked.mismatches, 1u);
    EXPECT_NEAR(masked.meanAbsDiff, 0.6 / 4.0, 1e-6);

    Disagreement pooled = masked;
    pooled.merge(d);
    EXPECT_EQ(pooled.compared, 12u);
    EXPECT_EQ(pooled.mismatches, 5u);
    EXPECT_NEAR(pooled.meanAbsDiff, (0.6 + expected * 8) / 12.0, 1e-6);

    EXPECT_EQ(compareVisibility({}, {}).rate(), 0.0);
}

TEST(ReferenceCone, SpotAndPointLights) {
    Light spot;
    spot.type = LightKind::Spot;
    spot.position = {0, 5, 0};
    spot.direction = {0, -1, 0};
    spot.outerAngle = 0.5f;
    spot.range = 10.0f;
    EXPECT_TRUE(inLightCone(spot, {0, 0, 0}));
    float r = 5.0f * std::tan(0.5f);
    EXPECT_TRUE(inLightCone(spot, {r * 0.99f, 0, 0}));
    EXPECT_FALSE(inLightCone(spot, {r * 1.01f, 0, 0}));
    EXPECT_FALSE(inLightCone(spot, {0, 6, 0}));     // behind
    EXPECT_FALSE(inLightCone(spot, {0, -5.5f, 0})); // in the cone but beyond range
    EXPECT_FALSE(inLightCone(spot, spot.position)); // no direction
    spot.outerAngle = 3.2f;
    EXPECT_TRUE(inLightCone(spot, {0, 6, 0})); // a cone wider than a hemisphere reaches behind

    Light point;
    point.type = LightKind::Point;
    point.position = {1, 1, 1};
    point.range = 2.0f;
    EXPECT_TRUE(inLightCone(point, {1, 1, 1}));
    EXPECT_TRUE(inLightCone(point, {1, -0.9f, 1}));
    EXPECT_FALSE(inLightCone(point, {1, -1.0f, 1})); // distance == range is out
    Light sun;
    sun.type = LightKind::Directional;
    EXPECT_TRUE(inLightCone(sun, {1e4f, 0, 0}));
}

// --- errors -----------------------------------------------------------------------------------------------

TEST(ReferenceBuild, ReportsBadInputInOneLine) {
    Scene s;
    addInstance(s, 3);
    auto r = RayReference::build(s);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("instance 0"), std::string::npos) << r.error();

    Scene t;
    addInstance(t, addMesh(t, makeMesh("broken", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 5})));
    r = RayReference::build(t);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("broken"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("index 5"), std::string::npos) << r.error();

    // Embree's errors come back as one line. A malformed device configuration is the one Embree error the
    // inputs can provoke (geometry is validated before Embree sees it); it fails before the device exists,
    // so only Embree's error code is available, not a callback message.
    Scene ok;
    addInstance(ok, addMesh(ok, quadMesh(1.0f)));
    r = RayReference::build(ok, true, "threads=abc");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("Embree"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("threads=abc"), std::string::npos) << r.error();
    EXPECT_EQ(r.error().find('\n'), std::string::npos) << r.error();
    auto single = RayReference::build(ok, true, "threads=1");
    ASSERT_TRUE(single.ok()) << single.error();
    EXPECT_FALSE(single->visible({0, 0, -1}, {0, 0, 1}, 1e-3f));

    // An empty scene is fine: everything is visible.
    Scene empty;
    auto e = RayReference::build(empty);
    ASSERT_TRUE(e.ok()) << e.error();
    EXPECT_TRUE(e->visible({0, 0, 0}, {1, 1, 1}, 1e-3f));
}

// --- the shared house -------------------------------------------------------------------------------------

TEST(ReferenceScene, FzkHausBuildsAndReportsRaysPerSecond) {
    ML_SKIP_WITHOUT_SHARED();
    const std::string path = test::sharedScenePath("fzk-haus.glb");
    auto loaded = loadScene(path, 16, 1);
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    const Scene& scene = loaded.value();

    auto t0 = std::chrono::steady_clock::now();
    auto built = RayReference::build(scene);
    double buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(built.ok()) << built.error();
    RayReference& ref = built.value();
    EXPECT_GT(ref.triangleCount(), 0u);

    // Receivers: a 320x180 frame's worth of points sampled on the static triangles by area, with their
    // face normals.
    std::vector<glm::vec3> tris; // 3 world-space vertices per triangle
    std::vector<double> cdf;
    double area = 0;
    for (const Instance& inst : scene.instances) {
        if (inst.dynamic) continue;
        const Mesh& m = scene.meshes[inst.mesh];
        for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
            glm::vec3 v[3];
            for (int k = 0; k < 3; ++k)
                v[k] = glm::vec3(inst.transform * glm::vec4(m.vertices[m.indices[i + k]].position, 1.0f));
            area += 0.5 * glm::length(glm::cross(v[1] - v[0], v[2] - v[0]));
            tris.insert(tris.end(), v, v + 3);
            cdf.push_back(area);
        }
    }
    ASSERT_GT(area, 0.0);
    const size_t frame = 320 * 180;
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    // Sorted by triangle so that neighbouring receivers lie on the same surface, as in a G-buffer read in
    // screen order: packets then hold rays that start close together, which is the case packets are for.
    std::vector<size_t> triangleOf(frame);
    for (size_t& t : triangleOf)
        t = std::min<size_t>(std::lower_bound(cdf.begin(), cdf.end(), u(rng) * area) - cdf.begin(),
                             cdf.size() - 1);
    std::sort(triangleOf.begin(), triangleOf.end());
    std::vector<glm::vec3> receivers(frame), normals(frame);
    for (size_t i = 0; i < frame; ++i) {
        size_t t = triangleOf[i];
        float a = float(u(rng)), b = float(u(rng));
        if (a + b > 1) {
            a = 1 - a;
            b = 1 - b;
        }
        glm::vec3 p0 = tris[3 * t], p1 = tris[3 * t + 1], p2 = tris[3 * t + 2];
        receivers[i] = p0 + a * (p1 - p0) + b * (p2 - p0);
        normals[i] = glm::cross(p1 - p0, p2 - p0);
    }

    // The single-ray path on every light's cone, and the batch without normals must agree with it exactly;
    // the batch with normals shows how much the choice of offset matters on a real asset.
    uint64_t raysSingle = 0, differByOffset = 0;
    double singleSeconds = 0;
    std::vector<glm::vec3> inCone, inConeNormals;
    std::vector<uint8_t> out, outNoNormals;
    for (const Light& light : scene.lights) {
        inCone.clear();
        inConeNormals.clear();
        for (size_t i = 0; i < frame; ++i)
            if (inLightCone(light, receivers[i])) {
                inCone.push_back(receivers[i]);
                inConeNormals.push_back(normals[i]);
            }
        std::vector<uint8_t> single(inCone.size());
        auto s0 = std::chrono::steady_clock::now();
        for (size_t i = 0; i < inCone.size(); ++i) single[i] = ref.visible(inCone[i], light.position, 1e-3f);
        singleSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
        raysSingle += inCone.size();
        out.resize(inCone.size());
        outNoNormals.resize(inCone.size());
        ref.visibleBatch(inCone.data(), nullptr, inCone.size(), light.position, 1e-3f, outNoNormals.data());
        ref.visibleBatch(inCone.data(), inConeNormals.data(), inCone.size(), light.position, 1e-3f,
                         out.data());
        EXPECT_EQ(outNoNormals, single);
        for (size_t i = 0; i < out.size(); ++i) differByOffset += out[i] != single[i];
    }

    // A frame: 200 lights (the scene's 16, cycled), each tracing only the receivers in its cone; the cone
    // test is timed too.
    uint64_t rays = 0, lit = 0;
    double batchSeconds = 0;
    auto f0 = std::chrono::steady_clock::now();
    for (int l = 0; l < 200; ++l) {
        const Light& light = scene.lights[l % scene.lights.size()];
        inCone.clear();
        inConeNormals.clear();
        for (size_t i = 0; i < frame; ++i)
            if (inLightCone(light, receivers[i])) {
                inCone.push_back(receivers[i]);
                inConeNormals.push_back(normals[i]);
            }
        out.resize(inCone.size());
        auto b0 = std::chrono::steady_clock::now();
        ref.visibleBatch(inCone.data(), inConeNormals.data(), inCone.size(), light.position, 1e-3f,
                         out.data());
        batchSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - b0).count();
        rays += inCone.size();
        lit += std::count(out.begin(), out.end(), uint8_t(1));
    }
    double frameSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - f0).count();
    ASSERT_GT(rays, 0u);

    // Every receiver towards one light: a batch large enough for both threads.
    glm::vec3 centre = 0.5f * (scene.boundsMin + scene.boundsMax) + glm::vec3(0.0f, 1.0f, 0.0f);
    out.resize(frame);
    double wide[2] = {0, 0};
    for (unsigned t = 1; t <= 2; ++t) {
        ref.setThreads(t);
        auto w0 = std::chrono::steady_clock::now();
        for (int rep = 0; rep < 4; ++rep)
            ref.visibleBatch(receivers.data(), normals.data(), frame, centre, 1e-3f, out.data());
        wide[t - 1] = 4.0 * double(frame) /
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    }

    double rate = double(rays) / std::max(batchSeconds, 1e-9);
    std::printf("[ reference ] fzk-haus: %zu instances, %llu triangles, build %.3f s, packet width %d\n",
                scene.instances.size(), (unsigned long long)ref.triangleCount(), buildSeconds,
                ref.packetWidth());
    std::printf("[ reference ] single rays: %llu in %.3f s = %.2f Mrays/s (rtcOccluded1, 1 thread)\n",
                (unsigned long long)raysSingle, singleSeconds, double(raysSingle) / singleSeconds * 1e-6);
    std::printf("[ reference ] normal offset vs ray offset: %llu of %llu receivers differ\n",
                (unsigned long long)differByOffset, (unsigned long long)raysSingle);
    std::printf(
        "[ reference ] frame 320x180 x 200 lights: %llu rays (%.1f%% lit), %.3f s tracing = %.2f Mrays/s, "
        "%.3f s with cone tests\n",
        (unsigned long long)rays, 100.0 * double(lit) / double(rays), batchSeconds, rate * 1e-6,
        frameSeconds);
    std::printf("[ reference ] one light, all %zu receivers: %.2f Mrays/s on 1 thread, %.2f on 2\n", frame,
                wide[0] * 1e-6, wide[1] * 1e-6);
    std::printf("[ reference ] worst case, every receiver in all 200 cones: %.1f s\n",
                double(frame) * 200.0 / std::max(wide[0], wide[1]));
    // Seconds, not minutes, even if every receiver were in every cone.
    EXPECT_LT(double(frame) * 200.0 / std::max(wide[0], wide[1]), 60.0);
}

} // namespace
} // namespace ml
