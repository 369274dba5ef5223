// What the API-sequence fuzzer (tests/api_fuzz/api_fuzz.cpp) found, kept as plain regression tests.
//
// A spot light whose cone validateLight accepts (outer half angle up to just under pi/2) made
// bakeStaticShadows fail for the whole scene: the bake's own frustum (fov = 2 x outer, above 3.1) was
// refused by setStaticShadow's check, which said "0 < fov < pi" but tested fov < 3.1.
#include "../../gpu/gpu_test_util.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace ml::test {
namespace {

void addGround(Module& m) {
    static const std::vector<MeshVertex> v = {
        {{-8, 0, -8}, {0, 1, 0}}, {{8, 0, -8}, {0, 1, 0}}, {{8, 0, 8}, {0, 1, 0}}, {{-8, 0, 8}, {0, 1, 0}}};
    static const std::vector<uint32_t> i = {0, 2, 1, 0, 3, 2};
    auto ground = m.addMesh({v, i, false, "ground"});
    ASSERT_TRUE(ground.ok()) << ground.error();
    ASSERT_TRUE(m.addInstance(ground.value(), glm::mat4(1.0f), glm::vec3(0.5f), false).ok());
    // A small raised quad above the ground: a static caster under the lights.
    ASSERT_TRUE(m.addInstance(ground.value(),
                              glm::scale(glm::translate(glm::mat4(1.0f), {0, 1.5f, 0}), glm::vec3(0.1f)),
                              glm::vec3(0.5f), false)
                    .ok());
}

TEST(FuzzFound, WideSpotConesBake) {
    auto m = makeModule();
    ASSERT_TRUE(m);
    addGround(*m);
    // The widest cones validateLight accepts, and one just past the old 3.1 limit (fov 3.12).
    for (float outer : {std::nextafter(1.5707963f, 0.0f), 1.56f, 1.2f}) {
        LightDesc l;
        l.kind = LightKind::Spot;
        l.position = {0, 4, 0};
        l.direction = {0, -1, 0};
        l.outerAngle = outer;
        l.innerAngle = 0.5f * outer;
        ASSERT_TRUE(validateLight(l).ok()) << outer;
        ASSERT_TRUE(m->addLight(l).ok());
    }
    for (StaticMethod method : {StaticMethod::SM, StaticMethod::DAGMH}) {
        auto baked = m->bakeStaticShadows(method, 32);
        ASSERT_TRUE(baked.ok()) << baked.error();
        EXPECT_EQ(baked.value(), 3u);
    }
    ASSERT_TRUE(m->createTargets(32, 18).ok());
    ASSERT_TRUE(m->setCamera({{0, 6, 8}, {0, 0, 0}}).ok());
    renderFrame(*m);
    std::vector<uint8_t> rgba;
    ASSERT_TRUE(m->readOutput(rgba).ok());
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
