// Static shadow API types of the public header (manylights/module.h): the encoding methods and the light
// frustum a bake is rendered with. The encoders, decoders and the bake file are this folder's library
// (manylights_static: static_method.h, dual_depth.h, bake_file.h), which hosts use only to make or read
// bakes.
#pragma once
#include "io/result.h"
#include "shaders/shared/enums.h"

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <string>

namespace ml {

// StaticMethod is shaders/shared/enums.h (one definition for C++ and GLSL).
const char* staticMethodName(StaticMethod method); // "sm", "mh", "mmh", "dagmh", "cpvs", "none"
Result<StaticMethod> parseStaticMethod(const std::string& name);
inline bool isDepthMethod(StaticMethod m) {
    return m >= StaticMethod::SM && m <= StaticMethod::DAGMH;
}

// A light's view: world -> light view (looking down -Z). Perspective: square, full vertical = horizontal
// field of view, and the depth range [nearPlane, farPlane] (farPlane = the light's range). Orthographic
// (directional): see orthoHalf; fitted to a box, the depth range is the box's slab along the light.
struct LightFrustum {
    glm::mat4 view{1.0f};
    float fov = 1.0f; // full angle, radians, < pi (perspective)
    float nearPlane = 0.05f;
    float farPlane = 10.0f;
    // > 0: orthographic (a directional light): the square view volume's half side in metres, fov
    // unused. Texel (x, y) then covers view x in [x/res*2-1, ...] * orthoHalf (and y alike: square
    // texels), depth is view -z as for perspective maps.
    float orthoHalf = 0.0f;
    // A directional map fitted to its box (directionalLightFrustum): > 0, at most orthoHalf.
    // The box's light-space rectangle (plus fitMargin on every side) is view x in [-orthoHalf,
    // orthoHalf] by view y in [-orthoHalf, -orthoHalf + 2 orthoHalfY]: only the first mapRows(res) rows
    // of the res x res texel grid lie in the light's volume, the rest are outside it (empty, lit). 0: a
    // square map, every row (perspective maps, and orthographic ones made by hand).
    float orthoHalfY = 0.0f;
    // The margin (metres) the fit added around the box on every side and along the light, so the box's
    // slab along the light is [nearPlane + fitMargin, farPlane - fitMargin]. 0 when not fitted.
    float fitMargin = 0.0f;
    bool orthographic() const { return orthoHalf > 0.0f; }
    bool fitted() const { return orthographic() && orthoHalfY > 0.0f; }
    // Rows in the light's volume at resolution res: ceil(res * orthoHalfY / orthoHalf) clamped to
    // [1, res] (in double, so the writer, the reader and the rasteriser agree), res when not fitted.
    uint32_t mapRows(uint32_t res) const {
        if (!fitted() || res == 0) return res;
        const double r = std::ceil(double(res) * double(orthoHalfY) / double(orthoHalf));
        return r >= double(res) ? res : (r < 1.0 ? 1u : uint32_t(r));
    }
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
