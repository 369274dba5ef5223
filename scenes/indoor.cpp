// The procedural indoor level ("indoor", scenes.h): a grid of rooms joined by doorways, with ceiling and
// wall spot-light fixtures, point lights in some rooms, crates and pillars, and carts (dynamic casters,
// each with a headlight) driving loops through the doorways. The many-light test level of the virtual
// shadow maps: hundreds of shadowed spot lights and tens of point lights (6 cube faces each) whose pools
// overlap the carts' paths. Deterministic for a seed (Pcg32, scenes/mesh_utils.h).
#include "scenes/mesh_utils.h"
#include "scenes/scenes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace ml {

using detail::Pcg32;

namespace {

constexpr uint32_t kMaxLights = 4096;
constexpr float kRoom = 12.0f;   // room pitch (metres): walls on multiples of it
constexpr float kHeight = 6.0f;  // floor to ceiling
constexpr float kWall = 0.3f;    // wall thickness
constexpr float kDoorW = 5.0f;   // doorway width, centred in every inner wall
constexpr float kDoorH = 5.0f;   // doorway height (the drive camera rides 4.5 m up behind a cart)
constexpr uint32_t kBoxMesh = 0; // the only mesh: the unit box, scaled per instance
// Fixture slots per room: a 3x3 ceiling grid and two on each wall (spots per room before slots repeat).
constexpr uint32_t kSlotsPerRoom = 9 + 8;

class IndoorBuilder {
  public:
    explicit IndoorBuilder(const IndoorOptions& o) : opt_(o) {}

    Scene build() {
        scene_.name = "indoor";
        Mesh box = detail::makeUnitBox();
        box.name = "box";
        box.closed = isClosedMesh(box);
        scene_.meshes.push_back(std::move(box));
        nx_ = opt_.roomsX;
        nz_ = opt_.roomsZ;
        const uint32_t points = opt_.lights >= 10 ? opt_.lights / 10 : 0; // a tenth are point lights
        const uint32_t carts = std::min(opt_.carts, opt_.lights - points);
        const uint32_t spots = opt_.lights - points - carts;
        if (nx_ == 0 || nz_ == 0) { // about 12 spot fixtures per room, a near-square grid
            const uint32_t rooms = std::max(1u, (spots + 11) / 12);
            nx_ = std::max(2u, uint32_t(std::ceil(std::sqrt(float(rooms)))));
            nz_ = std::max(2u, (rooms + nx_ - 1) / nx_);
        }
        addShell();
        addFurniture();
        addFixtures(spots);
        addPointLights(points);
        addCarts(carts);
        updateBounds(scene_);
        Camera& cam = scene_.camera; // in the first room's corner, looking across the level
        cam.position = glm::vec3(1.5f, 4.5f, 1.5f);
        cam.target = glm::vec3(0.5f * kRoom * float(nx_), 1.0f, 0.5f * kRoom * float(nz_));
        cam.fovY = 1.0f;
        cam.nearPlane = 0.1f;
        cam.farPlane = std::max(60.0f, 1.05f * glm::length(scene_.boundsMax - scene_.boundsMin));
        return std::move(scene_);
    }

  private:
    uint32_t addBox(glm::vec3 lo, glm::vec3 hi, glm::vec3 albedo, bool dynamic = false) {
        Instance inst;
        inst.mesh = kBoxMesh;
        glm::vec3 size = hi - lo;
        inst.transform = glm::scale(
            glm::translate(glm::mat4(1.0f), glm::vec3(0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z))),
            size);
        inst.albedo = albedo;
        inst.dynamic = dynamic;
        scene_.instances.push_back(inst);
        return uint32_t(scene_.instances.size() - 1);
    }

    // A wall along x (alongX) or z from a to b at coordinate c; inner walls have a doorway in the middle.
    void addWall(bool alongX, float a, float b, float c, bool door) {
        const glm::vec3 grey(0.55f, 0.53f, 0.5f);
        auto segment = [&](float s0, float s1, float y0, float y1) {
            if (s1 - s0 < 1e-3f) return;
            if (alongX)
                addBox({s0, y0, c - 0.5f * kWall}, {s1, y1, c + 0.5f * kWall}, grey);
            else
                addBox({c - 0.5f * kWall, y0, s0}, {c + 0.5f * kWall, y1, s1}, grey);
        };
        if (!door) return segment(a, b, 0.0f, kHeight);
        const float m = 0.5f * (a + b);
        segment(a, m - 0.5f * kDoorW, 0.0f, kHeight);
        segment(m + 0.5f * kDoorW, b, 0.0f, kHeight);
        segment(m - 0.5f * kDoorW, m + 0.5f * kDoorW, kDoorH, kHeight); // lintel
    }

