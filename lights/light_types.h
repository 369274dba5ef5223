// Light API types of the public header (engine/manylights.h): a light as the host describes it, and the
// validation the module runs on it. Below the engine so that the evaluation pass (lights/lights.h) can
// convert it without including the facade. LightKind is shaders/shared/enums.h.
#pragma once
#include "io/result.h"
#include "shaders/shared/enums.h"

#include <glm/glm.hpp>

namespace ml {

struct LightDesc {
    LightKind kind = LightKind::Spot;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f};
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    float range = 10.0f;
    float outerAngle = 0.6f;  // half angle, radians, (0, pi/2) for spots
    float innerAngle = 0.4f;  // [0, outer]
    bool dynamic = false;     // moves: its shadows are never baked (virtual shadow maps draw every caster)
    bool castsShadows = true; // false: no static bake is used and no virtual shadow map is made
};

// A one-line reason when a parameter is NaN, infinite, negative or out of its range (addLight and
// setLight call it; a host or a command line may call it first).
Result<void> validateLight(const LightDesc& light);

} // namespace ml
