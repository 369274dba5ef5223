// The static lookups' bias (shadows/static/static_visibility.h, twin of the shader): no self-shadowing
// ("acne") on a ground lit at grazing angles, and shadows where a box really blocks the light, for every
// method and resolution. Truth is an exact ray-box test.
#include "scenes/scene.h"
#include "shadows/static/raster_dual.h"
#include "shadows/static/static_method.h"
#include "shadows/static/static_visibility.h"

#include <gtest/gtest.h>

#include "tests/common/ray_box.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace ml {

namespace {
// Ray from p towards the light: does it pass through the box [lo, hi]?

CasterTriangles groundAndBox(glm::vec3 lo, glm::vec3 hi) {
    CasterTriangles c;
    c.add({-30, 0, -30}, {-30, 0, 30}, {30, 0, 30}, false);
    c.add({-30, 0, -30}, {30, 0, 30}, {30, 0, -30}, false);
    glm::vec3 p[8];
    for (int i = 0; i < 8; ++i)
        p[i] = glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (auto& f : faces) {
        c.add(p[f[0]], p[f[1]], p[f[2]], true);
        c.add(p[f[0]], p[f[2]], p[f[3]], true);
    }
    return c;
}
} // namespace

CasterTriangles groundAndBoxForPcf(glm::vec3 lo, glm::vec3 hi) {
    return groundAndBox(lo, hi);
}

class StaticBias : public ::testing::TestWithParam<float> {};

