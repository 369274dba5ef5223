// Ray-traced visibility: the ground truth that static shadow methods (baked shadow maps, voxel DAGs) are
// measured against.
//
// RayReference flattens the scene's instances into world-space triangles (one Embree triangle geometry per
// instance, geomID = instance index) and builds a single Embree scene once, with the high-quality builder
// and the robust flag. Robust traversal matters here: a ray that passes exactly through a shared edge or
// vertex of two triangles must not slip through, or the "truth" would report light leaks that the methods
// under test are then blamed for.
//
// Queries are occlusion rays (any hit, no hit record) from a receiver point to a light position:
//   - visible(): one ray; the origin moves `bias` along the ray towards the light (tnear = bias) and the ray
//     stops `bias` short of the light (tfar = distance - bias), so neither the receiver's own surface nor
//     geometry the light sits on (a lamp housing) counts as an occluder.
//   - visibleBatch(): many receivers, traced in packets of the CPU's native width (rtcOccluded16 with
//     AVX-512) and, for large batches, on two threads. The origin moves `bias` along the receiver's surface
//     normal instead (see the comment on the function for why).
//
// Accuracy: compareVisibility() counts binary disagreements (method < 0.5 means "in shadow") and the mean
// absolute difference of filtered values. Only receivers a light can reach should be compared; inLightCone()
// is the test the caller applies to pick them.
//
// Everything is CPU-only and independent of Vulkan. Errors come back as one-line Result messages; Embree's
// own error text is captured by a device error callback.
#pragma once
#include "io/result.h"
#include "scenes/scene.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

// Embree's handles are opaque pointers; forward-declared so that users of this header need not include
// <embree3/rtcore.h>.
typedef struct RTCDeviceTy* RTCDevice;
typedef struct RTCSceneTy* RTCScene;

namespace ml {

// The nearest surface along a ray (firstHit): distance, the instance it belongs to (index into
// Scene::instances), its geometric normal (world space, not normalised, facing per the CCW winding) and
// whether its mesh is marked closed.
struct RayHit {
    bool hit = false;
    float t = 0.0f;
    uint32_t instance = 0;
    glm::vec3 ng{0.0f};
    bool closed = false;
};

class RayReference {
  public:
    // Builds the occlusion scene from the world-space triangles of the scene's instances. With staticOnly
    // (the default) dynamic instances are left out: the static methods under test never see them either,
    // so their shadows would be counted as errors that no static method could avoid.
    // Fails (one line) on an instance naming a missing mesh, indices out of range or not a multiple of
    // three, a non-finite transform, or any Embree error (its message is included).
    static Result<RayReference> build(const Scene& scene, bool staticOnly = true);
    // Same, with an Embree device configuration string (e.g. "threads=1"); an empty string is the default.
    static Result<RayReference> build(const Scene& scene, bool staticOnly, const std::string& deviceConfig);

    RayReference(RayReference&&) noexcept;
    RayReference& operator=(RayReference&&) noexcept;
    RayReference(const RayReference&) = delete;
    RayReference& operator=(const RayReference&) = delete;
    ~RayReference();

    // True when nothing blocks the segment from `receiver` to `lightPos`, with `bias` metres cut off at both
    // ends (tnear = bias, tfar = distance - bias). A receiver closer than 2 * bias to the light is visible:
    // there is no segment left to test.
    bool visible(glm::vec3 receiver, glm::vec3 lightPos, float bias) const;

    // visible() for n receivers at once; out[i] = 1 when receiver i sees the light, 0 otherwise.
    //
    // The origin is offset by `bias` along the receiver's normal, not along the ray. Receivers come from
    // surfaces (a G-buffer, samples on triangles); at grazing light angles a shift along the ray barely moves
    // the origin off its own surface, and in a concave corner it can push the origin into the neighbouring
    // wall, while a shift along the normal always leaves the surface by the full bias. The ray then runs
    // from the shifted origin to `bias` short of the light.
    //
    // A normal that faces away from the light is flipped first. Visibility here is the shadow term only:
    // N.L <= 0 is the shading's business, and receivers on thin two-sided geometry (foliage cards, awnings,
    // open quads) carry whichever normal the asset happened to have. Flipping makes the answer the same for
    // both sides of such a surface, and a back-facing receiver on a closed mesh is still reported as
    // occluded by the rest of that mesh.
    //
    // normals may be null: then every receiver uses the visible() rule (shift along the ray), and the
    // results equal visible() exactly. Normals need not be unit length; a zero normal also falls back to
    // the visible() rule.
    void visibleBatch(const glm::vec3* receivers, const glm::vec3* normals, size_t n, glm::vec3 lightPos,
                      float bias, uint8_t* out) const;

