#include "engine/camera.h"

#include "lights/lights.h"
#include "shadows/static/static_visibility.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <string>

namespace ml {

namespace {
bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}
bool finite3(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
} // namespace

Result<void> validateCamera(const CameraDesc& c) {
    auto bounded = [](glm::vec3 v) {
        return finite3(v) && std::abs(v.x) <= kMaxCameraCoordinate && std::abs(v.y) <= kMaxCameraCoordinate &&
               std::abs(v.z) <= kMaxCameraCoordinate;
    };
    const std::string range =
        " is not finite or beyond +-" + std::to_string(int(kMaxCameraCoordinate)) + " m";
    const glm::vec3 position = toGlm(c.position), target = toGlm(c.target), up = toGlm(c.up);
    if (!bounded(position)) return fail("camera: position" + range);
    if (!bounded(target)) return fail("camera: target" + range);
    if (!finite3(up) || !(glm::length(up) > 1e-6f)) return fail("camera: up is zero or not finite");
    const glm::vec3 view = target - position;
    if (!(glm::length(view) > 1e-6f)) return fail("camera: target equals position");
    // sin of the angle between view and up; below ~0.006 degrees the view basis is degenerate.
    const float sine = glm::length(glm::cross(glm::normalize(view), glm::normalize(up)));
    if (!(sine > 1e-4f)) return fail("camera: view direction is parallel to up");
    if (!(c.fovY > 0.0f && c.fovY < 3.14159f)) return fail("camera: fovY must be in (0, pi)");
    if (!(c.nearPlane > 0.0f) || !(c.farPlane > c.nearPlane) || !std::isfinite(c.farPlane))
        return fail("camera: need 0 < near < far < infinity");
    return {};
}

CameraMatrices cameraMatrices(const CameraDesc& c, float aspect) {
    CameraMatrices m;
    m.view = glm::lookAt(toGlm(c.position), toGlm(c.target), toGlm(c.up));
    // Near and far swapped: depth 1 at the near plane, 0 at the far plane (reversed Z).
    m.projection = glm::perspectiveRH_ZO(c.fovY, aspect, c.farPlane, c.nearPlane);
    m.projection[1][1] *= -1.0f; // Vulkan clip space has +y down
    return m;
}

Result<CameraDesc> cameraFromMatrices(const glm::mat4& view, const glm::mat4& p) {
    if (!finite(view)) return fail("camera: view matrix is not finite");
    if (!finite(p)) return fail("camera: projection matrix is not finite");
    // Rigid: orthonormal rotation with determinant +1, last row (0, 0, 0, 1), to a host's rounding
    // (the static bakes' check, with a looser tolerance).
    if (!rigidView(view, 1e-3f))
        return fail("camera: view matrix is not a rigid transform (rotation and translation only)");
    // A perspective into Vulkan clip space: w = -z_view (right-handed), x and y scaled (off-centre terms
    // [2][0], [2][1] allowed), depth = (A z + B) / -z.
    if (p[2][3] != -1.0f || p[3][3] != 0.0f || p[0][3] != 0.0f || p[1][3] != 0.0f)
        return fail("camera: projection is not a right-handed perspective (w must equal -z_view)");
    if (p[0][1] != 0.0f || p[0][2] != 0.0f || p[1][0] != 0.0f || p[1][2] != 0.0f || p[3][0] != 0.0f ||
        p[3][1] != 0.0f)
        return fail("camera: projection has rotation or shear terms");
    if (!(p[0][0] > 0.0f)) return fail("camera: projection x scale must be > 0");
    // Every convention problem in one line: an infinite reversed-Z projection with y up breaks two
    // conventions, and the message names both.
    const float a = p[2][2], b = p[3][2];
    std::string problems;
    auto add = [&](const char* why) { problems += (problems.empty() ? "" : "; ") + std::string(why); };
    if (!(p[1][1] < 0.0f)) add("y must point down (Vulkan clip space): negate glm's [1][1]");
    if (a < 0.0f || b < 0.0f)
        add("it is standard Z (near -> 0); the module needs reversed Z (near -> 1, far -> 0), e.g. "
            "glm::perspectiveRH_ZO(fovY, aspect, far, near)");
    else if (a == 0.0f)
        add("it has an infinite far plane; the cluster grid needs a finite one");
    if (!problems.empty()) return fail("camera: projection: " + problems);
    // Reversed Z: A = n / (f - n), B = n f / (f - n), so f = B / A and n = B / (1 + A).
    CameraDesc c;
    c.farPlane = b / a;
    c.nearPlane = b / (1.0f + a);
    c.fovY = 2.0f * std::atan(1.0f / -p[1][1]);
    const glm::mat4 inv = glm::inverse(view);
    c.position = glm::vec3(inv[3]);
    c.target = glm::vec3(inv[3]) - glm::vec3(inv[2]); // the camera looks down view-space -Z
    c.up = glm::vec3(inv[1]);
    if (auto v = validateCamera(c); !v) return fail("camera (from matrices): " + v.error().substr(8));
    return c;
}

Result<void> validateJitter(glm::vec2 j) {
    if (!std::isfinite(j.x) || !std::isfinite(j.y)) return fail("camera: jitter is not finite");
    if (std::abs(j.x) > 1.0f || std::abs(j.y) > 1.0f) return fail("camera: jitter beyond one pixel");
    return {};
}

glm::mat4 jittered(const glm::mat4& projection, glm::vec2 j, uint32_t width, uint32_t height) {
    // ndc.x = ... - P[2][0] for a perspective with w = -z: lowering P[2][0] by 2 j / W moves every point
    // right by j pixels (and y, which points down in Vulkan clip space, down by j pixels).
    glm::mat4 p = projection;
    p[2][0] -= 2.0f * j.x / float(width);
    p[2][1] -= 2.0f * j.y / float(height);
    return p;
}

} // namespace ml
