// Virtual shadow maps against rays: the one-tap answer the VSM gave at each (G-buffer pixel, light)
// pair, read back through the probe pass (shadows/virtual/vsm_probe.comp) and redone on the CPU from the
// page table and pool (diag::vsmKernelLit, which `check vsm` and `bench flicker --vsm` hold equal to the
// GPU's lookup), against Embree rays from the same receiver to the light (the 1 mm normal offset of the
// static benches, docs/accuracy.md section 1). Used by `manylights bench vsm-rays` and the failure suite.
//
// A pair counts when its lookup ended at a page or found no caster (status Page, Fallback or NoCaster),
// its map is a spot light's or a point light's cube face (directional clip levels are left out: the rays
// here aim at a position), the receiver is in the light's cone and faces it, and the CPU kernel's centre
// texel equals the depth the probe read. Left-out pairs are counted by reason.
//
// A disagreement (the VSM's binary answer is not the rays') gets one cause, tested in this order:
//   Fallback   the lookup ended at a coarser page than it wanted (pool full: probe status Fallback);
//   Bias       an occluder within the lookup's bias band of the receiver: the VSM shadows and the texel's
//              depth lies less than the band plus the receiver surface's own depth span across a texel
//              (tan of its angle to the light, in texels) in front of the receiver's (acne: the
//              receiver's own surface, or one touching it), or the VSM lights and the rays' first occluder
//              lies within the band of the receiver (the normal and depth offsets stepped past it).
//              Band: (depth bias + normal bias + 1) texels of the lookup's mip at the receiver, plus the
//              rays' offset;
//   Seam       a neighbouring texel (8-neighbourhood at the lookup's mip) has no resident page, or a
//              neighbouring pixel's lookup of the same light (4-neighbourhood) ended at another map or
//              mip: the pair sits where the VSM changes level;
//   Resolution the one-tap answer changes within +-1 texel (a neighbouring texel at the same mip, read
//              with the same receiver depth, answers otherwise): a caster's edge in the receiver's texel;
//   Other      everything else (thin casters the texel centres miss, float-vs-double ties, receivers the
//              G-buffer puts inside geometry).
#pragma once
#include "engine/manylights_diagnostics.h"
#include "bake/reference/raytrace.h"

#include <array>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace ml {

enum class VsmRayClass : uint32_t { Fallback = 0, Bias, Seam, Resolution, Other, Count };
constexpr uint32_t kVsmRayClassCount = uint32_t(VsmRayClass::Count);
const char* vsmRayClassName(VsmRayClass c);

// One frame's read-backs: the module must have run with VsmSettings::probeCapacity > 0, PCF radius 0
// (the probe's texel is then the one tap), and createTargets (the G-buffer is read back).
struct VsmRayFrame {
    std::vector<diag::VsmProbe> probes;
    uint32_t probeOverflow = 0;
    std::shared_ptr<const diag::VsmPageState> pages;
    std::vector<diag::VsmMap> maps;
    diag::LastFrame constants;
    std::vector<float> depth;
    std::vector<glm::vec3> normal;
};
Result<VsmRayFrame> readVsmRayFrame(Module& module);

struct VsmRayOptions {
    uint32_t resolution = 1024; // VsmSettings::resolution (mip m is resolution >> m)
    float rayBias = 0.001f;     // the rays' normal offset, metres
    // The lights' shadowDepthBias and shadowNormalBias (texels; include/manylights/lights.h): the band.
    float depthBias = 0.5f, normalBias = 1.0f;
};

struct VsmRayCounts {
    uint64_t pairs = 0, raysLit = 0, vsmLit = 0, mismatches = 0;
    uint64_t vsmShadowsLit = 0;   // mismatches where the rays see the light (acne, over-shadowing)
    uint64_t vsmLightsShadow = 0; // mismatches where the rays are blocked (light leaks)
    std::array<uint64_t, kVsmRayClassCount> byClass{};
    // Left out, by reason.
    uint64_t directional = 0, missing = 0, outsideCone = 0, backFacing = 0, unknownLight = 0,
             probeDisagrees = 0, fallbackPairs = 0;
    uint32_t probeOverflow = 0;
    void merge(const VsmRayCounts& o);
    double rate() const { return pairs ? double(mismatches) / double(pairs) : 0.0; }
};

// One compared pair (for callers that compare another method at the same receivers).
struct VsmRayPair {
    uint32_t pixel = 0, sceneLight = 0;
    glm::vec3 p{0.0f}, n{0.0f};
    bool truth = false, vsm = false;
    VsmRayClass cause = VsmRayClass::Other; // meaningful when truth != vsm
};

// Compares every probe of `frame` with the rays (built from the frame's scene, dynamic instances
// included: the VSM draws them). `sceneLight` maps a module light slot to its index in scene.lights.
// Adds to `counts`; appends the compared pairs to `pairs` when given.
void measureVsmRays(const VsmRayFrame& frame, const Scene& scene, const RayReference& rays,
                    const std::unordered_map<uint32_t, uint32_t>& sceneLight, const VsmRayOptions& options,
                    VsmRayCounts& counts, std::vector<VsmRayPair>* pairs = nullptr);

} // namespace ml