    // Threads visibleBatch() may use; defaults to min(2, hardware threads). Batches under 32768 receivers
    // always run on the calling thread. Callers that already run in parallel (e.g. one light per thread)
    // should set 1.
    void setThreads(unsigned threads) { threads_ = threads == 0 ? 1 : threads; }
    unsigned threads() const { return threads_; }

    // Nearest hit on (origin + t * dir), t in (tnear, tfar); dir need not be unit length (t scales with
    // it). Used to explain disagreements (bake/reference/error_classes.h), not for visibility.
    RayHit firstHit(glm::vec3 origin, glm::vec3 dir, float tnear, float tfar) const;

    uint64_t triangleCount() const { return triangles_; }
    uint32_t geometryCount() const { return geometries_; }
    // Packet width visibleBatch() traces with (16, 8, 4 or 1), picked from what the Embree build supports
    // natively on this CPU.
    int packetWidth() const { return packetWidth_; }

  private:
    struct ErrorSink;
    RayReference() = default;
    void release();
    template <int N>
    void traceRange(const glm::vec3* receivers, const glm::vec3* normals, size_t begin, size_t end,
                    glm::vec3 lightPos, float bias, uint8_t* out) const;
    void traceRangeAny(const glm::vec3* receivers, const glm::vec3* normals, size_t begin, size_t end,
                       glm::vec3 lightPos, float bias, uint8_t* out) const;

    // Declared first so that it outlives the device whose callback writes into it.
    std::unique_ptr<ErrorSink> errors_;
    std::vector<uint8_t> closed_; // per instance index (= Embree geometry ID): its mesh is marked closed
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    uint64_t triangles_ = 0;
    uint32_t geometries_ = 0;
    unsigned threads_ = 1;
    int packetWidth_ = 1;
};

// Accuracy of a shadow method against ray-traced truth over a set of receivers.
struct Disagreement {
    uint64_t compared = 0;   // receivers compared
    uint64_t mismatches = 0; // binary disagreements: (method >= 0.5) != truth
    double meanAbsDiff = 0;  // mean |method - truth| over the compared receivers (filtered methods)
    double rate() const { return compared ? double(mismatches) / double(compared) : 0.0; }
    // Pools another measurement (e.g. the next light) into this one; meanAbsDiff is weighted by count.
    void merge(const Disagreement& other);
};

// method[i] in 0..1 (fraction of light reaching receiver i; filtered methods give values in between),
// truth[i] = 0 or 1 (from visibleBatch). Compares the first min(method.size(), truth.size()) receivers;
// callers pass equal sizes. Method values are clamped to 0..1; a NaN counts as a mismatch with difference 1,
// so a method that produces garbage cannot look accurate.
Disagreement compareVisibility(const std::vector<float>& methodVisibility, const std::vector<uint8_t>& truth);

// Same, counting only receivers with include[i] != 0 (e.g. inLightCone for the light being measured), so
// receivers the light cannot reach do not dilute the error rate.
Disagreement compareVisibility(const std::vector<float>& methodVisibility, const std::vector<uint8_t>& truth,
                               const std::vector<uint8_t>& include);

// Whether the light can illuminate p at all, i.e. whether p's visibility for this light matters.
// Spot: distance < range and angle between the light direction and (p - position) <= outerAngle.
// Point: distance < range. Directional: always true (no position, no range).
// A point exactly at a spot light's position has no direction and is outside.
bool inLightCone(const Light& light, glm::vec3 p);

} // namespace ml
