// The CPU part of the virtual shadow maps follows what changed: the coverage and
// stale bits are computed from the dynamic casters and the instances that moved, each tested against
// the lights near it, so adding static instances that never move adds no work. Counted, not timed
// (VsmSlotHost::sphereTests and projections): the same frames with 20 and with 2,000 static boxes do
// the same tests and projections, and the projections follow the lights the moving box is near. The
// module's instance and light records and the VSM's caster upload visit only what the host changed.
#include "gpu_test_util.h"

#include "shadows/static/raster_dual.h"
#include "shadows/virtual/vsm.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <random>

namespace ml::test {
namespace {

struct BoxMesh {
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    BoxMesh() {
        for (int k = 0; k < 8; ++k)
            vertices.push_back(
                {{k & 1 ? 0.5f : -0.5f, k & 2 ? 1.0f : 0.0f, k & 4 ? 0.5f : -0.5f}, {0, 1, 0}});
        indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    }
    MeshDesc desc() const { return {vertices, indices, true, "box"}; }
};

struct Work {
    uint64_t sphereTests = 0, projections = 0;
    // Frames 2 on (frames 0 and 1 write everything into each frame slot's new buffers): instances the
    // module compared, caster records the VSM visited, light records remade (light 5 is set to a new
    // colour in frame 2).
    uint64_t instancesVisited = 0, castersVisited = 0, lightRecordsMade = 0;
};

// A row of 16 spot lights 10 m apart along x (range 6), `statics` static boxes scattered in a far
// field, and one dynamic box that moves each frame under the first lights.
Work run(uint32_t statics, uint32_t frames) {
    ModuleOptions o;
    o.device.validation = true;
    o.vsm.enabled = true;
    o.vsm.resolution = 256;
    o.vsm.maxMaps = 32;
    auto created = Module::create(o);
    EXPECT_TRUE(created.ok()) << created.error();
    if (!created) return {};
    Module& m = *created.value();
    const BoxMesh box;
    auto mesh = m.addMesh(box.desc());
    EXPECT_TRUE(mesh.ok());
    auto ground = m.addInstance(mesh.value(), glm::scale(glm::mat4(1.0f), glm::vec3(400, 0.1f, 40)),
                                glm::vec3(0.5f), false);
    EXPECT_TRUE(ground.ok());
    for (uint32_t i = 0; i < statics; ++i) { // far from every light: z 100..140
        const glm::vec3 at(float(i % 50) * 3.0f, 0.0f, 100.0f + float(i / 50));
        EXPECT_TRUE(m.addInstance(mesh.value(), glm::translate(glm::mat4(1.0f), at), glm::vec3(0.6f), false));
    }
    auto mover = m.addInstance(mesh.value(), glm::mat4(1.0f), glm::vec3(0.6f), true);
    EXPECT_TRUE(mover.ok());
    for (uint32_t l = 0; l < 16; ++l) {
        LightDesc spot;
        spot.position = {10.0f * float(l), 5.0f, 0.0f};
        spot.direction = {0, -1, 0};
        spot.range = 6.0f;
        EXPECT_TRUE(m.addLight(spot));
    }
    EXPECT_TRUE(m.createTargets(64, 36));
    CameraDesc cam;
    cam.position = {75, 60, 60};
    cam.target = {75, 0, 0};
    EXPECT_TRUE(m.setCamera(cam));
    Work w;
    for (uint32_t f = 0; f < frames; ++f) {
        const glm::vec3 at(2.0f + float(f), 0.0f, 0.0f); // under lights 0 and 1
        EXPECT_TRUE(m.setInstanceTransform(mover.value(), glm::translate(glm::mat4(1.0f), at)));
        if (f == 2) {
            LightDesc spot;
            spot.position = {50.0f, 5.0f, 0.0f};
            spot.direction = {0, -1, 0};
            spot.range = 6.0f;
            spot.color = {1.0f, 0.5f, 0.25f};
            EXPECT_TRUE(m.setLight(LightId(5), spot));
        }
        const auto& impl = internals(m);
        const uint64_t instancesBefore = impl.instancesVisited, lightsBefore = impl.lightRecordsMade;
        renderFrame(m);
        w.sphereTests += impl.vsm.slotHost(impl.lastSlot).sphereTests;
        w.projections += impl.vsm.slotHost(impl.lastSlot).projections;
        if (f < 2) continue;
        w.instancesVisited += impl.instancesVisited - instancesBefore;
        w.castersVisited += impl.vsm.slotHost(impl.lastSlot).castersVisited;
        w.lightRecordsMade += impl.lightRecordsMade - lightsBefore;
    }
    EXPECT_EQ(validationErrors(), 0u);
    return w;
}

TEST(VsmCpu, WorkFollowsTheMovingInstances) {
    const Work few = run(20, 4), many = run(2000, 4);
    std::printf("20 statics: %llu sphere tests, %llu projections; 2000: %llu, %llu\n",
                (unsigned long long)few.sphereTests, (unsigned long long)few.projections,
                (unsigned long long)many.sphereTests, (unsigned long long)many.projections);
    // Frame 0 has no previous bounds (nothing is stale yet); frames 1-3 move one box: its old and new
    // bounds, tested against the lights whose centre lies within the largest radius of its x extent.
    EXPECT_GT(few.sphereTests, 0u);
    EXPECT_GT(few.projections, 0u);
    EXPECT_EQ(few.sphereTests, many.sphereTests) << "static instances that never move added sphere tests";
    EXPECT_EQ(few.projections, many.projections) << "static instances that never move added projections";
    // Projections: the moving box is within reach of lights 0 and 1 only (one map each), twice per
    // frame (old and new bounds) in frames 1-3: at most 2 x 2 x 3, far below maps x instances.
    EXPECT_LE(many.projections, 12u);
    // Sphere tests: a window of the lights near x (3 of the 16 at most per box), not all 16.
    EXPECT_LE(many.sphereTests, 3u * 2 * 3 + 3u * 4);
}

// The module's own per-frame pass over instances and lights follows the host's calls too: in frames 2-3
// only the moving box is compared (one instance a frame), the VSM's caster upload visits the changes
// since its slot's last frame (the mover of this frame and of the one before: at most 2 a frame), and a
// light's records are remade only in the frame after setLight (one light), whatever the instance count.
TEST(VsmCpu, RecordVisitsOnlyWhatTheHostChanged) {
    const Work few = run(20, 4), many = run(2000, 4);
    std::printf("frames 2-3: instances visited %llu / %llu, casters %llu / %llu, light records %llu / %llu\n",
                (unsigned long long)few.instancesVisited, (unsigned long long)many.instancesVisited,
                (unsigned long long)few.castersVisited, (unsigned long long)many.castersVisited,
                (unsigned long long)few.lightRecordsMade, (unsigned long long)many.lightRecordsMade);
    EXPECT_EQ(many.instancesVisited, 2u) << "one moving instance a frame";
    EXPECT_EQ(few.castersVisited, many.castersVisited);
    EXPECT_GE(many.castersVisited, 2u);
    EXPECT_LE(many.castersVisited, 4u);
    EXPECT_EQ(many.lightRecordsMade, 1u) << "setLight on one light";
    EXPECT_EQ(few.lightRecordsMade, 1u);
}

// The cone test that markCoverageAndStale runs before projecting a box into a spot light's map refuses
// only boxes with no point in the map's frustum (so drawing them changes no texel and no page needs
// their stale bits). Checked over 200 random spot lights (outer angles 0.05-1.5 rad, any direction) and
// 200 boxes each around them, the map built as VirtualShadowMaps::buildMap builds it (spotLightFrustum,
// perspective 0..1 depth): every refused box's 9^3 sample points lie outside the frustum. The plane test
// of vsmProjectBox is looser (it takes some boxes beside the frustum's corners): counted, not failed.
TEST(VsmCpu, SpotConeNeverRefusesABoxTheMapTakes) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    uint64_t refused = 0, taken = 0, looser = 0;
    for (int l = 0; l < 200; ++l) {
        VsmLight light;
        light.kind = ML_LIGHT_SPOT;
        light.position = {u(rng) * 20 - 10, u(rng) * 10, u(rng) * 20 - 10};
        light.direction = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) + 1e-3f);
        light.range = 2.0f + 10.0f * u(rng);
        light.outerAngle = 0.05f + 1.45f * u(rng);
        LightShape shape;
        shape.position = light.position;
        shape.direction = light.direction;
        shape.range = light.range;
        shape.outerAngle = light.outerAngle;
        const LightFrustum f = spotLightFrustum(shape);
        gpu::GpuVsmMap map{};
        map.viewProj = glm::perspectiveRH_ZO(f.fov, 1.0f, f.nearPlane, f.farPlane) * f.view;
        const VsmCone cone = vsmSpotCone(light);
        ASSERT_GT(cone.cos, -0.5f) << "every test light is a spot with a cone";
        for (int b = 0; b < 200; ++b) {
            const glm::vec3 c =
                light.position +
                1.2f * light.range * glm::vec3(u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1);
            const glm::vec3 h = glm::vec3(u(rng), u(rng), u(rng)) * (0.05f + 2.0f * u(rng));
            glm::uvec4 rect;
            const bool planes = vsmProjectBox(map, c - h, c + h, 64, rect);
            const bool mayTouch = vsmBoxMayTouchCone(cone, light.position, c - h, c + h);
            refused += mayTouch ? 0 : 1;
            taken += mayTouch ? 1 : 0;
            looser += !mayTouch && planes ? 1 : 0;
            if (mayTouch) continue;
            bool inside = false;
            for (int k = 0; k < 9 * 9 * 9 && !inside; ++k) {
                const glm::vec3 t(float(k % 9) / 8.0f, float(k / 9 % 9) / 8.0f, float(k / 81) / 8.0f);
                const glm::vec4 q = map.viewProj * glm::vec4(c - h + 2.0f * h * t, 1.0f);
                inside = q.w > 0 && std::abs(q.x) <= q.w && std::abs(q.y) <= q.w && q.z >= 0 && q.z <= q.w;
            }
            EXPECT_FALSE(inside) << "light " << l << " box " << b
                                 << ": refused, yet a point is in the frustum";
        }
    }
    std::printf("cone: %llu boxes refused, %llu taken; the plane test took %llu of the refused\n",
                (unsigned long long)refused, (unsigned long long)taken, (unsigned long long)looser);
    EXPECT_GT(refused, 4000u) << "the cone should refuse the boxes beside and behind the lights";
}

} // namespace
} // namespace ml::test
