// Scene animation: cars drive along their closed waypoint loops and attached lights follow their
// instances.
//
// Conventions: a car's object space has its front towards local -Z and +Y up (the night city builds
// its car mesh that way). At time t the car sits at arc length s = phase + speed * t (modulo the loop
// length) and its local -Z is the tangent of the segment it is on, so transforms stay rigid (rotation
// + translation, no scale) and attached lights keep their distances.
#include "scenes/scenes.h"

#include <cmath>

namespace ml {
namespace {

// Rigid transform that puts the origin at `position` with local -Z along `forward` (horizontal) and +Y up.
glm::mat4 carTransform(glm::vec3 position, glm::vec3 forward) {
    glm::vec3 z = -forward;
    glm::vec3 y(0.0f, 1.0f, 0.0f);
    glm::vec3 x = glm::cross(y, z);
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(x, 0.0f);
    m[1] = glm::vec4(y, 0.0f);
    m[2] = glm::vec4(z, 0.0f);
    m[3] = glm::vec4(position, 1.0f);
    return m;
}

void placeCar(Scene& scene, const CarPath& car, double seconds) {
    if (car.instance >= scene.instances.size() || car.waypoints.size() < 2) return;
    const auto& w = car.waypoints;
    size_t n = w.size();
    // Segment lengths in double: the modulo of a long drive must not lose the position to rounding.
    double total = 0.0;
    for (size_t i = 0; i < n; ++i) total += double(glm::length(w[(i + 1) % n] - w[i]));
    if (!(total > 0.0)) return;
    double s = std::fmod(double(car.phase) + double(car.speed) * seconds, total);
    if (s < 0.0) s += total;
    for (size_t i = 0; i < n; ++i) {
        glm::vec3 a = w[i], b = w[(i + 1) % n];
        double len = double(glm::length(b - a));
        if (len <= 0.0) continue;
        if (s <= len || i + 1 == n) {
            float f = float(std::min(s / len, 1.0));
            glm::vec3 dir = (b - a) / float(len);
            glm::vec3 flat(dir.x, 0.0f, dir.z);
            // A vertical segment has no heading: keep the previous orientation.
            if (glm::length(flat) < 1e-6f) return;
            scene.instances[car.instance].transform = carTransform(a + (b - a) * f, glm::normalize(flat));
            return;
        }
        s -= len;
    }
}

} // namespace

void animateScene(Scene& scene, double seconds) {
    for (const CarPath& car : scene.cars) placeCar(scene, car, seconds);
    for (Light& light : scene.lights) {
        if (light.attachedInstance < 0 || size_t(light.attachedInstance) >= scene.instances.size()) continue;
        const glm::mat4& m = scene.instances[size_t(light.attachedInstance)].transform;
        light.position = glm::vec3(m * glm::vec4(light.localPosition, 1.0f));
        glm::vec3 d = glm::vec3(m * glm::vec4(light.localDirection, 0.0f));
        float len = glm::length(d);
        if (len > 0.0f) light.direction = d / len;
    }
    updateBounds(scene);
}

} // namespace ml
