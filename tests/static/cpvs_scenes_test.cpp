// CPVS on real geometry: dual maps of night-city and FZK-Haus spotlights from the CPU rasteriser, every
// voxel checked; lights with no caster, only casters and a caster at the near plane.
#include "cpvs_test_util.h"

#include "bake/scene_casters.h"
#include "scenes/scenes.h"
#include "tests/common/shared_scenes.h"

namespace ml::ctest {
namespace {

// ---------------------------------------------------------------------------------------------------
// Real geometry: dual maps from the CPU rasteriser (shadows/static/raster_dual.h).

std::vector<Light> staticSpots(const Scene& scene, size_t count) {
    std::vector<Light> out;
    for (const Light& l : scene.lights)
        if (l.type == LightKind::Spot && !l.dynamic && out.size() < count) out.push_back(l);
    return out;
}

CpvsBake bakeLight(const DualDepthMap& map, const LightFrustum& f, uint32_t n) {
    CpvsParams p;
    p.resolution = n;
    p.nearPlane = f.nearPlane;
    p.farPlane = f.farPlane;
    auto b = bakeCpvs(map, p);
    EXPECT_TRUE(b.ok()) << b.error();
    return b.ok() ? std::move(*b) : CpvsBake{};
}

// 256^3: every voxel by lookup against cpvsReferenceVoxel; 512^3: every voxel by verifyCpvs's column walk.
void realScene(const char* name, const Scene& scene, size_t lights) {
    CasterTriangles casters = castersFromScene(scene);
    auto spots = staticSpots(scene, lights);
    ASSERT_FALSE(spots.empty());
    for (size_t li = 0; li < spots.size(); ++li) {
        LightFrustum f = spotLightFrustum(spots[li]);
        for (uint32_t n : {256u, 512u}) {
            SCOPED_TRACE(std::string(name) + " light " + std::to_string(li) + " at " + std::to_string(n));
            DualDepthMap map = rasterizeDual(casters, f, n);
            CpvsBake b = bakeLight(map, f, n);
            ASSERT_TRUE(validateCpvs(b.data.data(), b.data.size()).ok());
            CpvsVerifyReport v = verifyCpvs(b.data.data(), map);
            EXPECT_EQ(v.mismatches, 0u);
            EXPECT_EQ(v.checked + v.undefined, uint64_t(n) * n * n);
            if (n == 256) {
                auto space = makeCpvsSpace(n, f.nearPlane, f.farPlane);
                uint64_t wrong = 0, checked = 0;
                for (uint32_t s = 0; s < n; ++s)
                    for (uint32_t y = 0; y < n; ++y)
                        for (uint32_t x = 0; x < n; ++x) {
                            CpvsVoxel r = cpvsReferenceVoxel(*space, map, x, y, s);
                            if (r == CpvsVoxel::Undefined) continue;
                            ++checked;
                            wrong += cpvsShadowedVoxel(b.data.data(), 0, int32_t(x), int32_t(y),
                                                       int32_t(s)) != (r == CpvsVoxel::Shadowed);
                        }
                EXPECT_EQ(wrong, 0u);
                EXPECT_EQ(checked, v.checked);
            }
            std::printf("  [cpvs] %s light %zu: %llu voxels checked, %llu undefined\n", name, li,
                        (unsigned long long)v.checked, (unsigned long long)v.undefined);
            printSize(name, n, b);
        }
    }
}

TEST(CpvsScenes, NightCityExhaustive) {
    auto scene = loadScene("night-city", 64, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    realScene("night-city", *scene, 3);
}

TEST(CpvsScenes, FzkHausExhaustive) {
    ML_SKIP_WITHOUT_SHARED();
    auto scene = loadScene(test::sharedScenePath("fzk-haus.glb"), 8, 1);
    ASSERT_TRUE(scene.ok()) << scene.error();
    realScene("fzk-haus", *scene, 2);
}

// Lights whose frustum holds no caster, only casters (the light buried inside a closed box), and a caster
// touching the near plane.
TEST(CpvsScenes, EmptyFullAndNearCasterFrusta) {
    Scene scene;
    Mesh box;
    box.closed = true;
    const glm::vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1},
                            {-1, -1, 1},  {1, -1, 1},  {-1, 1, 1},  {1, 1, 1}};
    for (const auto& p : c) box.vertices.push_back({p, glm::vec3(0.0f)});
    box.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    scene.meshes.push_back(box);
    Instance inst;
    inst.transform = glm::mat4(1.0f);
    scene.instances.push_back(inst);
    CasterTriangles casters = castersFromScene(scene);
    struct Case {
        const char* name;
        glm::vec3 pos, dir;
    };
    const Case cases[] = {
        {"no-caster", {0, 10, 0}, {0, 1, 0}},       // looking away from the box
        {"inside-caster", {0, 0, 0}, {0, -1, 0}},   // the light sits inside the closed box
        {"near-caster", {0, 1.05f, 0}, {0, -1, 0}}, // the box's top 5 cm below: at the near plane
        {"box-below", {0, 4.0f, 0}, {0, -1, 0}},
    };
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        Light l;
        l.position = k.pos;
        l.direction = k.dir;
        l.range = 8.0f;
        l.outerAngle = 0.7f;
        LightFrustum f = spotLightFrustum(l);
        const uint32_t n = 128;
        DualDepthMap map = rasterizeDual(casters, f, n);
        CpvsBake b = bakeLight(map, f, n);
        ASSERT_TRUE(validateCpvs(b.data.data(), b.data.size()).ok());
        CpvsVerifyReport v = verifyCpvs(b.data.data(), map);
        EXPECT_EQ(v.mismatches, 0u);
        EXPECT_EQ(v.checked + v.undefined, uint64_t(n) * n * n);
        printSize(k.name, n, b);
    }
}

} // namespace
} // namespace ml::ctest
