// CPU reference rasteriser: analytic checks at every texel (closed box: enter = front face, exit = back
// or side face; open quad: exit = enter; misses: empty), tiling, far-plane and inside-a-mesh rules, and
// the slot rasteriser against the plain hit list at every texel.
#include "static_test_util.h"
#include "bake/scene_casters.h"
#include "scenes/scenes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace ml::stest {
namespace {

// Axis-aligned box with outward, counter-clockwise faces.
void addBox(CasterTriangles& c, glm::vec3 lo, glm::vec3 hi, bool closed) {
    glm::vec3 center = (lo + hi) * 0.5f;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            glm::vec3 n(0.0f);
            n[axis] = side ? 1.0f : -1.0f;
            int u = (axis + 1) % 3, v = (axis + 2) % 3;
            glm::vec3 p[4];
            for (int k = 0; k < 4; ++k) {
                p[k][axis] = side ? hi[axis] : lo[axis];
                p[k][u] = (k == 1 || k == 2) ? hi[u] : lo[u];
                p[k][v] = (k >= 2) ? hi[v] : lo[v];
            }
            glm::vec3 face = glm::cross(p[1] - p[0], p[2] - p[0]);
            if (glm::dot(face, n) < 0.0f) std::swap(p[1], p[3]);
            (void)center;
            c.add(p[0], p[1], p[2], closed);
            c.add(p[0], p[2], p[3], closed);
        }
}

LightFrustum originFrustum() {
    LightFrustum f; // view = identity: light at the origin looking down -Z
    f.fov = 1.0f;
    f.nearPlane = 0.05f;
    f.farPlane = 10.0f;
    return f;
}

TEST(StaticRaster, ClosedBoxEnterExitAnalytic) {
    CasterTriangles c;
    addBox(c, {-1, -1, -7}, {1, 1, -5}, true);
    const uint32_t res = 256;
    LightFrustum f = originFrustum();
    DualDepthMap m = rasterizeDual(c, f, res);
    const double t = std::tan(0.5);
    uint64_t covered = 0, checked = 0;
    for (uint32_t y = 0; y < res; ++y)
        for (uint32_t x = 0; x < res; ++x) {
            double nx = (x + 0.5) / res * 2 - 1, ny = (y + 0.5) / res * 2 - 1;
            double mm = std::max(std::abs(nx), std::abs(ny)) * t;                     // |lateral| / depth
            if (std::abs(mm * 5 - 1) < 1e-3 || std::abs(mm * 7 - 1) < 1e-3) continue; // on a silhouette
            ++checked;
            size_t i = size_t(y) * res + x;
            if (mm * 5 > 1) {
                EXPECT_EQ(m.enter[i], kDepthEmpty) << x << "," << y;
                EXPECT_EQ(m.exit[i], kDepthEmpty) << x << "," << y;
                continue;
            }
            ++covered;
            double exitDepth = std::min(7.0, 1.0 / mm);
            EXPECT_NEAR(dequantizeDepth(m.enter[i], f.farPlane), 5.0, 1e-4) << x << "," << y;
            // Side faces are seen at grazing angles: a vertex snapped by 1/512 texel moves their depth by
            // up to d^2 tan(fov/2) * (2 / res) / 512.
            double tol = 1e-4 + exitDepth * exitDepth * t * (2.0 / res) / 256.0;
            EXPECT_NEAR(dequantizeDepth(m.exit[i], f.farPlane), exitDepth, tol) << x << "," << y;
        }
    EXPECT_GT(covered, 2000u);
    EXPECT_GT(checked, res * res - 400);
}

