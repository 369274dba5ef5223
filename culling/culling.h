// Light culling: clustered (froxels) and tiled, in two compute passes, with a CPU reference.
//
//   cluster_bounds  one group per 8x8-pixel tile (ML_TILE_SIZE): each pixel with geometry goes to its
//                   depth slice (exponential slices, sliceBoundaries); the world AABB of the pixels in each
//                   (tile, slice) is reduced exactly with integer min/max. Empty clusters are marked.
//   light_assign    one group per tile: every visible light is tested against each occupied cluster
//                   (exact range-sphere vs AABB, cone vs the AABB's bounding sphere), counted,
//                   allocated from one pool, written. Overflowing clusters are flagged and counted.
// Tiled mode is the same with one slice (the tile's AABB over all its pixels); "none" skips both.
// Tight bounds from the actual pixels (rather than the froxel's frustum volume) is what keeps lights
// evaluated per pixel close to lights that reach it (Olsson et al.'s clustered shading with
// explicit bounds; the slice layout follows the exponential scheme of that paper).
#pragma once
#include "engine/manylights.h"
#include "engine/program.h"
#include "shaders/shared/gpu_types.h"

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

class LightCulling {
  public:
    void create(const Device& device);
    void destroy(const Device& device);
    // Sizes the cluster buffers for a grid; the pool holds ML_POOL_PER_CLUSTER entries per cluster
    // unless poolEntries overrides it (tests force overflow with a tiny pool).
    void resize(const Device& device, const ClusterGrid& grid, uint32_t poolEntries = 0);
    void record(const Device& device, VkCommandBuffer cmd, const Buffer& frame, const Buffer& slices,
                const Buffer& lights, VkImageView depth, const Buffer& counters, class Profiler& profiler);

    ClusterGrid grid;
    uint32_t poolCapacity = 0;
    Buffer bounds; // ClusterBounds per cluster
    Buffer ranges; // uvec2 (offset, count) per cluster
    Buffer pool;   // uint light indices

  private:
    ShaderModule boundsShader_, assignShader_;
    Program boundsProgram_, assignProgram_;
};

// CPU reference of both passes from the same inputs (the depth buffer as floats, row-major).
struct ClusterReference {
    std::vector<gpu::ClusterBounds> bounds;
    std::vector<std::vector<uint32_t>> lists; // sorted light indices per cluster
};
ClusterReference cullReference(const std::vector<float>& depth, const gpu::FrameConstants& frame,
                               const std::vector<float>& sliceFar, const std::vector<gpu::GpuLight>& lights);

// Slice of a linear depth, exactly as the shaders compute it.
uint32_t sliceOf(float z, const std::vector<float>& sliceFar, uint32_t slices);

} // namespace ml
