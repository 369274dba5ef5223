// Z-binning (Drobot, "Improved culling for tiled and clustered rendering", SIGGRAPH 2017), built to be
// measured beside the footprint clusters (culling.h; docs/culling.md "Z-binning side by side"). The
// evaluation pass does not consume it: what it gives is the assignment cost and the lights a pixel
// would evaluate, against the clusters' (bench culling --compare-zbin).
//
//   host (zbinPrepare)  each visible light's footprint (lightFootprint, the clusters' own); lights off
//                       screen are dropped, wide (directional) ones kept apart and evaluated everywhere;
//                       the others sorted by the middle of their depth range. Sorted index i is bit i.
//   zbin_mask           per ML_TILE_SIZE^2 tile a bitmask over the sorted lights (ceil(N / 32) words):
//                       each light rasterises its footprint's tile rectangle; with depthTest also only
//                       into tiles whose occupied cluster slices (cluster_bounds' tile masks) meet its
//                       depth range, which needs the bounds pass first.
//   zbin_bins           ML_ZBIN_BINS bins linear in view depth over [near, farthest light's far]; bin b
//                       holds the (min, max) sorted index of the lights whose depth range overlaps it.
//   zbin_stats          per pixel: lights evaluated (its tile's bits within its bin's [min, max], plus
//                       the wide lights) and, of those, lights that reach its point.
// A pixel's lights are a superset of the lights reaching it (every step is conservative), so the
// stats' reaching sum equals statistics.comp's brute-force one; the tests check that and the CPU
// reference (zbinReference) bit for bit.
#pragma once
#include "culling/zbin_types.h"
#include "gpu/program.h"
#include "shaders/shared/gpu_types.h"

#include <vector>

namespace ml {

// The host's part of a frame: the sorted list, the wide lights' visible indices and the push block.
struct ZBinFrame {
    gpu::ZBinPush push{};
    std::vector<gpu::ZBinLight> sorted;
    std::vector<uint32_t> wide;
};
// frame: the frame's constants (viewProj, size, tile size, near and far); sliceFar: the cluster slices'
// far boundaries (sliceBoundaries) for the depth test's slice masks; lights: the visible lights.
ZBinFrame zbinPrepare(const gpu::FrameConstants& frame, const std::vector<float>& sliceFar,
                      const std::vector<gpu::GpuLight>& lights, bool depthTest);

// CPU reference of the two passes: masks (tilesX * tilesY * push.words words) and bins (ML_ZBIN_BINS
// packed min | max << 16). tileSlices: per tile the occupied slices (cluster_bounds' tile masks), read
// only with push.depthTest.
struct ZBinReference {
    std::vector<uint32_t> masks, bins;
};
ZBinReference zbinReference(const ZBinFrame& zf, const gpu::FrameConstants& frame,
                            const std::vector<glm::uvec2>& tileSlices);

// Sums over the pixels with geometry: lights evaluated, of those the ones reaching the point, pixels;
// the tile's lights at any depth, and the evaluated lights whose own bin range holds the pixel's bin
// (exact per-light depth ranges: the rest of `evaluated` is the (min, max) range's false positives).
// The wide lights count in every sum but surface.
struct ZBinStats {
    uint64_t evaluated = 0, reaching = 0, surface = 0, tile = 0, exact = 0;
};
// The stats pass on the CPU from the reference's masks and bins (depth: the D32 values, row-major).
ZBinStats zbinStatsReference(const ZBinFrame& zf, const ZBinReference& ref, const std::vector<float>& depth,
                             const gpu::FrameConstants& frame, const std::vector<gpu::GpuLight>& lights);

class ZBinning {
  public:
    Result<void> create(const Device& device);
    void destroy(const Device& device);
    // Copies the frame (sorted list, wide list, constants, visible lights) into mapped buffers and sizes
    // the masks; the host must have waited for earlier Z-bin passes.
    Result<void> prepare(const Device& device, const ZBinFrame& zf, const gpu::FrameConstants& frame,
                         const std::vector<gpu::GpuLight>& lights);
    // Clear and rasterise the masks. tileSlices: cluster_bounds' tile masks (LightCulling::tileMasks),
    // bound always, read with depthTest.
    void recordMasks(const Device& device, VkCommandBuffer cmd, const Buffer& tileSlices);
    void recordBins(const Device& device, VkCommandBuffer cmd);
    // After both: the per-pixel statistics from the depth image (SHADER_READ_ONLY_OPTIMAL).
    void recordStats(const Device& device, VkCommandBuffer cmd, VkImageView depth);
    ZBinStats stats() const; // the last completed stats pass (mapped readback)
    // Shading-loop probe (zbin_shade.comp): shadeLight summed over each pixel's candidates, from the
    // frame's cluster lists (ranges, pool: LightCulling's) or (zbin) from the Z-bins; prepare() must have
    // had the frame's sliceFar (prepareSlices).
    void recordShade(const Device& device, VkCommandBuffer cmd, bool zbin, VkImageView depth,
                     VkImageView normal, const Buffer& ranges, const Buffer& pool);
    Result<void> prepareSlices(const Device& device, const std::vector<float>& sliceFar);

    gpu::ZBinPush push{};
    Buffer sorted, wide, frame, lights, slices; // mapped uploads
    Buffer masks, bins;                         // GPU-only (tests read them with readBuffer)
    Buffer statsBuffer;                         // readback: ZBinStats as uint64s
    Buffer shaded;                              // the shading probe's vec4 per pixel (GPU-only)
    uint32_t tiles = 0;

  private:
    ShaderModule maskShader_, binShader_, statsShader_, shadeShader_;
    Program maskProgram_, binProgram_, statsProgram_, shadePrograms_[2]; // shade: clusters, Z-bins
};

} // namespace ml