TEST(StaticRaster, OpenQuadExitEqualsEnterAndEmptyElsewhere) {
    CasterTriangles c;
    glm::vec3 a(-1, -1, -4), b(1, -1, -4), d(1, 1, -4), e(-1, 1, -4);
    c.add(a, b, d, false), c.add(a, d, e, false);
    addBox(c, {-0.5f, -3, -8}, {0.5f, 3, -6}, true); // partly behind the quad
    const uint32_t res = 256;
    LightFrustum f = originFrustum();
    DualDepthMap m = rasterizeDual(c, f, res);
    const double t = std::tan(0.5);
    uint64_t quad = 0;
    for (uint32_t y = 0; y < res; ++y)
        for (uint32_t x = 0; x < res; ++x) {
            double nx = (x + 0.5) / res * 2 - 1, ny = (y + 0.5) / res * 2 - 1;
            size_t i = size_t(y) * res + x;
            double qx = std::abs(nx) * t * 4, qy = std::abs(ny) * t * 4;
            if (qx < 0.999 && qy < 0.999) {
                ++quad;
                EXPECT_NEAR(dequantizeDepth(m.enter[i], f.farPlane), 4.0, 1e-4);
                EXPECT_EQ(m.exit[i], m.enter[i]);
            } else if (qx > 1.001 || qy > 1.001) {
                // Outside the quad: the box (front at 6) or nothing.
                bool box = std::abs(nx) * t * 6 < 0.499 && std::abs(ny) * t * 6 < 2.999;
                bool miss = std::abs(nx) * t * 6 > 0.501 || std::abs(ny) * t * 6 > 3.001;
                if (box) {
                    EXPECT_NEAR(dequantizeDepth(m.enter[i], f.farPlane), 6.0, 1e-4) << x << "," << y;
                    EXPECT_GT(m.exit[i], m.enter[i]) << x << "," << y;
                }
                if (miss) {
                    EXPECT_EQ(m.enter[i], kDepthEmpty) << x << "," << y;
                }
            }
        }
    EXPECT_GT(quad, 1000u);
}

// Directional maps take each triangle's depth from its fixed-point plane (raster_dual.h step 4): every
// covered texel lies within 2^-7 (x + y) + 2 units of the triangle's true depth at its centre, and on one
// integer plane that DAG-MH's decoder evaluates, so a tilted open triangle over empty ground costs no
// factor bits (the float rule before it left 1-9 bit factors on such planes).
TEST(StaticRaster, DirectionalDepthIsTheTrianglesFixedPointPlane) {
    CasterTriangles c;
    const glm::vec3 a(-9.3f, 1.7f, -8.9f), b(9.1f, 4.9f, -7.7f), d(-2.2f, -3.1f, 9.4f);
    c.add(a, b, d, false);
    LightFrustum f;
    f.view = glm::lookAt(glm::vec3(3.0f, 40.0f, 11.0f), glm::vec3(0.0f), glm::vec3(0, 0, 1));
    f.orthoHalf = 12.0f, f.nearPlane = 1.0f, f.farPlane = 80.0f;
    const uint32_t res = 512;
    DualDepthMap m = rasterizeDual(c, f, res);
    const glm::dmat4 v(f.view);
    glm::dvec3 q[3];
    for (int k = 0; k < 3; ++k)
        q[k] = glm::dvec3(v * glm::dvec4(glm::dvec3(k == 0 ? a : k == 1 ? b : d), 1.0));
    const glm::dvec3 n = glm::cross(q[1] - q[0], q[2] - q[0]);
    uint64_t covered = 0;
    double worst = 0.0;
    for (uint32_t y = 0; y < res; ++y)
        for (uint32_t x = 0; x < res; ++x) {
            const size_t i = size_t(y) * res + x;
            if (m.enter[i] == kDepthEmpty) continue;
            ++covered;
            EXPECT_EQ(m.exit[i], m.enter[i]);
            const double lx = ((x + 0.5) / res * 2 - 1) * f.orthoHalf,
                         ly = ((y + 0.5) / res * 2 - 1) * f.orthoHalf;
            const double z = q[0].z - (n.x * (lx - q[0].x) + n.y * (ly - q[0].y)) / n.z; // on the plane
            const double exact = -z / double(f.farPlane) * 4294967294.0;
            const double err = std::abs(double(m.enter[i]) - exact);
            worst = std::max(worst, err);
            ASSERT_LE(err, (x + y) / 128.0 + 2.0) << x << "," << y;
        }
    EXPECT_GT(covered, res * res / 8);
    printf("  [static] %llu texels on the plane, worst %.2f units from the true depth\n",
           (unsigned long long)covered, worst);
    auto tree = buildMhTree(m);
    ASSERT_TRUE(tree.ok());
    DagMhStats st;
    auto enc = encodeDAGMH(*tree, &st);
    ASSERT_TRUE(enc.ok()) << enc.error();
    EXPECT_EQ(st.factorBits, 0u);
    EXPECT_EQ(st.rawChunks, 0u);
    EXPECT_EQ(dagmhCheckValues(*tree, enc->data()), 0u);
    encodeChecked(m, codecs()[2]);
}

