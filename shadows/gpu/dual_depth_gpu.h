// Dual depth maps rendered with Vulkan (the bake's renderer; shadows/static/raster_dual.h is its CPU
// reference). The map is rendered in tiles of at most 4096x4096 texels, each tile with its own
// projection, so any resolution up to 64K^2 bakes with tile-sized images: only the assembled
// DualDepthMap (8 bytes per texel) grows with the resolution.
//
// Per tile three raster passes over the light's caster triangles write R32_UINT storage images with
// atomics (shadows/gpu/dual_depth.frag): enter (nearest surface), a closed-entry mark, exit (nearest closed
// back face behind enter). Depth is the light-view distance, quantised like quantizeDepth but in float
// (staticQuantize, shaders/static/static_pcf.h), so it differs from the CPU reference's double
// path by a few units of 2^-32 of the range; coverage follows Vulkan's rasterisation rules at texel
// centres, like the CPU reference's.
#pragma once
#include "gpu/program.h"
#include "shadows/static/raster_dual.h"

#include <functional>

namespace ml {

class DualDepthRenderer {
  public:
    static Result<std::unique_ptr<DualDepthRenderer>> create(const Device& device);
    ~DualDepthRenderer();
    // Renders the whole map; `progress` (may be empty) gets the fraction of tiles done.
    Result<DualDepthMap> render(const CasterTriangles& casters, const LightFrustum& frustum,
                                uint32_t resolution, uint32_t maxTile = 4096,
                                const std::function<void(float)>& progress = {});

  private:
    explicit DualDepthRenderer(const Device& device) : device_(device) {}
    const Device& device_;
    ShaderModule vs_, fs_;
    Program passes_[3];
    Buffer vertices_, readback_;
    Image enter_, closed_, exit_;
    uint32_t tile_ = 0;
};

} // namespace ml
