// Scene description shared by the demo (a host of the module API), the tests and the bake tools.
// A scene is plain data: meshes (triangle lists in object space), instances (mesh + transform, static or
// dynamic), lights, and a camera. Nothing here touches Vulkan; the host hands it to the module through
// manylights/module.h.
//
// Units: metres, right-handed, +Y up. Angles in radians.
#pragma once
#include "manylights/result.h"
#include "shadows/static/static_types.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace ml {

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
};

struct Mesh {
    std::string name;
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices; // triangle list, counter-clockwise front faces
    // True when every edge is shared by exactly two triangles with opposite winding (watertight and
    // consistently oriented). Shadow baking uses the open-geometry rules (exit = enter) when false.
    bool closed = false;
};

struct Instance {
    uint32_t mesh = 0;
    glm::mat4 transform{1.0f}; // object -> world
    glm::vec3 albedo{0.5f};
    float roughness = 0.5f, metalness = 0.0f; // glTF metallicRoughness factors (Module::setInstanceMaterial)
    bool dynamic = false;                     // moves every frame; never a static shadow caster
};

// A scene light: its shape (LightShape, shadows/static/static_types.h: kind, position, direction, range,
// outer angle; what its shadow frustums depend on) plus how it shines and moves.
struct Light : LightShape {
    glm::vec3 color{1.0f};   // linear RGB
    float intensity = 1.0f;  // scale on color (candela-like)
    float innerAngle = 0.4f; // half angle where the smooth edge begins (spot)
    bool dynamic = false;    // moves (e.g. a car's headlight)
    // For a light carried by a dynamic instance: the instance index and the light's pose in that
    // instance's object space (position w=1, direction w=0). -1 when the light is free.
    int32_t attachedInstance = -1;
    glm::vec3 localPosition{0.0f};
    glm::vec3 localDirection{0.0f, 0.0f, -1.0f};
};

struct Camera {
    glm::vec3 position{0.0f, 10.0f, 20.0f};
    glm::vec3 target{0.0f};
    float fovY = 1.0f; // radians
    float nearPlane = 0.1f;
    float farPlane = 500.0f;
};

// A car: a dynamic instance that drives around a closed loop of street waypoints at constant speed.
struct CarPath {
    uint32_t instance = 0;
    std::vector<glm::vec3> waypoints; // closed loop, y = road height
    float speed = 8.0f;               // m/s
    float phase = 0.0f;               // metres along the loop at t = 0
};

struct Scene {
    std::string name;
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<Light> lights;
    std::vector<CarPath> cars;
    Camera camera;
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f}; // world AABB of all instances
    // Things a loader skipped or repaired without failing (one line each), e.g. a glTF primitive of a
    // non-triangle mode, or a mirrored asset that was turned upright. Empty for the night city.
    std::vector<std::string> warnings;
};

} // namespace ml
