// Light culling: clustered (froxels) and tiled, with a CPU reference. Output in every mode: `ranges`
// ((offset, count) per cluster, ML_CLUSTER_OVERFLOW for an overflowed one) and `pool` (light indices),
// cluster c = (tile.y * tilesX + tile.x) * slices + slice.
//
//   cluster_bounds  one group per ML_TILE_SIZE^2-pixel tile: each pixel with geometry goes to its depth
//                   slice (exponential slices, sliceBoundaries); the world AABB of the pixels in each
//                   (tile, slice) is reduced exactly with integer min/max. Empty clusters are marked;
//                   each tile's occupied slices also go into a 64-bit mask.
//                   Its receiver variant (wantReceivers: VSM page marking per cluster) also writes the
//                   receivers' box and normal bounds per occupied cluster (ClusterReceivers).
//                   Where the device allows, its wave build runs a tile in one subgroup (waveBounds).
//   clustered (footprint; the default): light_footprint (count, record hits) -> light_alloc ->
//                   light_fill (mark, append: sorted lists from per-tile light bitmasks, linear in the
//                   hits). Each visible light (8 threads) tests only the occupied clusters inside its
//                   footprint (lightFootprint: tile rectangle x depth-slice range), with the same exact box
//                   test; cost follows the lights' footprints, not lights x clusters. Wide lights
//                   (directional ones, chosen by the host: wideFootprint) take a thread per tile instead
//                   (light_footprint's wide variant), so the moon is not serial over the screen.
//   clustered-brute light_assign, one group per tile: every visible light against each occupied
//                   cluster (exact range-sphere vs AABB, cone tests), counted, allocated, written.
//   tiled           light_assign with one slice (the tile's AABB over all its pixels).
// Lists come out sorted by light index in every mode, like the CPU reference's (tests compare them in
// order): light_fill ranks each hit within its cluster's list, light_assign writes its lights in
// chunks of ML_ASSIGN_GROUP in index order, each chunk's hits placed by prefix counts of a bit mask.
// Overflowing clusters are flagged and counted in every mode; "none" skips culling.
// Tight bounds from the actual pixels (rather than the froxel's frustum volume) is what keeps lights
// evaluated per pixel close to lights that reach it (Olsson et al.'s clustered shading with
// explicit bounds; the slice layout follows the exponential scheme of that paper).
#pragma once
#include "shaders/shared/enums.h"
#include "gpu/pass_timer.h"
#include "gpu/program.h"
#include "shaders/shared/cluster_receivers.h"
#include "shaders/shared/gpu_types.h"
#include "shaders/shared/light_math.h"

#include <optional>
#include <vector>

namespace ml {

// Far boundary of each of `slices` exponential slices between near and far: slice s covers
// [near*(far/near)^(s/S), near*(far/near)^((s+1)/S)). One slice: the whole range.
std::vector<float> sliceBoundaries(float nearPlane, float farPlane, uint32_t slices);

struct ClusterGrid {
    uint32_t tilesX = 0, tilesY = 0, slices = 0;
    uint32_t count() const { return tilesX * tilesY * slices; }
};
ClusterGrid clusterGrid(uint32_t width, uint32_t height, CullingMode mode);

// What each culling pass reads and writes besides LightCulling's own buffers (bounds, lists, hits,
// tile masks): the frame's buffers by name. Every pass binds them by name too (culling_bindings.h).
struct BoundsInputs {
    const Buffer* frame = nullptr;       // FrameConstants (uniform)
    const Buffer* slices = nullptr;      // slice boundaries (sliceBoundaries)
    VkImageView depth = VK_NULL_HANDLE;  // SHADER_READ_ONLY_OPTIMAL
    VkImageView normal = VK_NULL_HANDLE; // likewise; read by the receiver variant only
    const Buffer* counters = nullptr;    // FrameCounters (atomics)
};
struct AssignInputs {
    const Buffer* frame = nullptr; // FrameConstants: mode (cluster.w) and visible lights (cluster.z)
    const Buffer* slices = nullptr;
    const Buffer* lights = nullptr; // visible GpuLights
    // The frame's wideCount WideLight entries (the lights with params.w = 1), whose footprints hold
    // wideThreads tiles in all.
    const Buffer* wideLights = nullptr;
    uint32_t wideCount = 0, wideThreads = 0;
    const Buffer* counters = nullptr; // FrameCounters (overflow atomics)
};
struct ViewInputs {
    const Buffer* frame = nullptr;
    const Buffer* slices = nullptr;
    const Buffer* lights = nullptr;
    VkImageView depth = VK_NULL_HANDLE;  // SHADER_READ_ONLY_OPTIMAL
    VkImageView output = VK_NULL_HANDLE; // RGBA8 storage, GENERAL: overwritten where there is a surface
    uint32_t width = 0, height = 0;
    bool reaching = false; // colour by lights reaching (else lights evaluated)
};

class LightCulling {
  public:
    Result<void> create(const Device& device);
    void destroy(const Device& device);
    // Sizes the cluster buffers for a grid; the pool holds ML_POOL_PER_CLUSTER entries per cluster
    // unless poolEntries overrides it (tests force overflow with a tiny pool). The cluster buffers are
    // GPU-only (device-local; tests read them with readBuffer).
    Result<void> resize(const Device& device, const ClusterGrid& grid, uint32_t poolEntries = 0);
    // Sizes viewCounts for recordView (a readback buffer); call before recording a light-count view.
    Result<void> prepareView(const Device& device, uint32_t width, uint32_t height);
    // The two passes of the frame, each under its timer: cluster bounds from the depth buffer, then
    // light assignment, whose mode and visible-light count are read from the frame constants
    // (a mapped upload buffer the module wrote just before; read back from it on the CPU).
    // With wantReceivers (and ensureReceivers called since the last resize) bounds also writes
    // `receivers` from the G-buffer normal (the receiver variant of cluster_bounds.comp); otherwise
    // the normal is bound but not read.
    static constexpr PassTimer kBoundsTimer{"cluster_bounds"};
    // Whether create() loaded the wave build of cluster_bounds.comp (subgroup reduction before the shared
    // atomics; the device has subgroup arithmetic and ML_BOUNDS_WAVE is not 0). Same output bit for bit.
    bool waveBounds() const { return waveBounds_; }
    void recordBounds(const Device& device, VkCommandBuffer cmd, const BoundsInputs& in);
    // Sizes `receivers` for the grid (32 B per cluster, only for page marking per cluster).
    Result<void> ensureReceivers(const Device& device);
    static constexpr PassTimer kAssignTimer{"light_assign"};
    void recordAssign(const Device& device, VkCommandBuffer cmd, const AssignInputs& in);
    // Light-complexity view (lights/view_lights.comp), after the evaluation pass: overwrites the
    // output's surface pixels with the heat colour of lights evaluated (or reaching) per pixel and
    // writes both counts to viewCounts (evaluated | reaching << 16, row-major).
    void recordView(const Device& device, VkCommandBuffer cmd, const ViewInputs& in);
    // Box tests (light x cluster) the last recorded assignment ran; valid once its frame completed.
    uint32_t lastBoxTests() const { return work.data ? *work.as<uint32_t>() : 0u; }

