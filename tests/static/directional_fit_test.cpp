// Directional static bakes fitted to their box: the frustum holds the box's light-space
// rectangle in rows [0, mapRows) with square texels and its slab along the light as the depth range;
// CPVS slices that range linearly; every method's bake of a closed and of an open model is lossless on
// every texel / voxel at small sizes; >= 95 % of the texels and of the depth slices lie in the box; SM
// stores only the rows in the light's volume; the bake file records the fit (version 3) and refuses a
// directional record of an older version.
#include "static_test_util.h"

#include "shadows/static/bake_file.h"
#include "shadows/static/raster_dual.h"

#include <glm/gtc/constants.hpp>

namespace ml::stest {
namespace {

// A closed box (12 counter-clockwise triangles seen from outside).
void addClosedBox(CasterTriangles& c, glm::vec3 lo, glm::vec3 hi) {
    glm::vec3 p[8];
    for (int i = 0; i < 8; ++i) p[i] = {i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z};
    const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : q) {
        c.add(p[f[0]], p[f[1]], p[f[2]], true);
        c.add(p[f[0]], p[f[2]], p[f[3]], true);
    }
}

// An open tube along z (no caps): the open model, like an engine's two cylinders.
void addOpenTube(CasterTriangles& c, glm::vec2 centre, float radius, float z0, float z1, float y0) {
    const int k = 24;
    for (int i = 0; i < k; ++i) {
        float a0 = glm::two_pi<float>() * i / k, a1 = glm::two_pi<float>() * (i + 1) / k;
        glm::vec3 p0(centre.x + radius * std::cos(a0), y0 + centre.y + radius * std::sin(a0), z0);
        glm::vec3 p1(centre.x + radius * std::cos(a1), y0 + centre.y + radius * std::sin(a1), z0);
        glm::vec3 q0 = p0, q1 = p1;
        q0.z = q1.z = z1;
        c.add(p0, p1, q1, false);
        c.add(p0, q1, q0, false);
    }
}

struct Model {
    const char* name;
    CasterTriangles casters;
    glm::vec3 lo, hi; // the --bounds box, tight around the casters
};

std::vector<Model> models() {
    std::vector<Model> m(2);
    m[0].name = "closed";
    addClosedBox(m[0].casters, {-3, 0, -1}, {3, 1.5f, 1}); // a long closed slab on a closed plinth
    addClosedBox(m[0].casters, {-1, 1.5f, -0.5f}, {0.5f, 4, 0.5f});
    m[0].lo = {-3, 0, -1}, m[0].hi = {3, 4, 1};
    m[1].name = "open";
    addOpenTube(m[1].casters, {-1.2f, 1.0f}, 1.0f, -4.0f, 4.0f, 0.0f);
    addOpenTube(m[1].casters, {1.2f, 1.0f}, 1.0f, -4.0f, 4.0f, 0.0f);
    m[1].lo = {-2.2f, 0, -4}, m[1].hi = {2.2f, 2, 4};
    return m;
}

const glm::vec3 kDirections[] = {
    {-0.25f, -1.0f, 0.0f}, {0.3f, -1.0f, 0.2f}, {0.0f, -1.0f, 0.0f}, {1.0f, -0.2f, 0.1f}};

TEST(DirectionalFit, FrustumHoldsTheBoxWithSquareTexels) {
    for (const Model& m : models())
        for (glm::vec3 dir : kDirections) {
            SCOPED_TRACE(std::string(m.name) + " dir " + std::to_string(dir.x) + "," + std::to_string(dir.z));
            const LightFrustum f = directionalLightFrustum(dir, m.lo, m.hi);
            ASSERT_TRUE(f.fitted());
            ASSERT_LE(f.orthoHalfY, f.orthoHalf); // the longer extent runs along x
            glm::vec3 vmin(1e30f), vmax(-1e30f);
            for (int i = 0; i < 8; ++i) {
                glm::vec3 c(i & 1 ? m.hi.x : m.lo.x, i & 2 ? m.hi.y : m.lo.y, i & 4 ? m.hi.z : m.lo.z);
                glm::vec3 v = glm::vec3(f.view * glm::vec4(c, 1.0f));
                vmin = glm::min(vmin, v), vmax = glm::max(vmax, v);
            }
            const float eps = 1e-4f * f.orthoHalf;
            // Corners inside the fitted rectangle and slab, with the margin (up to float rounding).
            EXPECT_GE(vmin.x, -f.orthoHalf + f.fitMargin - eps);
            EXPECT_LE(vmax.x, f.orthoHalf - f.fitMargin + eps);
            EXPECT_GE(vmin.y, -f.orthoHalf + f.fitMargin - eps);
            EXPECT_LE(vmax.y, -f.orthoHalf + 2 * f.orthoHalfY - f.fitMargin + eps);
            EXPECT_NEAR(-vmax.z, f.nearPlane + f.fitMargin, eps);
            EXPECT_NEAR(-vmin.z, f.farPlane - f.fitMargin, eps);
            EXPECT_GE(f.nearPlane, 1.0f - eps);
            // Texels are square: the map's x and y both step 2 orthoHalf / N; mapRows covers the height.
            for (uint32_t n : {64u, 256u, 1024u}) {
                uint32_t rows = f.mapRows(n);
                EXPECT_GE(double(rows) * 2.0 * f.orthoHalf / n, 2.0 * f.orthoHalfY - 1e-6);
                EXPECT_LT(double(rows - 1) * 2.0 * f.orthoHalf / n, 2.0 * f.orthoHalfY);
            }
        }
}

// Rows from mapRows on are empty; SM stores only the others.
TEST(DirectionalFit, RowsOutsideTheLightAreEmptyAndSmStoresOnlyTheRest) {
    const Model m = models()[0];
    const LightFrustum f = directionalLightFrustum(kDirections[0], m.lo, m.hi);
    const uint32_t n = 128, rows = f.mapRows(n);
    ASSERT_LT(rows, n);
    DualDepthMap map = rasterizeDual(m.casters, f, n);
    EXPECT_EQ(map.rows, rows);
    EXPECT_TRUE(map.orthographic);
    uint64_t covered = 0;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const bool hit = map.enter[size_t(y) * n + x] != kDepthEmpty;
            if (y >= rows) {
                EXPECT_FALSE(hit) << x << "," << y;
            }
            covered += hit;
        }
    EXPECT_GT(covered, uint64_t(n) * rows / 4);
    auto sm = encodeStatic(StaticMethod::SM, map, {f.nearPlane, f.farPlane, {}});
    ASSERT_TRUE(sm.ok());
    EXPECT_EQ(sm->size(), smfmt::kHeaderWords + size_t(n) * rows);
    EXPECT_EQ((*sm)[smfmt::kVersion], 2u);
    ASSERT_TRUE(validateSM(sm->data(), sm->size()).ok());
    for (uint32_t y = rows; y < n; ++y) EXPECT_EQ(smLookup(sm->data(), 0, 5, y), kDepthEmpty);
    // A spot map keeps version 1, the rows word 0 and every row.
    DualDepthMap square = map;
    square.rows = 0;
    auto v1 = encodeStatic(StaticMethod::SM, square, {});
    ASSERT_TRUE(v1.ok());
    EXPECT_EQ((*v1)[smfmt::kVersion], 1u);
    EXPECT_EQ((*v1)[smfmt::kRows], 0u);
    EXPECT_EQ(v1->size(), smfmt::kHeaderWords + size_t(n) * n);
    // A wrong rows word is refused.
    std::vector<uint32_t> bad = sm.value();
    bad[smfmt::kRows] = n;
    bad[smfmt::kChecksum] = stat::checksumWords(bad.data(), bad.size(), smfmt::kChecksum);
    EXPECT_FALSE(validateSM(bad.data(), bad.size()).ok());
}