    void addShell() {
        for (uint32_t z = 0; z < nz_; ++z)
            for (uint32_t x = 0; x < nx_; ++x) {
                const glm::vec3 lo(kRoom * float(x), 0.0f, kRoom * float(z));
                addBox(lo - glm::vec3(0, 0.2f, 0), lo + glm::vec3(kRoom, 0.0f, kRoom), {0.4f, 0.38f, 0.35f});
                addBox(lo + glm::vec3(0, kHeight, 0), lo + glm::vec3(kRoom, kHeight + 0.2f, kRoom),
                       {0.6f, 0.6f, 0.6f});
            }
        for (uint32_t z = 0; z <= nz_; ++z) // walls along x, one segment per room
            for (uint32_t x = 0; x < nx_; ++x)
                addWall(true, kRoom * float(x), kRoom * float(x + 1), kRoom * float(z), z > 0 && z < nz_);
        for (uint32_t x = 0; x <= nx_; ++x)
            for (uint32_t z = 0; z < nz_; ++z)
                addWall(false, kRoom * float(z), kRoom * float(z + 1), kRoom * float(x), x > 0 && x < nx_);
    }

    // Crates and pillars away from the room's middle cross (the carts' lanes through the doorways).
    void addFurniture() {
        Pcg32 rng(opt_.seed, 1);
        for (uint32_t z = 0; z < nz_; ++z)
            for (uint32_t x = 0; x < nx_; ++x) {
                const glm::vec3 lo(kRoom * float(x), 0.0f, kRoom * float(z));
                const uint32_t n = 2 + rng.below(3);
                for (uint32_t k = 0; k < n; ++k) {
                    // One quadrant each, 1..4 m from the walls.
                    const float qx = (k & 1) ? 7.5f : 1.0f, qz = (k & 2) ? 7.5f : 1.0f;
                    const glm::vec3 p =
                        lo + glm::vec3(qx + rng.uniform(0.0f, 2.5f), 0.0f, qz + rng.uniform(0.0f, 2.5f));
                    const bool pillar = rng.chance(0.3f);
                    const glm::vec3 size = pillar
                                               ? glm::vec3(0.6f, kHeight, 0.6f)
                                               : glm::vec3(rng.uniform(0.8f, 2.0f), rng.uniform(0.6f, 2.2f),
                                                           rng.uniform(0.8f, 2.0f));
                    addBox(p, p + size, pillar ? glm::vec3(0.5f) : glm::vec3(0.45f, 0.32f, 0.2f));
                }
            }
    }

    static Light spot(glm::vec3 position, glm::vec3 direction, glm::vec3 color, float range, float outer) {
        Light l;
        l.type = LightKind::Spot;
        l.position = position;
        l.direction = glm::normalize(direction);
        l.color = color;
        l.intensity = 6.0f;
        l.range = range;
        l.outerAngle = outer;
        l.innerAngle = 0.7f * outer;
        return l;
    }

