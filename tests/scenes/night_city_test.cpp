// The procedural night city: geometry (closed buildings, open sheets, proper transforms), exact light
// counts and valid light parameters, determinism, and the cars with their headlights.
#include "scene_test_util.h"

#include "scenes/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ml {
namespace {

Scene city(uint32_t lights, uint32_t seed = 1) {
    NightCityOptions o;
    o.lights = lights;
    o.seed = seed;
    auto r = makeNightCity(o);
    EXPECT_TRUE(r.ok()) << r.error();
    return r.ok() ? std::move(r.value()) : Scene{};
}

bool startsWith(const std::string& s, const char* prefix) {
    return s.rfind(prefix, 0) == 0;
}

TEST(ScenesNightCity, BuildingMeshesAreClosedAndSheetsAreOpen) {
    Scene s = city(256);
    ASSERT_FALSE(s.meshes.empty());
    int buildings = 0, sheets = 0;
    for (const Mesh& m : s.meshes) {
        SCOPED_TRACE(m.name);
        EXPECT_EQ(m.closed, isClosedMesh(m)) << "the flag must match the test";
        if (startsWith(m.name, "building") || m.name == "unit-box" || m.name == "car") {
            EXPECT_TRUE(isClosedMesh(m));
            ++buildings;
        } else {
            EXPECT_FALSE(isClosedMesh(m)) << "awnings, fences and foliage are open sheets";
            ++sheets;
        }
        for (const Vertex& v : m.vertices) {
            ASSERT_TRUE(test::finite(v.position));
            ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
        }
        for (uint32_t i : m.indices) ASSERT_LT(i, m.vertices.size());
    }
    EXPECT_GE(buildings, 5);
    EXPECT_GE(sheets, 3);
    // Every kind of geometry is actually used, and some buildings are not plain boxes.
    std::vector<int> uses(s.meshes.size(), 0);
    for (const Instance& i : s.instances) ++uses[i.mesh];
    for (size_t m = 0; m < s.meshes.size(); ++m) EXPECT_GT(uses[m], 0) << s.meshes[m].name << " unused";
}

// Outward orientation: for a closed mesh, the signed volume (sum over triangles of a . (b x c) / 6) is
// positive exactly when the triangles wind counter-clockwise seen from outside. Flat normals agree.
TEST(ScenesNightCity, ClosedMeshesWindOutward) {
    Scene s = city(16);
    for (const Mesh& m : s.meshes) {
        if (!m.closed) continue;
        SCOPED_TRACE(m.name);
        double volume = 0.0;
        for (size_t t = 0; t < m.indices.size(); t += 3) {
            glm::dvec3 a = m.vertices[m.indices[t]].position, b = m.vertices[m.indices[t + 1]].position,
                       c = m.vertices[m.indices[t + 2]].position;
            volume += glm::dot(a, glm::cross(b, c)) / 6.0;
            glm::dvec3 n = glm::cross(b - a, c - a);
            EXPECT_GT(glm::dot(n, glm::dvec3(m.vertices[m.indices[t]].normal)), 0.0);
        }
        EXPECT_GT(volume, 0.0);
    }
}

// Transforms keep winding (positive determinant) and are far from singular, buildings stand on the
// sidewalk with heights in 6..45 m, albedos are plausible.
TEST(ScenesNightCity, InstancesArePlausible) {
    Scene s = city(256);
    int tall = 0, buildings = 0;
    for (const Instance& inst : s.instances) {
        float det = glm::determinant(glm::mat3(inst.transform));
        EXPECT_GT(det, 1e-4f);
        EXPECT_GE(inst.albedo.x, 0.0f);
        EXPECT_LE(std::max({inst.albedo.x, inst.albedo.y, inst.albedo.z}), 1.0f);
        EXPECT_GT(std::max({inst.albedo.x, inst.albedo.y, inst.albedo.z}), 0.02f);
        const std::string& name = s.meshes[inst.mesh].name;
        if (startsWith(name, "building")) {
            float h = glm::length(glm::vec3(inst.transform[1]));
            EXPECT_GE(h, 6.0f);
            EXPECT_LE(h, 45.0f);
            ++buildings;
            tall += h > 25.0f;
        }
    }
    EXPECT_GT(buildings, 0);
    // Bounds: 6 blocks of 40 m and 7 streets of 12 m = 324 m on each side, up to 45 m high.
    EXPECT_NEAR(s.boundsMax.x - s.boundsMin.x, 324.0f, 0.01f);
    EXPECT_NEAR(s.boundsMax.z - s.boundsMin.z, 324.0f, 0.01f);
    EXPECT_GT(s.boundsMax.y, 20.0f);
    EXPECT_LE(s.boundsMax.y, 45.2f);
}

TEST(ScenesNightCity, LightCountIsExact) {
    for (uint32_t n : {1u, 2u, 3u, 5u, 17u, 256u, 1000u, 4096u}) {
        SCOPED_TRACE(n);
        Scene s = city(n);
        EXPECT_EQ(s.lights.size(), n);
        test::expectValidLights(s);
        size_t headlights = std::count_if(s.lights.begin(), s.lights.end(),
                                          [](const Light& l) { return l.attachedInstance >= 0; });
        EXPECT_EQ(headlights, 2 * s.cars.size());
        EXPECT_EQ(s.cars.size(), std::min<size_t>(8, n / 2));
    }
}

TEST(ScenesNightCity, RejectsBadLightCounts) {
    for (uint32_t n : {0u, 4097u, 100000u}) {
        NightCityOptions o;
        o.lights = n;
        auto r = makeNightCity(o);
        ASSERT_FALSE(r.ok()) << n;
        EXPECT_NE(r.error().find("lights"), std::string::npos) << r.error();
        EXPECT_NE(r.error().find(std::to_string(n)), std::string::npos) << r.error();
    }
    NightCityOptions o;
    o.blocksX = 0;
    EXPECT_FALSE(makeNightCity(o).ok());
}

// More lights fill the same city: same buildings, same size; the per-kind mix of night_city.cpp.
TEST(ScenesNightCity, MoreLightsSameCity) {
    Scene small = city(64), large = city(4096);
    EXPECT_EQ(small.boundsMin, large.boundsMin);
    EXPECT_EQ(small.boundsMax, large.boundsMax);
    auto buildings = [](const Scene& s) {
        std::vector<glm::mat4> out;
        for (const Instance& i : s.instances)
            if (startsWith(s.meshes[i.mesh].name, "building")) out.push_back(i.transform);
        return out;
    };
    EXPECT_EQ(buildings(small), buildings(large));
    size_t down = std::count_if(large.lights.begin(), large.lights.end(), [](const Light& l) {
        return l.type == LightKind::Spot && l.direction.y < -0.9f && l.attachedInstance < 0;
    });
    size_t up = std::count_if(large.lights.begin(), large.lights.end(), [](const Light& l) {
        return l.type == LightKind::Spot && l.direction.y > 0.8f;
    });
    size_t moon = std::count_if(large.lights.begin(), large.lights.end(),
                                [](const Light& l) { return l.type == LightKind::Directional; });
    // 4079 static spots: 45 % lamps (down), 20 % floods (up), shop windows and signs the rest; one moon.
    EXPECT_NEAR(double(down) / 4079.0, 0.45, 0.02);
    EXPECT_NEAR(double(up) / 4079.0, 0.20, 0.02);
    EXPECT_EQ(moon, 1u);
    const Light& m = *std::find_if(large.lights.begin(), large.lights.end(),
                                   [](const Light& l) { return l.type == LightKind::Directional; });
    EXPECT_LT(m.direction.y, -0.5f) << "from above";
    EXPECT_LT(m.intensity * std::max({m.color.x, m.color.y, m.color.z}), 0.5f) << "dim";
}

// Most of the lights at the default count stand on the high street in front of the default camera:
// within 30 m of the camera's street line and 110 m of its west end.
TEST(ScenesNightCity, DefaultViewHoldsMostLights) {
    Scene s = city(256);
    const Camera& c = s.camera;
    size_t near = 0, spots = 0;
    for (const Light& l : s.lights) {
        if (l.type != LightKind::Spot || l.dynamic) continue;
        ++spots;
        near += std::abs(l.position.z - c.position.z) < 30.0f && l.position.x - c.position.x < 110.0f;
    }
    EXPECT_GT(double(near) / double(spots), 0.9);
}

TEST(ScenesNightCity, SameSeedSameBytesOtherSeedDiffers) {
    std::string a = test::sceneBytes(city(512, 7)), b = test::sceneBytes(city(512, 7));
    std::string c = test::sceneBytes(city(512, 8));
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
}

// Lamps: ~6 m high, aimed down, outer half-angle 0.6-0.8, range 12-16 m; pools land on the ground.
TEST(ScenesNightCity, LampsLightTheStreet) {
    Scene s = city(256);
    int lamps = 0;
    for (const Light& l : s.lights) {
        if (l.type != LightKind::Spot || l.attachedInstance >= 0 || l.direction.y > -0.9f) continue;
        ++lamps;
        EXPECT_NEAR(l.position.y, 6.0f, 0.5f);
        EXPECT_GE(l.outerAngle, 0.6f);
        EXPECT_LE(l.outerAngle, 0.8f);
        EXPECT_GE(l.range, 12.0f);
        EXPECT_LE(l.range, 16.0f);
        EXPECT_GT(l.color.x, l.color.z) << "warm sodium or white";
    }
    EXPECT_GT(lamps, 100);
}

TEST(ScenesNightCity, CameraLooksDownAStreet) {
    Scene s = city(256);
    const Camera& c = s.camera;
    EXPECT_GE(c.position.y, 12.0f);
    EXPECT_LE(c.position.y, 20.0f);
    glm::vec3 view = glm::normalize(c.target - c.position);
    float pitch = std::asin(-view.y);
    EXPECT_GT(pitch, 0.03f);
    EXPECT_LT(pitch, 0.5f);
    EXPECT_NEAR(c.fovY, 1.0f, 0.2f);
    EXPECT_NEAR(c.nearPlane, 0.1f, 1e-6f);
    EXPECT_GE(c.farPlane, glm::length(s.boundsMax - s.boundsMin));
}

// Distance from p to the closed polyline `loop` (xz plane).
float distanceToLoop(glm::vec3 p, const std::vector<glm::vec3>& loop) {
    float best = 1e30f;
    for (size_t i = 0; i < loop.size(); ++i) {
        glm::vec3 a = loop[i], b = loop[(i + 1) % loop.size()];
        glm::vec3 ab = b - a;
        float t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0f, 1.0f);
        best = std::min(best, glm::length(a + ab * t - p));
    }
    return best;
}