// A caster above the box (outside its slab, inside its bounding sphere) still shadows it: the rasteriser
// clips at kDirectionalClipNear, and the depth lies below near (CPVS: every voxel of the column shadowed).
TEST(DirectionalFit, CastersAboveTheBoxStillShadowIt) {
    CasterTriangles c;
    addClosedBox(c, {-0.5f, 3.0f, -0.5f}, {0.5f, 3.5f, 0.5f}); // above the box's top (y = 2)
    addClosedBox(c, {-3, 0, -1}, {3, 0.5f, 1});
    const LightFrustum f = directionalLightFrustum({0, -1, 0}, {-3, 0, -1}, {3, 2, 1});
    const uint32_t n = 64;
    const DualDepthMap map = rasterizeDual(c, f, n);
    const uint32_t centre = map.enter[size_t(f.mapRows(n) / 2) * n + n / 2];
    ASSERT_NE(centre, kDepthEmpty);
    EXPECT_LT(centre, quantizeDepth(f.nearPlane, f.farPlane));
    auto words = encodeStatic(StaticMethod::CPVS, map, {f.nearPlane, f.farPlane, {}});
    ASSERT_TRUE(words.ok());
    for (uint32_t s = 0; s < n; ++s)
        EXPECT_TRUE(
            cpvsShadowedVoxel(words->data(), 0, int32_t(n / 2), int32_t(f.mapRows(n) / 2), int32_t(s)));
    EXPECT_EQ(verifyCpvs(words->data(), map).mismatches, 0u);
}

