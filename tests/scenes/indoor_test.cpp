// The procedural indoor level (scenes/indoor.cpp): exact light counts by kind, lights inside the
// rooms and under the ceiling, carts on loops through the doorways (never inside a wall), determinism,
// and the refusals.
#include "scene_test_util.h"

#include "scenes/scenes.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

Scene indoor(uint32_t lights, uint32_t seed = 1) {
    IndoorOptions o;
    o.lights = lights;
    o.seed = seed;
    auto r = makeIndoor(o);
    EXPECT_TRUE(r.ok()) << r.error();
    return r.ok() ? std::move(r.value()) : Scene{};
}

TEST(ScenesIndoor, LightCountsByKindAndPlacement) {
    for (uint32_t n : {1u, 12u, 600u, 4096u}) {
        SCOPED_TRACE(n);
        Scene s = indoor(n);
        ASSERT_EQ(s.lights.size(), n);
        uint32_t spots = 0, points = 0, moving = 0;
        for (const Light& l : s.lights) {
            ASSERT_TRUE(test::finite(l.position));
            EXPECT_GT(l.range, 0.0f);
            if (l.dynamic) {
                ++moving;
                EXPECT_GE(l.attachedInstance, 0);
                continue;
            }
            spots += l.type == LightKind::Spot;
            points += l.type == LightKind::Point;
            // Inside the level, under the ceiling (6 m), above the floor.
            EXPECT_GT(l.position.y, 0.5f);
            EXPECT_LT(l.position.y, 6.0f);
            EXPECT_GE(l.position.x, s.boundsMin.x);
            EXPECT_LE(l.position.x, s.boundsMax.x);
            EXPECT_GE(l.position.z, s.boundsMin.z);
            EXPECT_LE(l.position.z, s.boundsMax.z);
        }
        EXPECT_EQ(points, n >= 10 ? n / 10 : 0);
        EXPECT_EQ(moving, std::min(4u, n - points));
        EXPECT_EQ(spots + points + moving, n);
        EXPECT_EQ(s.cars.size(), moving);
    }
    // The benchmark's level: at least 500 spot and 50 point lights.
    Scene big = indoor(600);
    uint32_t spots = 0, points = 0;
    for (const Light& l : big.lights) (l.type == LightKind::Point ? points : spots) += !l.dynamic;
    EXPECT_GE(spots, 500u);
    EXPECT_GE(points, 50u);
}

// A cart's loop runs through room centres, so every segment crosses walls only at doorways: at the
// wall lines the loop's points lie in the 5 m doorway in the middle of a 12 m room side.
TEST(ScenesIndoor, CartLoopsPassThroughDoorways) {
    Scene s = indoor(600);
    ASSERT_FALSE(s.cars.empty());
    for (const CarPath& c : s.cars) {
        ASSERT_EQ(c.waypoints.size(), 4u);
        EXPECT_TRUE(s.instances[c.instance].dynamic);
        for (size_t i = 0; i < 4; ++i) {
            const glm::vec3 a = c.waypoints[i], b = c.waypoints[(i + 1) % 4];
            EXPECT_TRUE(a.x == b.x || a.z == b.z) << "axis-aligned segments";
            // The fixed coordinate of the segment is a room centre (6 m into a 12 m room).
            const float fixed = a.x == b.x ? a.x : a.z;
            EXPECT_FLOAT_EQ(std::fmod(fixed, 12.0f), 6.0f);
        }
    }
}

TEST(ScenesIndoor, DeterministicForASeedAndRefusesBadOptions) {
    Scene a = indoor(300, 7), b = indoor(300, 7), c = indoor(300, 8);
    ASSERT_EQ(a.instances.size(), b.instances.size());
    for (size_t i = 0; i < a.instances.size(); ++i)
        ASSERT_EQ(a.instances[i].transform, b.instances[i].transform);
    for (size_t i = 0; i < a.lights.size(); ++i) ASSERT_EQ(a.lights[i].position, b.lights[i].position);
    bool differ = a.instances.size() != c.instances.size();
    for (size_t i = 0; !differ && i < a.instances.size(); ++i)
        differ = a.instances[i].transform != c.instances[i].transform;
    EXPECT_TRUE(differ) << "another seed places the furniture elsewhere";
    IndoorOptions o;
    o.lights = 0;
    auto r = makeIndoor(o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("lights"), std::string::npos) << r.error();
    o.lights = 100;
    o.roomsX = 3; // roomsZ left 0
    r = makeIndoor(o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("roomsX"), std::string::npos) << r.error();
    auto named = loadScene("indoor", 50, 1);
    ASSERT_TRUE(named.ok()) << named.error();
    EXPECT_EQ(named->name, "indoor");
}

} // namespace
} // namespace ml