TEST(ScenesNightCity, CarsDriveTheirLoopsAndHeadlightsFollow) {
    Scene s = city(256);
    ASSERT_EQ(s.cars.size(), 8u);
    std::vector<glm::vec3> before;
    for (const CarPath& c : s.cars) before.push_back(glm::vec3(s.instances[c.instance].transform[3]));
    const double t = 1.5;
    animateScene(s, t);
    for (size_t k = 0; k < s.cars.size(); ++k) {
        const CarPath& car = s.cars[k];
        const Instance& inst = s.instances[car.instance];
        EXPECT_TRUE(inst.dynamic);
        glm::vec3 p(inst.transform[3]);
        float moved = glm::length(p - before[k]);
        // Along the loop it drove speed * t; the chord is shorter only around a corner.
        EXPECT_LE(moved, car.speed * float(t) + 1e-3f);
        EXPECT_GT(moved, 0.6f * car.speed * float(t));
        EXPECT_LT(distanceToLoop(p, car.waypoints), 1e-3f);
        // On a street: the loop runs 3 m outside a block, so the car centre is never inside a block.
        EXPECT_NEAR(p.y, 0.0f, 1e-5f);
        // Rigid transform (headlight offsets stay metric).
        EXPECT_NEAR(glm::determinant(glm::mat3(inst.transform)), 1.0f, 1e-4f);
        // One full lap later the car is back.
        Scene lap = s;
        float length = 0.0f;
        for (size_t i = 0; i < car.waypoints.size(); ++i)
            length += glm::length(car.waypoints[(i + 1) % car.waypoints.size()] - car.waypoints[i]);
        animateScene(lap, t + double(length / car.speed));
        EXPECT_LT(glm::length(glm::vec3(lap.instances[car.instance].transform[3]) - p), 0.01f);
    }
    int headlights = 0;
    for (const Light& l : s.lights) {
        if (l.attachedInstance < 0) continue;
        ++headlights;
        EXPECT_TRUE(l.dynamic);
        const glm::mat4& m = s.instances[size_t(l.attachedInstance)].transform;
        EXPECT_LT(glm::length(l.position - glm::vec3(m * glm::vec4(l.localPosition, 1.0f))), 1e-4f);
        glm::vec3 forward = -glm::normalize(glm::vec3(m[2]));
        EXPECT_GT(glm::dot(l.direction, forward), 0.95f) << "headlights point forward";
        EXPECT_LT(l.direction.y, 0.0f) << "and slightly down";
        EXPECT_NEAR(l.range, 20.0f, 5.0f);
        // In front of the car.
        EXPECT_GT(glm::dot(l.position - glm::vec3(m[3]), forward), 2.0f);
    }
    EXPECT_EQ(headlights, 16);
}