// Every texel of a directional map names the plane its enter depth lies on (a quad's two triangles one
// plane), and the planar tree (mh.h) holds the open tilted sheets in a few nodes, which DAG-MH decodes
// exactly at every texel; a perspective map names none.
TEST(StaticRaster, EnterPlanesNameTheirTexelsPlanes) {
    CasterTriangles c;
    c.add({-9.3f, 1.7f, -8.9f}, {9.1f, 4.9f, -7.7f}, {-2.2f, -3.1f, 9.4f}, false);
    const glm::vec3 q0(-8.0f, -2.0f, -9.0f), q1(8.0f, -1.0f, -9.0f), q2(8.0f, -3.0f, 9.0f),
        q3(-8.0f, -4.0f, 9.0f);
    c.add(q0, q1, q2, false), c.add(q0, q2, q3, false); // one tilted quad below the triangle
    LightFrustum f;
    f.view = glm::lookAt(glm::vec3(3.0f, 40.0f, 11.0f), glm::vec3(0.0f), glm::vec3(0, 0, 1));
    f.orthoHalf = 12.0f, f.nearPlane = 1.0f, f.farPlane = 80.0f;
    const uint32_t res = 512;
    const DualRasterizer r(c, f, res);
    EXPECT_EQ(r.planes().size(), 2u);
    const DualDepthMap m = r.render();
    ASSERT_EQ(m.enterPlane.size(), m.enter.size());
    ASSERT_EQ(m.planes, r.planes());
    uint64_t covered = 0, named = 0, off = 0;
    for (uint32_t y = 0; y < res; ++y)
        for (uint32_t x = 0; x < res; ++x) {
            const size_t i = size_t(y) * res + x;
            const uint32_t id = m.enterPlane[i];
            covered += m.enter[i] != kDepthEmpty;
            if (id == 0) continue;
            ++named;
            ASSERT_LE(id, m.planes.size());
            off += m.planes[id - 1].at(x, y) != int64_t(m.enter[i]);
        }
    EXPECT_GT(covered, res * res / 4);
    EXPECT_EQ(named, covered); // nothing clamped here: every covered texel names its plane
    EXPECT_EQ(off, 0u);
    auto plain = buildMhTree(m), planar = buildMhTree(m, true);
    ASSERT_TRUE(plain.ok() && planar.ok());
    EXPECT_TRUE(planar->planar());
    EXPECT_LT(planar->valuedCount() * 20, plain->valuedCount());
    DagMhStats st;
    auto enc = encodeDAGMH(*planar, &st);
    ASSERT_TRUE(enc.ok()) << enc.error();
    ASSERT_TRUE(validateDAGMH(enc->data(), enc->size()).ok());
    EXPECT_GT(st.planarValues, 0u);
    EXPECT_EQ(dagmhCheckValues(*planar, enc->data()), 0u);
    uint64_t wrong = 0;
    for (uint32_t y = 0; y < res; ++y)
        for (uint32_t x = 0; x < res; ++x) // open sheets: exit = enter, the only lossless value
            wrong += dagmhLookup(enc->data(), x, y) != m.enter[size_t(y) * res + x];
    EXPECT_EQ(wrong, 0u);
    printf("  [static] planar tree %zu values (plain %zu), DAG-MH %zu B, %llu plane values\n",
           planar->valuedCount(), plain->valuedCount(), enc->size() * 4, (unsigned long long)st.planarValues);
    // A perspective map has no planes.
    LightShape spot;
    spot.type = LightKind::Spot, spot.position = {0.0f, 30.0f, 0.0f}, spot.direction = {0.0f, -1.0f, 0.0f};
    spot.outerAngle = 0.6f, spot.range = 60.0f;
    const DualDepthMap sm = rasterizeDual(c, spotLightFrustum(spot), 128);
    EXPECT_TRUE(sm.enterPlane.empty());
}

