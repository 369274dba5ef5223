// manylights diagnostics: read-backs for tools, benchmarks and checks (`manylights bench`, `check vsm`),
// through the public API. A host engine renders with manylights/manylights.h alone and has no need of
// these. Not installed: the project's own tools use them, built with the module's settings (these types
// are glm's and the static shadow library's, whose layout the includer's definitions may change).
//
//   G-buffer      readGBuffer: the module-owned depth and normals of the last frame (receivers for
//                 ray-traced references).
//   last frame    lastFrame: the constants the passes used (view-projection, its inverse, eye, size).
//   counters      cullingBoxTests, vsmPrepareMs, sceneCounts.
//   VSM           vsmMeshPath, vsmMaps, readVsmProbes (the probe pass: VsmSettings::probeCapacity > 0),
//                 vsmCasterPoint (the page draws' transform, for CPU reference maps), readVsmPageState
//                 with vsmKernelLit (the lookup's kernel redone on the CPU).
//
// Every function reads the results of frames the host has already waited for (e.g. submitFrame() or
// vkQueueWaitIdle); the read-backs that copy from the GPU wait for the queue themselves: not for a frame
// loop.
#pragma once
#include "manylights/glm.h"
#include "manylights/manylights.h"
#include "shadows/static/static_types.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace ml::diag {

// The constants of the last recorded frame (all zero before the first record()).
struct LastFrame {
    glm::mat4 viewProj{0.0f};    // world -> clip (Vulkan, reversed Z: near 1, far 0)
    glm::mat4 invViewProj{0.0f}; // clip -> world
    glm::vec3 cameraPosition{0.0f};
    glm::uvec4 size{0}; // x width, y height, zw 0 (the layout gpu::worldFromPixel takes)
    float nearPlane = 0, farPlane = 0;
};
LastFrame lastFrame(const Module& module);

// Module-owned targets (createTargets) only: the G-buffer depth (the D32 values as stored, in the depth
// convention HostTargets documents) and world normals (half floats as stored, unit length up to
// rounding) of the last frame, width * height each, row-major in image rows. Waits for the queue.
// Refused with host targets (setTargets) or before the first frame.
Result<void> readGBuffer(Module& module, std::vector<float>& depth, std::vector<glm::vec3>& normal);

// Bytes the module allocates for targets of width x height (createTargets: ownTargets; setTargets: not):
// the images, the cluster buffers and the readback (engine/limits.h), for a command's memory estimate.
uint64_t targetBytes(uint32_t width, uint32_t height, bool ownTargets);

// Light-versus-cluster box tests of the light assignment in the last completed frame (culling
// statistics; 0 in mode None).
uint32_t cullingBoxTests(const Module& module);
// CPU wall time of the virtual shadow maps' preparation in the last record() (0 with them off).
double vsmPrepareMs(const Module& module);

// Z-binning (culling/zbin.h, Drobot 2017) run on the last frame's depth, lights and cluster tile masks,
// beside the footprint clusters (`bench culling --compare-zbin`, docs/culling.md): host work
// (footprints, sort, upload), the mask and bin passes timed fenced (each its own submission, means
// over `frames` after a warm-up; host: footprints + sort + upload, also a mean), and the per-pixel sums
// of the stats pass (wide lights included in all but surface). depthTest: masks also test
// the tile's occupied cluster slices (needs cluster_bounds, which the frame ran). The last frame must
// have used module-owned targets and the clustered mode. Waits for the queue; the evaluation pass
// does not use the result.
// shadeClustersMs, shadeZBinMs: the shading-loop probe (culling/zbin_shade.comp: the evaluation's
// light term, no visibility) over the clusters' lists and over the Z-bin candidates, fenced means: what
// the candidates cost the evaluation, measured with one loop body.
struct ZBinMeasure {
    double hostMs = 0, maskMs = 0, binsMs = 0, statsMs = 0;
    double shadeClustersMs = 0, shadeZBinMs = 0;
    uint32_t sorted = 0, wide = 0; // lights in the sorted list; wide (directional) lights
    uint64_t evaluated = 0, reaching = 0, surface = 0;
    uint64_t tile = 0;  // the tile's lights at any depth (the mask alone)
    uint64_t exact = 0; // evaluated lights whose own depth bins hold the pixel's (no (min, max) range)
};
Result<ZBinMeasure> measureZBin(Module& module, bool depthTest, uint32_t frames);

// Slots in the module's scene tables (removed objects included) and the meshlets built for the VSM mesh
// path (meshoptimizer, VsmSettings::meshletVertices / meshletTriangles).
struct SceneCounts {
    uint32_t meshes = 0, instances = 0, meshlets = 0;
};
SceneCounts sceneCounts(const Module& module);

