// Why a static shadow lookup disagrees with the rays: one class per disagreement, so `bench static`
// can say which part of its error falls with resolution and which is a floor.
//
// Classes, tested in this order (the first that applies wins):
//   Inside     the rays' origin (the receiver moved `rayBias` along its normal, turned towards the
//              light, as visibleBatch does) is inside closed geometry: the first surface the ray meets
//              is a back face of a closed mesh. Truth and map then judge a point no camera should see
//              (a G-buffer sample in a seam or on a face buried in another box).
//   Contact    a surface lies within the lookup's bias band of the receiver along the ray to the light
//              (band = 1.5 texel footprints, the normal offset plus the half-texel depth bias, plus the
//              ray bias): the map cannot tell the receiver from its occluder there, by design.
//   Resolution the one-tap map answer changes within +-1 texel around the receiver (one of the 8
//              receivers moved by a texel footprint along the light's x/y axes reads otherwise): a
//              caster's edge falls in the receiver's texel, which a finer map would resolve.
//   ThinOpen   the rays are blocked by an open (not closed) mesh and none of the above holds: thin
//              casters (fences, cards, awnings) that the map's texel centres miss.
//   Other      everything else.
// Inputs are what the comparison already has: the rays, the record and words of the light's bake
// (the one-tap lookup is used for the neighbourhood test whatever the PCF radius).
#pragma once
#include "shaders/shared/gpu_types.h"
#include "bake/reference/raytrace.h"

#include <array>
#include <cstdint>

namespace ml {

enum class ErrorClass : uint32_t { Inside = 0, Contact, Resolution, ThinOpen, Other, Count };
constexpr uint32_t kErrorClassCount = uint32_t(ErrorClass::Count);
const char* errorClassName(ErrorClass c);

struct ErrorContext {
    const RayReference* rays = nullptr;
    gpu::GpuShadowRecord record{}; // the bake's record (base into words); its PCF radius is ignored here
    const uint32_t* words = nullptr;
    glm::vec3 lightPos{0.0f};
    float rayBias = 0.02f; // as passed to visibleBatch
};

// Class of one disagreement of receiver (p, n) (n unit).
ErrorClass classifyDisagreement(const ErrorContext& ctx, glm::vec3 p, glm::vec3 n);

// Counts per class.
using ErrorCounts = std::array<uint64_t, kErrorClassCount>;

} // namespace ml