TEST(StaticRaster, TilesMatchWholeMap) {
    CasterTriangles c;
    std::mt19937 rng(5);
    for (int i = 0; i < 30; ++i) {
        glm::vec3 p(float(rng() % 100) / 10 - 5, float(rng() % 100) / 10 - 5, -3.0f - float(rng() % 50) / 10);
        addBox(c, p, p + glm::vec3(0.5f + float(rng() % 10) / 10), i % 2 == 0);
    }
    LightFrustum f = originFrustum();
    DualRasterizer r(c, f, 300);
    DualDepthMap whole = r.render(uint64_t(300) * 300), tiled = r.render(300 * 7);
    EXPECT_TRUE(whole.enter == tiled.enter);
    EXPECT_TRUE(whole.exit == tiled.exit);
    // And a single row band rendered on its own equals the same rows of the whole map.
    std::vector<uint32_t> en(300 * 10), ex(300 * 10);
    r.renderRows(100, 110, en.data(), ex.data());
    EXPECT_TRUE(std::equal(en.begin(), en.end(), whole.enter.begin() + 300 * 100));
    EXPECT_TRUE(std::equal(ex.begin(), ex.end(), whole.exit.begin() + 300 * 100));
}

// renderRect (4 hit slots a texel, covered spans solved per row) equals renderRectReference (one sorted
// hit list, every column tested) at every texel: a stack of 12 boxes (texels with up to 24 hits, past
// the slots into the overflow list), the open and the closed night city's moon and a street spot light,
// 512^2, in 64^2 tiles and in odd 70 x 100 blocks.
TEST(StaticRaster, SlotsEqualTheHitListEveryTexel) {
    std::vector<std::pair<std::string, std::pair<CasterTriangles, LightFrustum>>> cases;
    {
        CasterTriangles c;
        for (int i = 0; i < 12; ++i) // nested, overlapping, open and closed
            addBox(c, glm::vec3(-1.0f - 0.1f * i, -1.0f, -2.0f - 0.3f * i),
                   glm::vec3(1.0f, 1.0f + 0.05f * i, -1.9f - 0.3f * i + 0.25f), i % 3 != 0);
        cases.push_back({"stacked boxes", {c, originFrustum()}});
    }
    for (const char* name : {"night-city", "night-city-closed"}) {
        auto scene = loadScene(name, 256, 1);
        ASSERT_TRUE(scene.ok()) << scene.error();
        const CasterTriangles casters = castersFromScene(*scene);
        bool moon = false, spot = false;
        for (const Light& l : scene->lights) {
            if (l.type == LightKind::Directional && !moon)
                moon = true,
                cases.push_back(
                    {std::string(name) + " moon",
                     {casters, directionalLightFrustum(l.direction, scene->boundsMin, scene->boundsMax)}});
            if (l.type == LightKind::Spot && !spot)
                spot = true, cases.push_back({std::string(name) + " spot", {casters, spotLightFrustum(l)}});
        }
        ASSERT_TRUE(moon && spot) << name;
    }
    const uint32_t res = 512;
    for (const auto& [name, c] : cases) {
        const DualRasterizer raster(c.first, c.second, res);
        uint64_t covered = 0, differ = 0;
        for (uint32_t bw : {64u, 70u}) {
            const uint32_t bh = bw == 64 ? 64 : 100;
            for (uint32_t y0 = 0; y0 < res; y0 += bh)
                for (uint32_t x0 = 0; x0 < res; x0 += bw) {
                    const uint32_t w = std::min(bw, res - x0), h = std::min(bh, res - y0);
                    std::vector<uint32_t> e(size_t(w) * h), x(e.size()), re(e.size()), rx(e.size());
                    raster.renderRect(x0, y0, w, h, e.data(), x.data());
                    raster.renderRectReference(x0, y0, w, h, re.data(), rx.data());
                    for (size_t t = 0; t < e.size(); ++t) {
                        differ += e[t] != re[t] || x[t] != rx[t];
                        covered += bw == 64 && re[t] != kDepthEmpty;
                    }
                }
        }
        EXPECT_EQ(differ, 0u) << name;
        EXPECT_GT(covered, uint64_t(res) * res / 20) << name << ": the map should see the casters";
    }
}

