// Exact shadow truth for tests: does the segment from p to the light pass through the box [lo, hi]?
// (Slab test; the first 1e-4 of the segment is ignored so a receiver on the box's surface is not its
// own occluder.) Shared by static_tests and gpu_tests.
#pragma once
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace ml::test {

inline bool blockedByBox(glm::vec3 p, glm::vec3 light, glm::vec3 lo, glm::vec3 hi) {
    glm::vec3 d = light - p;
    float t0 = 1e-4f, t1 = 1.0f;
    for (int i = 0; i < 3; ++i) {
        if (std::abs(d[i]) < 1e-12f) {
            if (p[i] < lo[i] || p[i] > hi[i]) return false;
            continue;
        }
        float a = (lo[i] - p[i]) / d[i], b = (hi[i] - p[i]) / d[i];
        t0 = std::max(t0, std::min(a, b));
        t1 = std::min(t1, std::max(a, b));
    }
    return t0 < t1;
}

} // namespace ml::test