// Light elevation above the ground: 30, 10 and 5 degrees (60..85 degrees from the normal).
TEST_P(StaticBias, NoAcneAtGrazingAnglesAndShadowsWhereBlocked) {
    const float elevation = GetParam() * 3.14159265f / 180.0f;
    const glm::vec3 lo(-0.5f, 0.0f, 1.5f), hi(0.5f, 1.0f, 2.5f);
    CasterTriangles casters = groundAndBox(lo, hi);
    Light light;
    light.position = glm::vec3(0.0f, 12.0f * std::sin(elevation), -12.0f * std::cos(elevation));
    light.direction = glm::normalize(glm::vec3(0.0f, 0.0f, 4.0f) - light.position);
    light.range = 30.0f;
    light.outerAngle = 0.5f;
    LightFrustum f = spotLightFrustum(light);
    for (uint32_t res : {512u, 2048u}) {
        DualDepthMap map = rasterizeDual(casters, f, res);
        for (StaticMethod method : {StaticMethod::SM, StaticMethod::MH, StaticMethod::MMH,
                                    StaticMethod::DAGMH, StaticMethod::CPVS}) {
            auto words = encodeStatic(method, map, {f.nearPlane, f.farPlane, {}});
            ASSERT_TRUE(words.ok()) << words.error();
            auto rec = makeShadowRecord(method, f, 0, res, 0);
            uint32_t acne = 0, lit = 0, shadowed = 0, missed = 0;
            for (float x = -3.0f; x <= 3.0f; x += 0.05f)
                for (float z = -2.0f; z <= 12.0f; z += 0.05f) {
                    glm::vec3 p(x, 0.0f, z);
                    glm::vec3 toLight = light.position - p;
                    if (glm::dot(glm::normalize(-toLight), light.direction) < std::cos(light.outerAngle) ||
                        glm::length(toLight) >= light.range)
                        continue;
                    // Skip receivers within 0.25 m of the box's footprint edge or its shadow edge: the
                    // bias may move the boundary by a texel or two there.
                    bool b = test::blockedByBox(p, light.position, lo, hi);
                    bool near = false;
                    for (glm::vec3 o : {glm::vec3(0.25f, 0, 0), glm::vec3(-0.25f, 0, 0),
                                        glm::vec3(0, 0, 0.25f), glm::vec3(0, 0, -0.25f)})
                        near |= test::blockedByBox(p + o, light.position, lo, hi) != b;
                    if (near ||
                        (x >= lo.x - 0.25f && x <= hi.x + 0.25f && z >= lo.z - 0.25f && z <= hi.z + 0.25f))
                        continue;
                    float v = staticVisibility(rec, words->data(), p, glm::vec3(0, 1, 0));
                    if (b) {
                        ++shadowed;
                        missed += v > 0.5f;
                    } else {
                        ++lit;
                        acne += v < 0.5f;
                    }
                }
            EXPECT_GT(lit, 1000u);
            EXPECT_GT(shadowed, 20u);
            EXPECT_EQ(acne, 0u) << staticMethodName(method) << " at " << res << ", elevation " << GetParam();
            EXPECT_EQ(missed, 0u) << staticMethodName(method) << " at " << res << ", elevation "
                                  << GetParam();
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Elevations, StaticBias, ::testing::Values(30.0f, 10.0f, 5.0f));

} // namespace ml

namespace ml {
// A spot light looking down at a 1 m box on the ground, its DAG-MH map at `res` (the PCF and bounds tests).
Result<std::vector<uint32_t>> boxSceneDagmh(uint32_t res, LightFrustum& f) {
    const glm::vec3 lo(-0.5f, 0.0f, 1.5f), hi(0.5f, 1.0f, 2.5f);
    CasterTriangles casters = groundAndBoxForPcf(lo, hi);
    Light light;
    light.position = glm::vec3(0.3f, 6.0f, -1.0f);
    light.direction = glm::normalize(glm::vec3(0.0f, 0.0f, 2.0f) - light.position);
    light.range = 20.0f;
    light.outerAngle = 0.7f;
    f = spotLightFrustum(light);
    return encodeStatic(StaticMethod::DAGMH, rasterizeDual(casters, f, res));
}

// Hierarchical PCF: every tap decoded from a shared prefix equals its own full lookup, for every
// block position and radius 1..4 on a real map.
TEST(StaticHierarchicalPcf, SharedPrefixTapsEqualFullLookups) {
    const uint32_t res = 256;
    LightFrustum f;
    auto words = boxSceneDagmh(res, f);
    ASSERT_TRUE(words.ok()) << words.error();
    const uint32_t* d = words->data();
    const DagmhHeader h = dagmhHeader(d, 0);
    uint64_t shared = 0, taps = 0, memoHits = 0;
    for (int r = 1; r <= 4; ++r)
        for (int cy = 0; cy < int(res); ++cy)
            for (int cx = 0; cx < int(res); ++cx) {
                int x0 = std::max(cx - r, 0), y0 = std::max(cy - r, 0);
                int x1 = std::min(cx + r, int(res) - 1), y1 = std::min(cy + r, int(res) - 1);
                DagmhState prefix = dagmhPcfPrefix(d, h, x0, y0, x1, y1);
                if (prefix.kind == kDagNoPrefix) continue;
                ++shared;
                // The PCF loop's memo (dagmhMemoValue, shaders/static/static_pcf.h): a tap whose value index
                // equals the previous tap's reuses that value, so equal indices must mean equal values.
                uint32_t memoIndex = 0xFFFFFFFFu, memoValue = 0;
                for (int y = y0; y <= y1; ++y)
                    for (int x = x0; x <= x1; ++x, ++taps) {
                        const uint32_t full = dagmhLookup(d, 0, x, y);
                        ASSERT_EQ(dagmhFinish(d, h, x, y, prefix), full)
                            << "block at " << cx << "," << cy << " radius " << r << " tap " << x << "," << y;
                        DagmhState st = dagmhLocate(d, h, x, y, prefix);
                        if (st.vlast == memoIndex) {
                            ++memoHits;
                            ASSERT_EQ(memoValue, full) << "tap " << x << "," << y << " radius " << r;
                        }
                        memoIndex = st.vlast, memoValue = full;
                    }
            }
    EXPECT_GT(shared, 100000u);
    EXPECT_GT(memoHits, taps / 5); // 28 % here (row-major taps: a new row usually starts a new node)
    std::printf("  %llu blocks shared a prefix, %llu taps identical, %llu reused the previous tap's value\n",
                (unsigned long long)shared, (unsigned long long)taps, (unsigned long long)memoHits);
}
} // namespace ml

namespace ml {
// bench static's count of lookups the DAG-MH value bounds answer (dagmhBoundsDecision) says what the lookup
// answers: "lit" receivers are lit and "shadowed" ones shadowed in every in-map tap, over a grid of ground
// receivers around a box, one tap and 3x3; both kinds of answer and undecided lookups occur.
TEST(StaticVisibility, DagmhBoundsDecisionAgreesWithTheLookup) {
    const uint32_t res = 256;
    LightFrustum f;
    auto words = boxSceneDagmh(res, f);
    ASSERT_TRUE(words.ok()) << words.error();
    for (uint32_t radius : {0u, 1u}) {
        const auto rec = makeShadowRecord(StaticMethod::DAGMH, f, 0, res, radius);
        const float taps = float((2 * radius + 1) * (2 * radius + 1));
        uint64_t count[4] = {};
        for (float x = -4.0f; x <= 4.0f; x += 0.02f)
            for (float z = -1.0f; z <= 8.0f; z += 0.02f) {
                const glm::vec3 p(x, 0.0f, z), n(0, 1, 0);
                const uint32_t k = dagmhBoundsDecision(rec, words->data(), p, n);
                ASSERT_LT(k, 4u);
                ++count[k];
                const float v = staticVisibility(rec, words->data(), p, n);
                if (k == 1) {
                    ASSERT_EQ(v, 1.0f) << "at " << x << "," << z << " radius " << radius;
                }
                // Shadowed in every in-map tap: only taps off the map (counted lit) remain.
                if (k == 2) {
                    ASSERT_LE(v * taps, taps - 1.0f) << "at " << x << "," << z << " radius " << radius;
                }
                if (k == 2 && radius == 0) {
                    ASSERT_EQ(v, 0.0f) << "at " << x << "," << z;
                }
            }
        EXPECT_GT(count[1], 1000u) << "radius " << radius;
        EXPECT_GT(count[2], 100u) << "radius " << radius;
        EXPECT_GT(count[0], 10u) << "radius " << radius; // the box's shadow edge stays undecided
        std::printf("  radius %u: %llu lit, %llu shadowed by the bounds, %llu undecided, %llu off the map\n",
                    radius, (unsigned long long)count[1], (unsigned long long)count[2],
                    (unsigned long long)count[0], (unsigned long long)count[3]);
    }
}
} // namespace ml

namespace ml {
// GpuShadowRecord keeps the light view as a quaternion and a translation (shaders/shared/shadow_record.h):
// for spot, point-face and directional frustums in many directions (the cube axes, where lookAt's
// rotation has zeros and quat_cast takes each branch, and random ones), the record maps world points and
// normals where the frustum's matrix does, to float rounding; the info word keeps method, radius and
// resolution; and rigidView tells lookAt views from scaled, sheared, mirrored, projective and NaN ones.
TEST(StaticVisibility, RecordViewMatchesTheFrustumMatrix) {
    std::vector<LightFrustum> frustums;
    std::vector<glm::vec3> dirs = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    uint32_t seed = 12345;
    auto next = [&] {
        seed = seed * 1664525u + 1013904223u;
        return float(seed >> 8) / float(1u << 24) * 2.0f - 1.0f;
    };
    for (int i = 0; i < 200; ++i) {
        glm::vec3 d(next(), next(), next());
        if (glm::length(d) > 0.1f) dirs.push_back(glm::normalize(d));
    }
    for (const glm::vec3& d : dirs) {
        LightShape spot;
        spot.position = glm::vec3(next(), next(), next()) * 50.0f;
        spot.direction = d;
        frustums.push_back(spotLightFrustum(spot));
        frustums.push_back(directionalLightFrustum(d, glm::vec3(-20, -1, -30), glm::vec3(40, 12, 25)));
    }
    LightShape point;
    point.type = LightKind::Point;
    point.position = {3, 4, -5};
    for (uint32_t face = 0; face < 6; ++face) frustums.push_back(pointLightFaceFrustum(point, face));
    float worst = 0.0f;
    for (const LightFrustum& f : frustums) {
        ASSERT_TRUE(rigidView(f.view));
        const auto rec = makeShadowRecord(StaticMethod::DAGMH, f, 7, 1024, 2);
        ASSERT_EQ(gpu::shadowRecordMethod(rec), uint32_t(StaticMethod::DAGMH));
        ASSERT_EQ(gpu::shadowRecordRadius(rec), 2u);
        ASSERT_EQ(gpu::shadowRecordResolution(rec), 1024u);
        ASSERT_EQ(rec.info.y, 7u);
        for (int k = 0; k < 20; ++k) {
            const glm::vec3 p = glm::vec3(next(), next(), next()) * 60.0f;
            const glm::vec3 want = glm::vec3(f.view * glm::vec4(p, 1.0f));
            const glm::vec3 got = gpu::shadowViewPoint(rec, p);
            // Relative to the point's distance from the light's origin (the translation's size).
            const float scale = glm::length(p) + glm::length(glm::vec3(f.view[3])) + 1.0f;
            worst = std::max(worst, glm::length(got - want) / scale);
            const glm::vec3 n = glm::normalize(glm::vec3(next(), next(), next()) + glm::vec3(0.01f));
            ASSERT_LT(glm::length(gpu::shadowViewVector(rec, n) - glm::mat3(f.view) * n), 1e-6f);
        }
    }
    EXPECT_LT(worst, 1e-6f);
    std::printf("  %zu frustums: largest difference %.2e of the distance scale\n", frustums.size(), worst);
    // The bake format's largest maps (kMhMaxResolution texels a side) with the largest method value.
    const auto big = makeShadowRecord(StaticMethod::CPVS, frustums[0], 0, kMhMaxResolution, 9);
    EXPECT_EQ(gpu::shadowRecordResolution(big), kMhMaxResolution);
    EXPECT_EQ(gpu::shadowRecordMethod(big), uint32_t(StaticMethod::CPVS));
    EXPECT_EQ(gpu::shadowRecordRadius(big), uint32_t(ML_MAX_PCF_RADIUS));
    EXPECT_EQ(gpu::shadowRecordRadius(makeShadowRecord(StaticMethod::SM, frustums[0], 0, 64, 9)),
              uint32_t(ML_MAX_PCF_RADIUS));

    const glm::mat4 view = frustums[1].view;
    EXPECT_FALSE(rigidView(glm::scale(view, glm::vec3(1.01f))));
    EXPECT_FALSE(rigidView(glm::scale(view, glm::vec3(-1, 1, 1)))); // mirrored: det -1
    glm::mat4 shear = view;
    shear[1][0] += 0.01f;
    EXPECT_FALSE(rigidView(shear));
    glm::mat4 projective = view;
    projective[2][3] = -1.0f;
    EXPECT_FALSE(rigidView(projective));
    glm::mat4 nan = view;
    nan[3][1] = NAN;
    EXPECT_FALSE(rigidView(nan));
    EXPECT_TRUE(rigidView(glm::mat4(1.0f)));
}
} // namespace ml

namespace ml {
namespace {
// The depth methods' visibility as a plain loop: the mapping and bias of shaders/static/static_pcf.h
// written out again, then every tap of the kernel looked up alone (lookupStaticDepth at the finest level,
// the methods' level lookups above it), without the shared descents, memos and value bounds.
float perTapVisibility(const gpu::GpuShadowRecord& rec, const uint32_t* data, glm::vec3 P, glm::vec3 N,
                       float footprint2, uint32_t& stepOut) {
    const StaticMethod method = StaticMethod(gpu::shadowRecordMethod(rec));
    const uint32_t base = rec.info.y, res = gpu::shadowRecordResolution(rec);
    const int radius = int(gpu::shadowRecordRadius(rec));
    const float tanHalf = rec.frustum.x, farPlane = rec.frustum.z;
    const bool ortho = tanHalf < 0.0f;
    const float orthoHalf = -tanHalf;
    const glm::vec3 vp = gpu::shadowViewPoint(rec, P), vn = gpu::shadowViewVector(rec, N);
    const float z = -vp.z;
    stepOut = 0;
    if (z <= rec.frustum.y) return 1.0f;
    float texelWorld = ortho ? 2.0f * orthoHalf / float(res) : 2.0f * z * tanHalf / float(res);
    uint32_t step = 0;
    if (gpu::shadowRecordByLevel(rec) && method != StaticMethod::SM)
        step = gpu::shadowLevelStep(texelWorld, footprint2, data[base + mhfmt::kLevels]);
    stepOut = step;
    texelWorld = texelWorld * float(1u << step);
    const glm::vec3 q = vp + vn * (texelWorld * float(1 + radius) * rec.bias.y);
    const float zq = -q.z;
    if (zq <= rec.frustum.y) return 1.0f;
    const glm::vec2 ndc = ortho ? glm::vec2(q) / orthoHalf : glm::vec2(q) / (zq * tanHalf);
    const glm::ivec2 t = glm::ivec2(glm::floor((ndc * 0.5f + 0.5f) * float(res))) >> int(step);
    const uint32_t depth = staticQuantizeFloat(std::max(zq - rec.bias.x * texelWorld, 0.0f), farPlane);
    const int levelRes = int((res + (1u << step) - 1u) >> step);
    uint32_t lit = 0;
    for (int y = t.y - radius; y <= t.y + radius; ++y)
        for (int x = t.x - radius; x <= t.x + radius; ++x) {
            if (x < 0 || y < 0 || x >= levelRes || y >= levelRes) {
                ++lit;
                continue;
            }
            const uint32_t ux = uint32_t(x), uy = uint32_t(y), steps = data[base + mhfmt::kLevels] - step;
            const uint32_t d = step == 0                     ? lookupStaticDepth(method, data, base, ux, uy)
                               : method == StaticMethod::MH  ? mhLookupLevel(data, base, ux, uy, steps)
                               : method == StaticMethod::MMH ? mmhLookupLevel(data, base, ux, uy, steps)
                                                             : dagmhLookupLevel(data, base, ux, uy, steps);
            lit += depth <= d;
        }
    return float(lit) / float((2 * radius + 1) * (2 * radius + 1));
}
} // namespace

// The PCF kernels of shaders/static/static_pcf.h (the shader's text, here compiled as C++) count the lit
// taps a plain per-tap loop counts: SM, MH, MMH and DAG-MH (DAG-MH's bounds, shared prefix, shared
// treelet and memos), radius 0 to 2, at the finest level and filtering by level (pixel footprints that
// reach several levels up), on ground receivers around and under a box, the map at an odd base word.
TEST(StaticVisibility, PcfKernelsCountTheTapsAPerTapLoopCounts) {
    const uint32_t res = 256, base = 37;
    const glm::vec3 lo(-0.5f, 0.0f, 1.5f), hi(0.5f, 1.0f, 2.5f);
    Light light;
    light.position = glm::vec3(0.3f, 6.0f, -1.0f);
    light.direction = glm::normalize(glm::vec3(0.0f, 0.0f, 2.0f) - light.position);
    light.range = 20.0f;
    light.outerAngle = 0.7f;
    const LightFrustum f = spotLightFrustum(light);
    const DualDepthMap map = rasterizeDual(groundAndBoxForPcf(lo, hi), f, res);
    const glm::vec3 camera(0.0f, 3.0f, -6.0f);
    for (StaticMethod method : {StaticMethod::SM, StaticMethod::MH, StaticMethod::MMH, StaticMethod::DAGMH}) {
        auto words = encodeStatic(method, map, {f.nearPlane, f.farPlane, {}});
        ASSERT_TRUE(words.ok()) << words.error();
        std::vector<uint32_t> data(base, 0xDEADBEEFu);
        data.insert(data.end(), words->begin(), words->end());
        for (uint32_t radius : {0u, 1u, 2u})
            for (float pixelAngle2 : {0.0f, 1e-4f, 4e-3f}) {
                auto rec = makeShadowRecord(method, f, base, res, radius);
                if (pixelAngle2 > 0.0f) rec.info.z |= 1u; // filter by level
                uint64_t diff = 0, partial = 0, byLevel = 0, receivers = 0;
                for (float x = -4.0f; x <= 4.0f; x += 0.05f)
                    for (float zz = -1.0f; zz <= 8.0f; zz += 0.05f) {
                        const glm::vec3 p(x, 0.0f, zz), n(0, 1, 0);
                        const float fp2 = gpu::shadowFootprint2(camera, p, pixelAngle2);
                        uint32_t step = 0;
                        const float want = perTapVisibility(rec, data.data(), p, n, fp2, step);
                        const float got = staticVisibility(rec, data.data(), p, n, fp2);
                        diff += got != want;
                        partial += want > 0.0f && want < 1.0f;
                        byLevel += step > 0;
                        ++receivers;
                    }
                EXPECT_EQ(diff, 0u) << staticMethodName(method) << " radius " << radius << " pixel angle^2 "
                                    << pixelAngle2 << ", of " << receivers;
                if (radius > 0) {
                    EXPECT_GT(partial, 50u) << staticMethodName(method) << " radius " << radius;
                }
                if (pixelAngle2 > 1e-3f && method != StaticMethod::SM) {
                    EXPECT_GT(byLevel, receivers / 2) << staticMethodName(method);
                }
            }
    }
}
} // namespace ml