// A host thread that bakes whole maps keeps no rasteriser scratch afterwards: render() frees the slots
// that renderRect keeps between tiles (64 MiB for its default band of 2^20 texels).
TEST(StaticRaster, RenderFreesTheThreadScratch) {
    CasterTriangles c;
    c.add({-1, -1, -3}, {1, -1, -3}, {0, 1, -3}, false);
    LightFrustum fr;
    fr.fov = 1.2f;
    fr.farPlane = 10.0f;
    DualRasterizer raster(c, fr, 256);
    std::vector<uint32_t> e(64 * 64), x(64 * 64);
    raster.renderRect(0, 0, 64, 64, e.data(), x.data());
    EXPECT_GE(DualRasterizer::threadScratchBytes(), size_t(64 * 64 * 68)); // kept for the next tile
    DualDepthMap m = raster.render();
    EXPECT_EQ(DualRasterizer::threadScratchBytes(), 0u);
    EXPECT_EQ(m.enter.size(), size_t(256) * 256);
}

TEST(StaticRaster, FarPlaneAndLightInsideMesh) {
    const uint32_t res = 64;
    LightFrustum f = originFrustum();
    {
        // A box straddling far: its back faces are clipped, the ray stays inside until far.
        CasterTriangles c;
        addBox(c, {-1, -1, -12}, {1, 1, -9}, true);
        DualDepthMap m = rasterizeDual(c, f, res);
        size_t i = size_t(res / 2) * res + res / 2;
        EXPECT_NEAR(dequantizeDepth(m.enter[i], f.farPlane), 9.0, 1e-4);
        EXPECT_EQ(m.exit[i], 0xFFFFFFFEu);
    }
    {
        // The light inside a closed box: the first hit is a back face, so exit = enter.
        CasterTriangles c;
        addBox(c, {-3, -3, -3}, {3, 3, 3}, true);
        DualDepthMap m = rasterizeDual(c, f, res);
        for (size_t i = 0; i < m.enter.size(); ++i) {
            ASSERT_NE(m.enter[i], kDepthEmpty);
            ASSERT_EQ(m.exit[i], m.enter[i]);
        }
    }
}

// Quad a-b-c-d split along the diagonal a-c, wound counter-clockwise around `outward`.
void addQuad(CasterTriangles& t, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 outward) {
    if (glm::dot(glm::cross(b - a, c - a), outward) < 0.0f) std::swap(b, d);
    t.add(a, b, c, true);
    t.add(a, c, d, true);
}

TEST(StaticRaster, SharedEdgesCountedOnce) {
    // A closed box whose front face is split along x = y, a line through texel centres, and whose back
    // face is split along the other diagonal, which misses every centre. With a ">= 0" tie rule the
    // centres on the front diagonal are entered twice but left once, and would never be left.
    CasterTriangles c;
    const float lo = -1.0f, hi = 1.3f, zf = -4.0f, zb = -6.0f;
    glm::vec3 f00(lo, lo, zf), f10(hi, lo, zf), f11(hi, hi, zf), f01(lo, hi, zf);
    glm::vec3 b00(lo, lo, zb), b10(hi, lo, zb), b11(hi, hi, zb), b01(lo, hi, zb);
    addQuad(c, f00, f10, f11, f01, {0, 0, 1});  // front, diagonal f00-f11 (x = y)
    addQuad(c, b10, b11, b01, b00, {0, 0, -1}); // back, diagonal b10-b01 (x + y = 0.3)
    addQuad(c, f00, f10, b10, b00, {0, -1, 0});
    addQuad(c, f01, f11, b11, b01, {0, 1, 0});
    addQuad(c, f00, f01, b01, b00, {-1, 0, 0});
    addQuad(c, f10, f11, b11, b10, {1, 0, 0});
    LightFrustum f = originFrustum();
    DualDepthMap m = rasterizeDual(c, f, 128);
    uint32_t diagonal = 0;
    for (uint32_t y = 0; y < 128; ++y)
        for (uint32_t x = 0; x < 128; ++x) {
            size_t i = size_t(y) * 128 + x;
            if (m.enter[i] == kDepthEmpty) continue;
            diagonal += x == y;
            ASSERT_NE(m.exit[i], 0xFFFFFFFEu) << "texel " << x << "," << y << " never left the box";
            ASSERT_GT(m.exit[i], m.enter[i]) << "texel " << x << "," << y;
        }
    EXPECT_GT(diagonal, 10u);
}

} // namespace
} // namespace ml::stest