TEST(DirectionalFit, CpvsSlicesTheSlabLinearly) {
    const float nearZ = 3.0f, farZ = 11.0f;
    auto space = makeCpvsSpace(64, nearZ, farZ, CpvsSlicing::Linear);
    ASSERT_TRUE(space.ok()) << space.error();
    for (uint32_t s = 0; s < 64; ++s) {
        const double z = nearZ + (farZ - nearZ) * s / 64.0;
        EXPECT_EQ(space->thresholds[s], uint32_t(z / farZ * 4294967294.0)) << s;
        // every slice is 1/64 of the range, to a quantum
        const double width = double(space->thresholds[s + 1 < 64 ? s + 1 : s]) - space->thresholds[s];
        if (s + 1 < 64) {
            EXPECT_NEAR(width, (farZ - nearZ) / 64.0 / farZ * 4294967294.0, 2.0);
        }
        // a depth inside slice s lands in it
        const uint32_t mid = quantizeDepth(float(z + (farZ - nearZ) / 128.0), farZ);
        EXPECT_EQ(cpvsSliceOf(*space, mid), s);
    }
}

// Every method on both models, three directions, at 64 and 128: lossless on every texel (depth methods:
// the decoded value in [enter, exit]) or voxel (CPVS against its reference), >= 95 % of texels and slices
// in the box.
TEST(DirectionalFit, EveryMethodLosslessAndInTheBox) {
    for (const Model& m : models())
        for (int di = 0; di < 3; ++di)
            for (uint32_t n : {64u, 128u}) {
                const LightFrustum f = directionalLightFrustum(kDirections[di], m.lo, m.hi);
                const DualDepthMap map = rasterizeDual(m.casters, f, n);
                for (StaticMethod method : {StaticMethod::SM, StaticMethod::MH, StaticMethod::MMH,
                                            StaticMethod::DAGMH, StaticMethod::CPVS}) {
                    SCOPED_TRACE(std::string(m.name) + " " + staticMethodName(method) + " dir " +
                                 std::to_string(di) + " n " + std::to_string(n));
                    auto words = encodeStatic(method, map, {f.nearPlane, f.farPlane, {}});
                    ASSERT_TRUE(words.ok()) << words.error();
                    ASSERT_TRUE(validateStatic(method, words->data(), words->size()).ok());
                    uint64_t checked = 0, bad = 0;
                    if (method == StaticMethod::CPVS) {
                        EXPECT_EQ((*words)[kCpvsHSlicing], uint32_t(CpvsSlicing::Linear));
                        CpvsVerifyReport r = verifyCpvs(words->data(), map);
                        checked = r.checked, bad = r.mismatches;
                        EXPECT_EQ(r.checked + r.undefined, uint64_t(n) * n * n); // every voxel
                    } else {
                        for (uint32_t y = 0; y < n; ++y)
                            for (uint32_t x = 0; x < n; ++x) {
                                const size_t i = size_t(y) * n + x;
                                const uint32_t v = lookupStaticDepth(method, words->data(), 0, x, y);
                                bad += v < map.enter[i] || v > std::max(map.enter[i], map.exit[i]);
                                ++checked;
                            }
                    }
                    EXPECT_EQ(bad, 0u) << checked << " checked";
                    BakeRecord rec{0, 0, method, n, f, words.value()};
                    auto fit = directionalFit(rec);
                    ASSERT_TRUE(fit.ok()) << fit.error();
                    EXPECT_GE(fit->texelsInBox, 0.95);
                    EXPECT_GE(fit->depthSlicesInBox, 0.95);
                    // Stored shadow boundaries: inside closed casters the encoder may put them anywhere
                    // between entry and exit, so only the range is checked here.
                    EXPECT_GT(fit->casterSlices, 0.0);
                    EXPECT_LE(fit->casterSlices, 1.0);
                }
            }
}