// vkDeviceWaitIdle calls the module has made since create() (docs/integration.md lists the calls that
// still wait: bakeStaticShadows, the module's destruction, readOutput's and submitFrame's queue waits
// are not device waits and are not counted).
uint64_t deviceWaitCount(const Module& module);

// Every queue submission and every queue, device or fence wait the module made on its device (its own or
// the borrowed one), counted at the one place they all go through (the module's device layer), and
// those made inside record(): 0 submits and 0 waits there outside TimingChoice::Fenced (the host's queue is
// its own; QueueAccess.* interpose the Vulkan calls and agree with these).
struct QueueAccessCounts {
    uint64_t submits = 0, waits = 0;             // since create()
    uint64_t recordSubmits = 0, recordWaits = 0; // of those, inside record()
    // Pipelines built (vkCreateComputePipelines / vkCreateGraphicsPipelines), and inside record(): 0
    // there, every pipeline a frame can reach being built by create(), createTargets and setTargets.
    uint64_t pipelines = 0, recordPipelines = 0;
};
QueueAccessCounts queueAccessCounts(const Module& module);

// Whether the virtual shadow maps draw pages with task and mesh shaders (VsmRaster::Auto resolved at
// create()); false when the maps are off or on the vertex path.
bool vsmMeshPath(const Module& module);

// One virtual shadow map slot (a spot light, a point light's cube face, a directional clip level).
struct VsmMap {
    bool inUse = false;
    uint32_t light = 0;        // module light slot (LightId without its generation)
    uint32_t face = 0;         // cube face or clip level
    bool orthographic = false; // a directional light's clip level
    bool dynamicOnly = false;  // the light has a static bake: its pages hold dynamic casters only
    LightFrustum frustum;      // the volume a reference rasteriser uses (orthoHalf > 0 for clip levels)
};
std::vector<VsmMap> vsmMaps(const Module& module);

// What one shaded pixel's lookup of one light found (the probe pass, shadows/virtual/vsm_probe.comp).
enum class VsmProbeStatus : uint32_t {
    Page = 0,     // read from a page at the wanted mip
    Fallback = 1, // read from a coarser allocated page (pool full)
    NoCaster = 2, // no dynamic caster's bounds cover the texel: visibility 1
    Missing = 3,  // no valid page at any mip (must stay 0)
};
struct VsmProbe {
    uint32_t map = 0, mip = 0, x = 0, y = 0; // the texel read, at the mip used
    uint32_t pixel = 0, light = 0;
    uint32_t depth = 0;         // quantised depth read (0xFFFFFFFF: empty texel)
    uint32_t receiverDepth = 0; // the receiver's biased depth it was compared with
    VsmProbeStatus status = VsmProbeStatus::Page;
};
// The probe records of the last recorded frame (at most VsmSettings::probeCapacity; `overflow` receives
// the records that did not fit). Empty when the probe pass is off. The host must have waited for the frame.
std::vector<VsmProbe> readVsmProbes(const Module& module, uint32_t* overflow = nullptr);

// The virtual shadow maps' page state after the last frame (page table, physical pool, the maps'
// coverage bits; read back, waits for the queue), and the evaluation pass's PCF kernel evaluated on it
// on the CPU (the shader's vsmKernelLit): for checks that redo a lookup at a probe's place.
struct VsmPageState;
std::shared_ptr<const VsmPageState> readVsmPageState(Module& module);
// Whether the texel (map, mip, x, y) reads a page (a map with a static bake needs pages only under
// dynamic casters' bounds; the others everywhere).
bool vsmTexelNeedsPage(const VsmPageState& state, uint32_t map, uint32_t mip, int x, int y);
// Lit taps of the (2 radius + 1)^2 kernel around texel (x, y) of (map, mip) for a receiver's quantised
// depth; -1 when a tap's page is not resident. `centre` receives the centre texel's depth (0xFFFFFFFF
// when no page is read there).
int vsmKernelLit(const VsmPageState& state, uint32_t map, uint32_t mip, int x, int y, uint32_t receiverDepth,
                 int radius, uint32_t& centre);
// A candidate filtered lookup, not one the module has: the 2x2 texels around the biased receiver's
// sub-texel position in (map, mip), weighted bilinearly, each compared with `receiverDepth` (the
// visibility in [0, 1] that `bench flicker --vsm --bilinear` thresholds at 0.5); -1 when a tap is not
// resident or the position's texel is not (x, y), the probe's.
float vsmBilinearLit(const VsmPageState& state, uint32_t map, uint32_t mip, glm::vec3 P, glm::vec3 N, int x,
                     int y, uint32_t receiverDepth);

// An instance vertex transformed exactly as the page draws transform it (bit for bit with the shaders),
// so a CPU reference rasteriser sees the same triangles.
glm::vec3 vsmCasterPoint(const glm::mat4& transform, glm::vec3 position);

} // namespace ml::diag
