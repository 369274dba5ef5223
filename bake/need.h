// Resolution from need: per static light, the bake resolution that the camera can
// actually resolve, given where the camera can be.
//
// A light's map spans a world width W(p) at a receiver point p (perspective: 2 z tan(fov/2), z the
// depth along the light's axis; orthographic: 2 * half side). A camera at depth d from p (along its
// view axis; from a box region, the distance, since it may look straight at p) sees one pixel of width
// P = 2 d tan(fovY/2) / H there (H the image height). One texel per pixel needs R >= W(p) / P. The
// light's need is the largest such R over its receivers and the camera samples that see them; its
// resolution is that rounded up to a power of two and clamped to [minRes, maxRes].
//
// Receivers are points sampled on the scene's static triangles inside the light's volume (a grid of
// spacing range/40 in each triangle's plane, clipped to the light's sphere), facing the light on the
// side the camera sees (two-sided), in a bake frustum of the light and within its range. A camera
// sample sees a point when the point lies in its view frustum (paths) and, with a visibility callback
// (the bake uses Embree rays), nothing blocks the segment; without the callback occlusion is ignored
// (an upper bound on the need). Limits, said plainly: the camera is only tested at its samples (moving
// between two samples it can come closer); slopes are ignored (a receiver seen at a grazing angle by
// the light needs more, one seen at a grazing angle by the camera less); PCF is not taken into account.
//
// A light whose volume holds no triangle at all would bake an empty map (every lookup lit, the same as
// no record): it gets no structure (reason NoCaster). The test is conservative: a triangle counts unless
// it lies wholly outside one plane of one of the light's bake frustums, so a light that could cast any
// shadow is never dropped. CPU only, deterministic (no threads, no clock).
#pragma once
#include "scenes/scene.h"
#include "shadows/static/bake_file.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ml {

// One position the camera can take.
struct NeedCamera {
    glm::vec3 position{0.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f}; // unit; ignored when anyDirection
    float fovY = 1.0f;                    // radians
    float aspect = 16.0f / 9.0f;
    float nearPlane = 0.1f, farPlane = 500.0f;
    bool anyDirection = false; // a box region: the camera may look anywhere (depth = distance)
};

// A grid of n x n x n positions filling the box [lo, hi] (n = 1: its centre), any direction.
std::vector<NeedCamera> boxCameras(glm::vec3 lo, glm::vec3 hi, uint32_t n, float fovY, float nearPlane,
                                   float farPlane);

struct NeedOptions {
    uint32_t width = 1280, height = 720; // the image the camera renders
    uint32_t minRes = 64, maxRes = 4096; // clamp (powers of two keep CPVS bakeable)
    // Optional occlusion test between a camera position and a receiver point (offset off its surface):
    // true when nothing blocks the segment. Empty: occlusion ignored.
    std::function<bool(const glm::vec3& camera, const glm::vec3& receiver)> visible;
    uint64_t maxRaysPerLight = 200000; // past this, the rest is taken unoccluded (counted in raysCapped)
};

// Estimates the need of each light in `lights` (indices into scene.lights; dynamic lights are not the
// caller's business here: they are estimated like the others). Fails on an index out of range, no
// camera sample, or options out of range.
Result<std::vector<LightNeed>> estimateNeed(const Scene& scene, const std::vector<uint32_t>& lights,
                                            const std::vector<NeedCamera>& cameras,
                                            const NeedOptions& options);

// "footprint", "capped", "floor", "not-seen", "no-caster".
const char* needReasonName(NeedReason r);
// One line: why the light got its resolution ("receiver 7.9 m from camera sample 41 needs 1790: 2048").
std::string needReasonText(const LightNeed& n, uint32_t samples);

} // namespace ml