TEST(ScenesNightCity, CarsStayOnStreets) {
    Scene s = city(256, 3);
    // Block rectangles are the sidewalk slabs: unit boxes 40 m wide and 0.15 m high.
    std::vector<std::pair<glm::vec2, glm::vec2>> blocks;
    for (const Instance& i : s.instances) {
        glm::vec3 size(glm::length(glm::vec3(i.transform[0])), glm::length(glm::vec3(i.transform[1])),
                       glm::length(glm::vec3(i.transform[2])));
        if (s.meshes[i.mesh].name == "unit-box" && std::abs(size.x - 40.0f) < 1e-3f &&
            std::abs(size.y - 0.15f) < 1e-3f) {
            glm::vec2 c(i.transform[3].x, i.transform[3].z);
            blocks.push_back({c - 20.0f, c + 20.0f});
        }
    }
    ASSERT_EQ(blocks.size(), 36u);
    for (double t : {0.0, 2.0, 7.5, 33.0}) {
        animateScene(s, t);
        for (const CarPath& car : s.cars) {
            glm::vec3 p(s.instances[car.instance].transform[3]);
            for (const auto& [lo, hi] : blocks)
                EXPECT_FALSE(p.x > lo.x + 0.5f && p.x < hi.x - 0.5f && p.z > lo.y + 0.5f && p.z < hi.y - 0.5f)
                    << "car inside a block at t=" << t;
        }
    }
}

