// The camera's matrices. The module renders and reconstructs with reversed Z: a perspective projection
// into Vulkan clip space (y down) whose depth is 1 at the near plane and 0 at the far plane, and a
// G-buffer cleared to 0 and tested with GREATER. A D32F value then keeps 2^-24 relative precision at
// every distance; standard Z (far -> 1) reconstructs receivers 200 m away centimetres off their
// surface (docs/accuracy.md, section 1; tests/gpu/camera_test.cpp measures both).
//
// A host gives the camera either as a CameraDesc (position, target, up, fovY, near, far) or as its own
// view and projection matrices (Module::setCameraMatrices); both may carry a sub-pixel jitter.
#pragma once
#include "manylights/glm.h"
#include "manylights/manylights.h"

namespace ml {

struct CameraMatrices {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f}; // reversed Z, y down, without jitter
};

// Standard Z from a CameraDesc for the module's own camera: glm::lookAt and a reversed-Z perspective.
CameraMatrices cameraMatrices(const CameraDesc& camera, float aspect);

// Checks a host's view (rigid, finite) and projection (finite reversed-Z right-handed perspective into
// Vulkan clip space, finite far plane, y down) and returns the CameraDesc they describe (position,
// a target one metre ahead, up, fovY, near, far), validated like setCamera's. One-line reasons.
Result<CameraDesc> cameraFromMatrices(const glm::mat4& view, const glm::mat4& projection);

// Refuses a non-finite jitter or one beyond a pixel on either axis.
Result<void> validateJitter(glm::vec2 jitterPixels);

// The projection shifted so that every projected point moves by `jitterPixels` (x right, y down) on a
// width x height target.
glm::mat4 jittered(const glm::mat4& projection, glm::vec2 jitterPixels, uint32_t width, uint32_t height);

} // namespace ml