    ClusterGrid grid;
    uint32_t poolCapacity = 0;
    Buffer bounds;     // ClusterBounds per cluster
    Buffer ranges;     // uvec2 (offset, count) per cluster
    Buffer pool;       // uint light indices
    Buffer tileMasks;  // uvec2 per tile: bit s set when slice s holds a pixel
    Buffer counts;     // uint per cluster (footprint mode: list lengths)
    Buffer work;       // uint box tests run, uint hits recorded, uint tile-light cursor
    Buffer hits;       // uvec2 (cluster, light) per recorded hit (footprint mode)
    Buffer tileBits;   // ML_TILE_WORDS uint per tile: lights with a hit in the tile (footprint mode)
    Buffer tilePrefix; // ML_TILE_WORDS uint per tile: lights of the tile's earlier words
    Buffer tileRanges; // uvec2 (offset, count) per tile into tileSlices
    Buffer tileSlices; // uvec2 slice mask per (tile, light), in light order (hitCapacity entries)
    uint32_t hitCapacity = 0;
    Buffer viewCounts; // uint per pixel, written by recordView
    // Page marking per cluster (VsmSettings::clusterMarking) reads ClusterReceivers per cluster; the host
    // sets wantReceivers per frame.
    Buffer receivers;
    bool wantReceivers = false;

  private:
    ShaderModule boundsShader_, assignShader_, footprintShader_, allocShader_, fillShader_, viewShader_;
    Program boundsProgram_, receiversProgram_, assignProgram_, countProgram_, wideProgram_, allocProgram_;
    Program fillPrograms_[2]; // light_fill.comp's steps: mark, append
    bool waveBounds_ = false;
    Program viewPrograms_[2]; // evaluated, reaching
};

// Whether the host gives a visible light to the wide pass (directional lights, config.h): its footprint
// (lightFootprint with the frame's constants) when it is wide; the host writes it into the light's
// WideLight entry, so host and shader agree on its tiles exactly.
std::optional<gpu::LightFootprint> wideFootprint(const gpu::GpuLight& light,
                                                 const gpu::FrameConstants& frame);

// CPU reference of the passes from the same inputs (the depth buffer as floats, row-major). The mode
// is frame.cluster.w: in clustered (footprint) mode a cluster's list holds the lights whose footprint
// covers it and whose box test passes; in the brute-force modes every light whose box test passes.
struct ClusterReference {
    std::vector<gpu::ClusterBounds> bounds;
    std::vector<std::vector<uint32_t>> lists; // sorted light indices per cluster
};
ClusterReference cullReference(const std::vector<float>& depth, const gpu::FrameConstants& frame,
                               const std::vector<float>& sliceFar, const std::vector<gpu::GpuLight>& lights);

// cluster_bounds.comp's receiver variant: per cluster the receivers' world box and normal codes
// (shaders/shared/cluster_receivers.h), from the depth buffer and the G-buffer normals as stored
// (RGBA16F -> float, row-major). Bit for bit the GPU's.
std::vector<gpu::ClusterReceivers> cullReceiversReference(const std::vector<float>& depth,
                                                          const std::vector<glm::vec4>& normal,
                                                          const gpu::FrameConstants& frame,
                                                          const std::vector<float>& sliceFar);

// Slice of a linear depth, exactly as the shaders compute it.
uint32_t sliceOf(float z, const std::vector<float>& sliceFar, uint32_t slices);

} // namespace ml