// The file records the fit (version 3) and reads it back; a directional record in an older version is
// refused with a line that says to re-bake; spot-only files keep their version.
TEST(DirectionalFit, BakeFileVersion3AndOldDirectionalRecordsRefused) {
    const Model m = models()[1];
    const LightFrustum f = directionalLightFrustum(kDirections[1], m.lo, m.hi);
    const DualDepthMap map = rasterizeDual(m.casters, f, 64);
    BakeFile file;
    file.scene = {"directional-fit-test", 1, 1};
    file.method = StaticMethod::CPVS;
    file.resolution = 64;
    auto words = encodeStatic(StaticMethod::CPVS, map, {f.nearPlane, f.farPlane, {}});
    ASSERT_TRUE(words.ok());
    file.records.push_back({0, 0, StaticMethod::CPVS, 64, f, words.value()});
    EXPECT_EQ(bakeFileVersion(file), bakefmt::kVersionFitted);
    auto w = serializeBakeFile(file);
    ASSERT_TRUE(w.ok()) << w.error();
    EXPECT_EQ((*w)[bakefmt::kHVersion], 3u);
    auto back = parseBakeFile("mem", w->data(), w->size());
    ASSERT_TRUE(back.ok()) << back.error();
    const LightFrustum& g = back->records[0].frustum;
    EXPECT_EQ(g.orthoHalf, f.orthoHalf);
    EXPECT_EQ(g.orthoHalfY, f.orthoHalfY);
    EXPECT_EQ(g.fitMargin, f.fitMargin);
    EXPECT_EQ(g.nearPlane, f.nearPlane);

    // The same record as a version 1 file carries it (not fitted to a box: no words 30, 31).
    std::vector<uint32_t> old = w.value();
    const uint32_t hw = old[bakefmt::kHHeaderWords];
    old[bakefmt::kHVersion] = bakefmt::kVersionFixed;
    old[bakefmt::kHChecksum] = stat::checksumWords(old.data(), hw, bakefmt::kHChecksum);
    uint32_t* rec = old.data() + hw;
    rec[bakefmt::kROrthoHalfY] = rec[bakefmt::kRFitMargin] = 0;
    rec[bakefmt::kRChecksum] = stat::checksumWords(rec, bakefmt::kRecordWords, bakefmt::kRChecksum);
    auto refused = parseBakeFile("old.mlbk", old.data(), old.size());
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().find("re-bake"), std::string::npos) << refused.error();
    EXPECT_NE(refused.error().find("version 1"), std::string::npos) << refused.error();

    // A linear CPVS under a spot record, or a log one under a directional record, is refused.
    BakeFile spot = file;
    spot.records[0].frustum = spotLightFrustum(LightShape{});
    spot.records[0].frustum.farPlane = f.farPlane, spot.records[0].frustum.nearPlane = f.nearPlane;
    EXPECT_EQ(bakeFileVersion(spot), bakefmt::kVersionFixed);
    auto sw = serializeBakeFile(spot);
    ASSERT_TRUE(sw.ok());
    auto r = parseBakeFile("mem", sw->data(), sw->size());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("eq. 1"), std::string::npos) << r.error();
}

} // namespace
} // namespace ml::stest