// The large city (loadScene "night-city-large"): the seeds' scale (their CLOSED CITY: 613K triangles),
// the same lights, a larger box, its own name (bake files record it).
TEST(ScenesNightCity, LargeCityHasTheSeedsScale) {
    auto triangles = [](const Scene& s) {
        uint64_t n = 0;
        for (const Instance& i : s.instances) n += s.meshes[i.mesh].indices.size() / 3;
        return n;
    };
    auto small = loadScene("night-city", 256, 1);
    auto large = loadScene("night-city-large", 256, 1);
    ASSERT_TRUE(small.ok() && large.ok());
    EXPECT_EQ(large->name, "night-city-large");
    EXPECT_EQ(large->lights.size(), 256u);
    EXPECT_GE(triangles(*large), 500000u) << "the default city has " << triangles(*small);
    EXPECT_GT(large->boundsMax.x - large->boundsMin.x, 3.0f * (small->boundsMax.x - small->boundsMin.x));
    std::printf("night-city: %llu triangles, night-city-large: %llu\n", (unsigned long long)triangles(*small),
                (unsigned long long)triangles(*large));
}

// The closed variant is the same city with its open sheets (awnings, fences, foliage) turned into thin
// closed boxes: every static mesh an instance uses passes the watertightness test, the layout and the
// lights are the open city's, and only the three sheet meshes changed.
TEST(ScenesNightCity, ClosedVariantHasOnlyClosedCasters) {
    auto open = loadScene("night-city", 256, 1);
    auto closed = loadScene("night-city-closed", 256, 1);
    ASSERT_TRUE(open.ok() && closed.ok());
    EXPECT_EQ(closed->name, "night-city-closed");
    ASSERT_EQ(open->instances.size(), closed->instances.size());
    ASSERT_EQ(open->lights.size(), closed->lights.size());
    ASSERT_EQ(open->meshes.size(), closed->meshes.size());
    size_t openUsed = 0, changed = 0;
    std::vector<bool> used(closed->meshes.size(), false);
    for (size_t i = 0; i < closed->instances.size(); ++i) {
        EXPECT_EQ(open->instances[i].mesh, closed->instances[i].mesh) << "instance " << i;
        EXPECT_EQ(open->instances[i].transform, closed->instances[i].transform) << "instance " << i;
        if (!closed->instances[i].dynamic) used[closed->instances[i].mesh] = true;
    }
    for (size_t m = 0; m < closed->meshes.size(); ++m) {
        if (!used[m]) continue;
        const Mesh& c = closed->meshes[m];
        EXPECT_TRUE(c.closed && isClosedMesh(c)) << c.name;
        if (!open->meshes[m].closed) ++openUsed;
        if (open->meshes[m].indices != c.indices || open->meshes[m].name != c.name) ++changed;
    }
    EXPECT_EQ(openUsed, 3u) << "awning, fence and foliage are the open city's open casters";
    EXPECT_EQ(changed, 3u);
    for (size_t l = 0; l < closed->lights.size(); ++l)
        EXPECT_EQ(open->lights[l].position, closed->lights[l].position) << "light " << l;
    auto large = loadScene("night-city-large-closed", 16, 1);
    ASSERT_TRUE(large.ok());
    EXPECT_EQ(large->name, "night-city-large-closed");
    EXPECT_GT(large->instances.size(), 10 * closed->instances.size());
}

} // namespace
} // namespace ml
