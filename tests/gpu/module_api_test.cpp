// The public API's lifecycle and refusals (manylights/module.h): removal with generation-checked ids,
// shadow-casting flags, environment, HDR output, and the values a host must not get away with.
#include "gpu_test_util.h"

#include <cmath>

namespace ml::test {
namespace {

MeshId addBox(Module& m) {
    static const std::vector<MeshVertex> v = {
        {{-1, 0, -1}, {0, 1, 0}}, {{1, 0, -1}, {0, 1, 0}}, {{1, 0, 1}, {0, 1, 0}}, {{-1, 0, 1}, {0, 1, 0}}};
    static const std::vector<uint32_t> i = {0, 2, 1, 0, 3, 2};
    auto id = m.addMesh({v, i, false, "quad"});
    EXPECT_TRUE(id.ok());
    return id.value();
}

TEST(ModuleApi, RemovedIdsAreRefusedAndSlotsReused) {
    auto m = makeModule();
    LightDesc l;
    l.position = {0, 5, 0};
    auto a = m->addLight(l);
    ASSERT_TRUE(a.ok());
    EXPECT_EQ(m->lightCount(), 1u);
    ASSERT_TRUE(m->removeLight(a.value()).ok());
    EXPECT_EQ(m->lightCount(), 0u);
    EXPECT_FALSE(m->setLight(a.value(), l).ok());
    EXPECT_FALSE(m->removeLight(a.value()).ok());
    auto b = m->addLight(l); // reuses the slot with a new generation
    ASSERT_TRUE(b.ok());
    EXPECT_NE(a.value(), b.value());
    EXPECT_TRUE(m->setLight(b.value(), l).ok());
    EXPECT_FALSE(m->setLight(a.value(), l).ok()) << "the old id must not reach the slot's new light";

    MeshId mesh = addBox(*m);
    auto inst = m->addInstance(mesh, glm::mat4(1.0f), glm::vec3(0.5f), true);
    ASSERT_TRUE(inst.ok());
    EXPECT_FALSE(m->removeMesh(mesh).ok()) << "a mesh in use is not removed";
    ASSERT_TRUE(m->removeInstance(inst.value()).ok());
    EXPECT_FALSE(m->setInstanceTransform(inst.value(), glm::mat4(1.0f)).ok());
    auto inst2 = m->addInstance(mesh, glm::mat4(1.0f), glm::vec3(0.5f), true);
    ASSERT_TRUE(inst2.ok());
    EXPECT_NE(inst.value(), inst2.value());
    ASSERT_TRUE(m->removeInstance(inst2.value()).ok());
    EXPECT_TRUE(m->removeMesh(mesh).ok());
    EXPECT_FALSE(m->addInstance(mesh, glm::mat4(1.0f), glm::vec3(0.5f), false).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(ModuleApi, RemovedInstanceIsNotDrawnAndEnvironmentIsUsed) {
    auto m = makeModule();
    MeshId mesh = addBox(*m);
    auto inst = m->addInstance(mesh, glm::scale(glm::mat4(1.0f), glm::vec3(50.0f)), glm::vec3(0.5f), false);
    ASSERT_TRUE(inst.ok());
    ASSERT_TRUE(m->setCamera({{0, 10, 10}, {0, 0, 0}}).ok());
    ASSERT_TRUE(m->createTargets(64, 36).ok());
    ASSERT_TRUE(m->setEnvironment(glm::vec3(0.0f), glm::vec3(0.5f, 0.0f, 0.0f)).ok());
    renderFrame(*m);
    auto r1 = m->takeReports();
    ASSERT_EQ(r1.size(), 1u);
    EXPECT_GT(r1[0].stats.surfacePixels, 0u);
    ASSERT_TRUE(m->removeInstance(inst.value()).ok());
    renderFrame(*m);
    auto r2 = m->takeReports();
    ASSERT_EQ(r2.size(), 1u);
    EXPECT_EQ(r2[0].stats.surfacePixels, 0u);
    std::vector<uint8_t> rgba;
    ASSERT_TRUE(m->readOutput(rgba).ok());
    EXPECT_GT(rgba[0], 100); // the red sky, tone-mapped
    EXPECT_LT(rgba[1], 10);
    EXPECT_FALSE(m->setEnvironment(glm::vec3(NAN), glm::vec3(0.0f)).ok());
    EXPECT_FALSE(m->setEnvironment(glm::vec3(0.0f), glm::vec3(-1.0f)).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(ModuleApi, RefusesBadCamerasTransformsAndMovingStaticInstances) {
    auto m = makeModule();
    MeshId mesh = addBox(*m);
    auto stat = m->addInstance(mesh, glm::mat4(1.0f), glm::vec3(0.5f), false);
    auto dyn = m->addInstance(mesh, glm::mat4(1.0f), glm::vec3(0.5f), true);
    ASSERT_TRUE(stat.ok() && dyn.ok());
    EXPECT_FALSE(m->setInstanceTransform(stat.value(), glm::mat4(2.0f)).ok());
    glm::mat4 bad(1.0f);
    bad[3][0] = NAN;
    EXPECT_FALSE(m->setInstanceTransform(dyn.value(), bad).ok());
    EXPECT_FALSE(m->addInstance(mesh, bad, glm::vec3(0.5f), true).ok());
    EXPECT_FALSE(m->addInstance(mesh, glm::mat4(1.0f), glm::vec3(NAN), true).ok());
    EXPECT_TRUE(m->setInstanceTransform(dyn.value(), glm::mat4(2.0f)).ok());
    CameraDesc c{{0, 10, 0}, {0, 0, 0}};
    EXPECT_FALSE(m->setCamera(c).ok()) << "up parallel to the view direction";
    c.up = {0, 0, 1};
    EXPECT_TRUE(m->setCamera(c).ok());
    c.position.x = NAN;
    EXPECT_FALSE(m->setCamera(c).ok());
    c.position = {0, 10, 0};
    c.target = {0, 0, 1e9f};
    EXPECT_FALSE(m->setCamera(c).ok());
    c.target = {0, 0, 0};
    c.farPlane = INFINITY;
    EXPECT_FALSE(m->setCamera(c).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(ModuleApi, NonCastingLightsAndInstancesGetNoShadowMaps) {
    auto scene = loadScene("night-city", 64, 1);
    ASSERT_TRUE(scene.ok());
    auto m = makeModule(CullingMode::Clustered, /*vsm*/ true);
    auto binding = bindScene(*m, scene.value());
    ASSERT_TRUE(binding.ok());
    ASSERT_TRUE(m->createTargets(160, 90).ok());
    renderFrame(*m);
    auto before = m->takeReports();
    ASSERT_EQ(before.size(), 1u);
    ASSERT_GT(before[0].stats.vsm.lightsWithPages, 0u);
    for (size_t i = 0; i < scene->lights.size(); ++i) {
        LightDesc d = toLightDesc(scene->lights[i]);
        d.castsShadows = false;
        ASSERT_TRUE(m->setLight(binding->lights[i], d).ok());
    }
    renderFrame(*m);
    auto after = m->takeReports();
    ASSERT_EQ(after.size(), 1u);
    EXPECT_EQ(after[0].stats.vsm.lightsWithPages, 0u);
    EXPECT_EQ(validationErrors(), 0u);
}

// Values that used to pass silently: 0 frames in flight (clamped to 1), a frame recorded before any
// camera (a default view the host never chose), a zero-scale transform (no inverse: NaN normals).
TEST(ModuleApi, RefusesZeroFramesInFlightNoCameraAndZeroScale) {
    resetValidationCounters();
    ModuleOptions o;
    o.device.validation = true;
    o.framesInFlight = 0;
    auto none = Module::create(o);
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error(), "framesInFlight must be 1..16, got 0");
    auto m = makeModule();
    ASSERT_TRUE(m->createTargets(32, 18).ok());
    auto early = m->submitFrame();
    ASSERT_FALSE(early.ok());
    EXPECT_EQ(early.error(), "record: no camera (call setCamera or setCameraMatrices first)");
    ASSERT_TRUE(m->setCamera({{0, 5, 10}, {0, 0, 0}}).ok());
    EXPECT_TRUE(m->submitFrame().ok());
    MeshId mesh = addBox(*m);
    const glm::mat4 flat = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 0.0f, 1.0f));
    auto zero = m->addInstance(mesh, flat, glm::vec3(0.5f), true);
    ASSERT_FALSE(zero.ok());
    EXPECT_EQ(zero.error(), "addInstance: transform is singular (a zero scale)");
    auto dyn = m->addInstance(mesh, glm::mat4(1.0f), glm::vec3(0.5f), true);
    ASSERT_TRUE(dyn.ok()) << dyn.error();
    auto moved = m->setInstanceTransform(dyn.value(), glm::mat4(0.0f));
    ASSERT_FALSE(moved.ok());
    EXPECT_NE(moved.error().find("transform is singular (a zero scale)"), std::string::npos) << moved.error();
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(ModuleApi, HdrOutputWritesTheHdrImageOnly) {
    resetValidationCounters();
    ModuleOptions o;
    o.device.validation = true;
    o.hdrOutput = true;
    auto m = Module::create(o);
    ASSERT_TRUE(m.ok()) << m.error();
    ASSERT_TRUE(m.value()->createTargets(32, 18).ok());
    ASSERT_TRUE(m.value()->setCamera({{0, 5, 10}, {0, 0, 0}}).ok());
    renderFrame(*m.value());
    std::vector<uint8_t> rgba;
    EXPECT_FALSE(m.value()->readOutput(rgba).ok());
    EXPECT_EQ(m.value()->outputImage(), internals(*m.value()).hdr.image);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test

namespace ml::test {
// Virtual shadow map settings the device cannot hold are refused at create(), with the reason.
TEST(ModuleApi, RefusesVsmSettingsTheDeviceCannotHold) {
    ModuleOptions o;
    o.device.validation = true;
    o.vsm.enabled = true;
    o.vsm.maxMaps = 65537; // past the settings' range (map slots no longer depend on image array layers)
    auto m = Module::create(o);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().find("max maps"), std::string::npos) << m.error();
    o.vsm.maxMaps = 512;
    o.vsm.pageSize = 48;
    m = Module::create(o);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().find("page size"), std::string::npos) << m.error();
    o.vsm.pageSize = 64;
    for (float t : {3.0f, 16.0f, 0.125f, std::nanf("")}) {
        o.vsm.texelsPerPixel = t;
        m = Module::create(o);
        ASSERT_FALSE(m.ok()) << t;
        EXPECT_NE(m.error().find("texels per pixel"), std::string::npos) << m.error();
    }
}
} // namespace ml::test

#include "shadows/static/static_method.h"

namespace ml::test {
namespace {
// A perspective frustum looking down -Z from the origin, and a plain map of `res`^2 empty texels for it.
LightFrustum plainFrustum() {
    LightFrustum f;
    f.fov = 1.2f;
    f.nearPlane = 0.05f;
    f.farPlane = 10.0f;
    return f;
}
Result<std::vector<uint32_t>> emptyPlainBake(uint32_t res, const LightFrustum& f) {
    DualDepthMap map;
    map.resolution = res;
    map.enter.assign(size_t(res) * res, kDepthEmpty);
    map.exit = map.enter;
    return encodeStatic(StaticMethod::SM, map, {f.nearPlane, f.farPlane, {}});
}
} // namespace

// Every light's static words share one storage buffer: a bake that would take it past the device's
// storage buffer range is refused by setStaticShadow with the sizes, not bound and left to fail.
TEST(ModuleApi, RefusesStaticShadowsBeyondTheStorageBufferRange) {
    auto m = makeModule();
    const uint64_t range = deviceOf(*m).properties.limits.maxStorageBufferRange;
    const LightFrustum f = plainFrustum();
    auto words = emptyPlainBake(2048, f); // 16 MiB of words
    ASSERT_TRUE(words.ok()) << words.error();
    const uint64_t perBake = words->size() * 4;
    const uint32_t fit = uint32_t(range / perBake); // bakes that fit; one more must be refused
    ASSERT_LE(fit, 64u) << "storage buffer range too large for this test's sizes";
    std::vector<LightId> ids;
    for (uint32_t i = 0; i <= fit; ++i) {
        LightDesc l;
        l.position = {float(i), 3, 0};
        auto id = m->addLight(l);
        ASSERT_TRUE(id.ok()) << id.error();
        ids.push_back(id.value());
    }
    for (uint32_t i = 0; i < fit; ++i) {
        auto r = m->setStaticShadow(ids[i], {StaticMethod::SM, f, words.value(), 0});
        ASSERT_TRUE(r.ok()) << "bake " << i << ": " << r.error();
    }
    auto refused = m->setStaticShadow(ids[fit], {StaticMethod::SM, f, words.value(), 0});
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().find("storage buffer range"), std::string::npos) << refused.error();
    // Replacing a bake counts its old words out; removing one makes room.
    EXPECT_TRUE(m->setStaticShadow(ids[0], {StaticMethod::SM, f, words.value(), 0}).ok());
    m->clearStaticShadow(ids[0]);
    EXPECT_TRUE(m->setStaticShadow(ids[fit], {StaticMethod::SM, f, words.value(), 0}).ok());
    ASSERT_TRUE(m->createTargets(64, 36).ok());
    ASSERT_TRUE(m->setCamera({{0, 5, 10}, {0, 0, 0}}).ok());
    renderFrame(*m);
    EXPECT_EQ(validationErrors(), 0u);
}

// The shadow record holds a light view as a quaternion and a translation: a bake whose view is not a
// rigid motion (scaled, mirrored, projective) is refused with the reason, not looked up wrongly.
TEST(ModuleApi, RefusesStaticShadowsWithANonRigidView) {
    auto m = makeModule();
    const LightFrustum f = plainFrustum();
    auto words = emptyPlainBake(16, f);
    ASSERT_TRUE(words.ok()) << words.error();
    LightDesc l;
    l.position = {0, 3, 0};
    auto id = m->addLight(l);
    ASSERT_TRUE(id.ok()) << id.error();
    ASSERT_TRUE(m->setStaticShadow(id.value(), {StaticMethod::SM, f, words.value(), 0}).ok());
    for (int k = 0; k < 3; ++k) {
        LightFrustum g = f;
        if (k == 0) g.view[0][0] = 2.0f;
        if (k == 1) g.view[2][2] = -1.0f;
        if (k == 2) g.view[2][3] = -1.0f;
        auto r = m->setStaticShadow(id.value(), {StaticMethod::SM, g, words.value(), 0});
        ASSERT_FALSE(r.ok()) << "case " << k;
        EXPECT_NE(r.error().find("not a rigid motion"), std::string::npos) << r.error();
    }
    EXPECT_EQ(validationErrors(), 0u);
}
} // namespace ml::test