    // Spot fixtures, room by room: slot s of a room is a ceiling fixture (3x3 grid, aimed down) or a wall
    // fixture (two per wall, 4 m up, aimed into the room and down). Past kSlotsPerRoom slots per room
    // they repeat with a small offset.
    void addFixtures(uint32_t count) {
        Pcg32 rng(opt_.seed, 2);
        const uint32_t rooms = nx_ * nz_;
        for (uint32_t i = 0; i < count; ++i) {
            const uint32_t room = i % rooms, slot = (i / rooms) % kSlotsPerRoom,
                           round = i / (rooms * kSlotsPerRoom);
            const glm::vec3 lo(kRoom * float(room % nx_), 0.0f, kRoom * float(room / nx_));
            const glm::vec3 jitter(0.3f * float(round), 0.0f, 0.2f * float(round));
            const glm::vec3 warm(1.0f, 0.85f, 0.65f), cool(0.75f, 0.85f, 1.0f);
            const glm::vec3 color = rng.chance(0.5f) ? warm : cool;
            if (slot < 9) {
                const glm::vec3 p =
                    lo +
                    glm::vec3(2.0f + 4.0f * float(slot % 3), kHeight - 0.05f, 2.0f + 4.0f * float(slot / 3)) +
                    jitter;
                scene_.lights.push_back(
                    spot(p, {rng.uniform(-0.2f, 0.2f), -1.0f, rng.uniform(-0.2f, 0.2f)}, color, 9.0f, 0.7f));
            } else {
                const uint32_t w = (slot - 9) / 2, side = (slot - 9) % 2;
                const float along = side ? 9.0f : 3.0f;
                const glm::vec3 inward[4] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}};
                const glm::vec3 at[4] = {{along, 4.0f, 0.3f},
                                         {along, 4.0f, kRoom - 0.3f},
                                         {0.3f, 4.0f, along},
                                         {kRoom - 0.3f, 4.0f, along}};
                scene_.lights.push_back(
                    spot(lo + at[w] + jitter, inward[w] - glm::vec3(0, 0.8f, 0), color, 10.0f, 0.6f));
            }
        }
    }

    // Point lights (lamps hanging 2 m under the ceiling) in every k-th room, off-centre.
    void addPointLights(uint32_t count) {
        Pcg32 rng(opt_.seed, 3);
        const uint32_t rooms = nx_ * nz_;
        for (uint32_t i = 0; i < count; ++i) {
            const uint32_t room = (i * 7 + 3) % rooms, round = (i * 7 + 3) / rooms;
            const glm::vec3 lo(kRoom * float(room % nx_), 0.0f, kRoom * float(room / nx_));
            Light l;
            l.type = LightKind::Point;
            l.position = lo + glm::vec3(4.0f + 1.3f * float(round % 4), kHeight - 2.0f,
                                        5.0f + 0.9f * float(round % 3));
            l.color = glm::vec3(1.0f, 0.7f + 0.2f * rng.uniform(), 0.5f);
            l.intensity = 4.0f;
            l.range = 8.0f;
            scene_.lights.push_back(l);
        }
    }

    // Carts: dynamic boxes on rectangular loops through the rooms' centres (so through the doorways),
    // the outermost ring first, each with a headlight.
    void addCarts(uint32_t count) {
        Pcg32 rng(opt_.seed, 4);
        const uint32_t rings = std::max(1u, std::min(nx_, nz_) / 2);
        for (uint32_t k = 0; k < count; ++k) {
            const uint32_t ring = k % rings;
            const float x0 = kRoom * (float(ring) + 0.5f), z0 = kRoom * (float(ring) + 0.5f);
            const float x1 = kRoom * (float(nx_ - ring) - 0.5f), z1 = kRoom * (float(nz_ - ring) - 0.5f);
            CarPath cart;
            cart.instance = addBox({-0.6f, 0.0f, -0.9f}, {0.6f, 1.0f, 0.9f}, {0.7f, 0.2f, 0.1f}, true);
            cart.waypoints = {{x0, 0.0f, z0}, {x1, 0.0f, z0}, {x1, 0.0f, z1}, {x0, 0.0f, z1}};
            cart.speed = rng.uniform(2.0f, 4.0f);
            const float length = 2.0f * ((x1 - x0) + (z1 - z0));
            cart.phase = length * float(k / rings) / float((count + rings - 1) / rings);
            scene_.cars.push_back(std::move(cart));
            Light l = spot({}, {0, -1, 0}, {1.0f, 0.95f, 0.85f}, 12.0f, 0.5f);
            l.dynamic = true;
            l.attachedInstance = int32_t(scene_.cars.back().instance);
            l.localPosition = glm::vec3(0.0f, 0.9f, -0.95f); // car object space: front towards -Z
            l.localDirection = glm::normalize(glm::vec3(0.0f, -0.15f, -1.0f));
            scene_.lights.push_back(l);
        }
    }

    IndoorOptions opt_;
    Scene scene_;
    uint32_t nx_ = 0, nz_ = 0;
};

} // namespace

Result<Scene> makeIndoor(const IndoorOptions& options) {
    if (options.lights == 0 || options.lights > kMaxLights)
        return fail("indoor: lights must be in 1.." + std::to_string(kMaxLights) + ", got " +
                    std::to_string(options.lights));
    if (options.roomsX > 64 || options.roomsZ > 64 || (options.roomsX == 0) != (options.roomsZ == 0))
        return fail("indoor: roomsX and roomsZ must both be 0 (from the light count) or in 1..64, got " +
                    std::to_string(options.roomsX) + " x " + std::to_string(options.roomsZ));
    return IndoorBuilder(options).build();
}

} // namespace ml
