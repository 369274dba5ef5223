// Lights: validation of host-given parameters, conversion to the GPU layout, and the per-frame
// frustum test that builds the visible-light list (on the CPU: 4096 sphere-plane tests cost
// microseconds, and the culling passes then work on visible lights only).
#pragma once
#include "manylights/glm.h"
#include "manylights/lights.h"
#include "shaders/shared/gpu_types.h"

#include <array>

namespace ml {

// validateLight is public (manylights/lights.h); validateCamera is engine/camera.cpp.

// A host's light with its vectors as glm (the public LightDesc has plain ones): the module's own math
// converts once, at the API boundary. The members hide LightDesc's of the same name; the rest is read
// from the LightDesc.
struct GlmLight : LightDesc {
    glm::vec3 position, direction, color;
    explicit GlmLight(const LightDesc& light)
        : LightDesc(light), position(toGlm(light.position)), direction(toGlm(light.direction)),
          color(toGlm(light.color)) {}
};

gpu::GpuLight toGpuLight(const LightDesc& light, uint32_t id);

// World-space bounding sphere of everything the light can reach (xyz centre, w radius); for a spot
// with half angle a < 45 deg the sphere around the cone is smaller than the range sphere.
glm::vec4 lightBoundingSphere(const LightDesc& light);

// Planes (xyz normal pointing inside, w offset) of a view-projection's frustum, Vulkan depth [0,1].
std::array<glm::vec4, 6> frustumPlanes(const glm::mat4& viewProj);
bool sphereInFrustum(const std::array<glm::vec4, 6>& planes, glm::vec4 sphere);

} // namespace ml
