// Exact receivers of the static shadow benchmarks (bench static, bench flicker, bench static --need):
// the camera ray through a pixel's centre in double precision, traced against the static scene with
// Embree, so receivers sit on the surface rather than at the G-buffer's reconstructed depth; and the
// static spot lights measured over them (those reaching the most).
#pragma once
#include "bake/reference/raytrace.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace ml {

enum class PixelConvention {
    Standard, // NDC y up, depth 0 near and 1 far (the benchmarks' own double-precision views)
    GBuffer,  // the module's G-buffer: NDC y down, reversed Z (depth 1 near, 0 far: engine/camera.h)
};

// The unit direction of the ray through pixel (x, y)'s centre, from the inverse view-projection.
glm::dvec3 pixelRayDirection(const glm::dmat4& invViewProj, uint32_t x, uint32_t y, uint32_t width,
                             uint32_t height, PixelConvention convention);

struct SurfaceHit {
    bool hit = false;
    glm::vec3 p{0.0f}, n{0.0f}; // the hit and its geometric normal, turned to face the ray's origin
};

// The first static surface along the ray within `farDistance`.
SurfaceHit traceSurface(const RayReference& rays, const glm::dvec3& eye, const glm::dvec3& dir,
                        float farDistance);

// The static spot lights of `scene` by how many receivers each reaches (`reach`), most first (equal
// counts: the higher index first), those reaching none left out: (count, light index) pairs.
std::vector<std::pair<size_t, uint32_t>> rankStaticSpots(const Scene& scene,
                                                         const std::function<size_t(const Light&)>& reach);
// The light indices of the first `count` of a ranking.
std::vector<uint32_t> firstLights(const std::vector<std::pair<size_t, uint32_t>>& ranked, uint32_t count);

} // namespace ml
