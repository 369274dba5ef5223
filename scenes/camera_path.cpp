#include "scenes/camera_path.h"

#include <cmath>

namespace ml {

Result<CameraPath> parseCameraPath(const std::string& name) {
    if (name == "static") return CameraPath::Static;
    if (name == "drive") return CameraPath::Drive;
    if (name == "orbit") return CameraPath::Orbit;
    return fail("unknown camera path '" + name + "' (static, drive or orbit)");
}

const char* cameraPathName(CameraPath path) {
    switch (path) {
    case CameraPath::Static:
        return "static";
    case CameraPath::Drive:
        return "drive";
    case CameraPath::Orbit:
        return "orbit";
    }
    return "?";
}

Result<Camera> cameraOnPath(const Scene& scene, CameraPath path, double seconds) {
    Camera cam = scene.camera;
    if (path == CameraPath::Static) return cam;
    if (path == CameraPath::Drive) {
        // The car whose loop passes closest to the scene camera's target (the night city's lit high
        // street), ties to the first: a choice that does not change while the cars move.
        size_t pick = scene.cars.size();
        float best = 1e30f;
        for (size_t c = 0; c < scene.cars.size(); ++c) {
            if (scene.cars[c].instance >= scene.instances.size()) continue;
            for (const glm::vec3& w : scene.cars[c].waypoints) {
                const float d = glm::length(glm::vec2(w.x - cam.target.x, w.z - cam.target.z));
                if (d < best) best = d, pick = c;
            }
        }
        if (pick == scene.cars.size())
            return fail(scene.name + ": the drive path follows a car and this scene has none");
        // Car object space: front towards -Z, +Y up (scenes/animate.cpp).
        const glm::mat4& m = scene.instances[scene.cars[pick].instance].transform;
        glm::vec3 position(m[3]);
        glm::vec3 forward = -glm::normalize(glm::vec3(m[2]));
        cam.position = position - forward * 9.0f + glm::vec3(0.0f, 4.5f, 0.0f);
        cam.target = position + forward * 14.0f + glm::vec3(0.0f, 0.5f, 0.0f);
        return cam;
    }
    // Orbit: radius and height from the scene's bounds, one turn per 60 s.
    glm::vec3 centre = 0.5f * (scene.boundsMin + scene.boundsMax);
    glm::vec3 extent = scene.boundsMax - scene.boundsMin;
    float radius = 0.45f * std::max(extent.x, extent.z);
    if (!(radius > 1.0f)) radius = 10.0f;
    double angle = seconds * (2.0 * 3.14159265358979 / 60.0);
    cam.position = centre + glm::vec3(float(std::cos(angle)) * radius, 0.35f * radius + 2.0f,
                                      float(std::sin(angle)) * radius);
    cam.target = centre;
    return cam;
}

} // namespace ml
