// The disagreement classifier (bake/reference/error_classes.h) on receivers whose class is known by
// construction: a light 6 m above a ground with a closed box and a floating open quad, a 64^2 map.
#include "failure_util.h"
#include "bake/scene_casters.h"

#include "bake/reference/error_classes.h"

namespace ml::test {

TEST(ErrorClasses, KnownReceiversGetTheirClass) {
    Scene s = groundScene("classes");
    addBox(s, {-1, 0, -1}, {1, 2, 1});         // closed, 2 m tall
    addQuad(s, 2.0f, 4.0f, -1.0f, 1.0f, 2.0f); // open, 2 m up
    Light l = spotAt({1, 6, 0}, {1, 0, 0}, 20.0f, 0.8f);
    s.lights.push_back(l);
    auto rays = RayReference::build(s, true);
    ASSERT_TRUE(rays.ok()) << rays.error();
    LightFrustum f = spotLightFrustum(l);
    const uint32_t res = 64;
    DualDepthMap map = rasterizeDual(castersFromScene(s), f, res);
    auto words = encodeStatic(StaticMethod::SM, map, {f.nearPlane, f.farPlane, {}});
    ASSERT_TRUE(words.ok()) << words.error();
    ErrorContext ctx{&rays.value(), makeShadowRecord(StaticMethod::SM, f, 0, res, 0), words->data(),
                     l.position, 0.02f};
    const glm::vec3 up(0, 1, 0);
    // Inside the box: the first surface towards the light is the box's top from inside (a back face).
    EXPECT_EQ(classifyDisagreement(ctx, {0, 1, 0}, up), ErrorClass::Inside);
    // On the ground 1 cm from the box's -x wall, which shadows it from the light at x = 1: the wall is
    // within the bias band.
    EXPECT_EQ(classifyDisagreement(ctx, {-1.01f, 0, 0}, up), ErrorClass::Contact);
    // On the ground in the middle of the quad's shadow (far from its edges): blocked by open geometry.
    glm::vec3 underQuad = glm::vec3(3.0f, 0.0f, 0.0f);
    EXPECT_EQ(classifyDisagreement(ctx, underQuad, up), ErrorClass::ThinOpen);
    // On the ground at the edge of the quad's shadow (the quad's +z edge projects to z = 1 * 6 / 4).
    EXPECT_EQ(classifyDisagreement(ctx, {3.0f, 0.0f, 1.5f}, up), ErrorClass::Resolution);
    // On the box's lit top, away from every edge: no reason known.
    EXPECT_EQ(classifyDisagreement(ctx, {0.3f, 2.0f, 0.0f}, up), ErrorClass::Other);
}

} // namespace ml::test
