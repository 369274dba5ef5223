// The --window camera: pure arithmetic on its inputs (no window), so the key and mouse mapping is
// tested here and the window test only checks that events reach it.
#include "host/fly_camera.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

void expectNear(glm::vec3 a, glm::vec3 b, float eps = 1e-4f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

TEST(FlyCamera, StartsLookingAtTheTarget) {
    FlyCamera c = FlyCamera::lookingAt({1, 2, 3}, {4, 2, -1});
    expectNear(c.forward(), glm::normalize(glm::vec3(3, 0, -4)));
    CameraDesc d = c.desc({});
    expectNear(glm::normalize(toGlm(d.target) - toGlm(d.position)), glm::normalize(glm::vec3(3, 0, -4)));
}

TEST(FlyCamera, KeysMoveAlongItsAxesAndShiftIsFaster) {
    FlyCamera c = FlyCamera::lookingAt({0, 0, 0}, {0, 0, -1}); // looking down -z, right is +x
    c.update({.forward = 1}, 0.5f);
    expectNear(c.position(), {0, 0, -0.5f * FlyCamera::kSpeed});
    c.update({.forward = -1}, 0.5f);
    c.update({.right = 1}, 1.0f);
    expectNear(c.position(), {FlyCamera::kSpeed, 0, 0});
    c.update({.right = -1, .up = 1, .fast = true}, 1.0f);
    expectNear(c.position(), {FlyCamera::kSpeed * (1 - FlyCamera::kFastFactor),
                              FlyCamera::kSpeed * FlyCamera::kFastFactor, 0});
}

TEST(FlyCamera, MouseTurnsAndPitchStopsShortOfVertical) {
    FlyCamera c = FlyCamera::lookingAt({0, 0, 0}, {0, 0, -1});
    float quarter = 1.5707963f / FlyCamera::kRadiansPerPixel;
    c.update({.lookX = quarter}, 0.0f); // mouse right: now facing +x
    expectNear(c.forward(), {1, 0, 0}, 1e-3f);
    c.update({.lookY = -100000.0f}, 0.0f); // far up: clamped
    EXPECT_NEAR(c.forward().y, std::sin(FlyCamera::kMaxPitch), 1e-4f);
    c.update({.lookY = 100000.0f}, 0.0f);
    EXPECT_NEAR(c.forward().y, -std::sin(FlyCamera::kMaxPitch), 1e-4f);
    EXPECT_LT(std::abs(c.forward().y), 0.999f); // never parallel to up
}

} // namespace
} // namespace ml
