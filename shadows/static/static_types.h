// Static shadow API types of the public header (engine/manylights.h): the encoding methods and the light
// frustum a bake is rendered with. The encoders, decoders and the bake file are this folder's library
// (manylights_static: static_method.h, dual_depth.h, bake_file.h), which hosts use only to make or read
// bakes.
#pragma once
#include "io/result.h"
#include "shaders/shared/enums.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>

namespace ml {

// StaticMethod is shaders/shared/enums.h (one definition for C++ and GLSL).
const char* staticMethodName(StaticMethod method); // "sm", "mh", "mmh", "dagmh", "cpvs", "none"
Result<StaticMethod> parseStaticMethod(const std::string& name);
inline bool isDepthMethod(StaticMethod m) {
    return m >= StaticMethod::SM && m <= StaticMethod::DAGMH;
}

// A light's square perspective view: world -> light view (looking down -Z), full vertical = horizontal
// field of view, and the depth range [nearPlane, farPlane] (farPlane = the light's range).
struct LightFrustum {
    glm::mat4 view{1.0f};
    float fov = 1.0f; // full angle, radians, < pi (perspective)
    float nearPlane = 0.05f;
    float farPlane = 10.0f;
    // > 0: orthographic (a directional light): the square view volume's half side in metres, fov
    // unused. Texel (x, y) then covers view x in [x/res*2-1, ...] * orthoHalf, depth is view -z as for
    // perspective maps.
    float orthoHalf = 0.0f;
    bool orthographic() const { return orthoHalf > 0.0f; }
};

// What a light's shadow frustums depend on (spotLightFrustum, pointLightFaceFrustum, lightFrustums in
// raster_dual.h): its kind, pose, range and cone. A scene's Light (scenes/scene.h) is one, so the
// static shadow library needs no scene type.
struct LightShape {
    LightKind type = LightKind::Spot;
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f}; // unit; spot and directional
    float range = 10.0f;                    // metres; attenuation reaches zero here
    float outerAngle = 0.6f;                // half angle of the cone where light ends (spot)
};

} // namespace ml
