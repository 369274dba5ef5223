// shadows/tools/: the GPU tools of the static shadow commands (`bake`, `bench static`), a library of its own
// (manylights_shadow_tools; built with ML_BUILD_TOOLS, not installed). They build on the engine's base
// layer (device, programs, resources) and on shadows/gpu/, so apps/ need not: their headers expose no
// Vulkan wrapper class, and apps/ include only them (the test PublicApiIncludes checks apps/ and host/).
//
// GpuDualRenderer: the Vulkan dual depth renderer (shadows/gpu/dual_depth_gpu.h) on a device of its own,
// for commands that bake without a module (bake) or beside one (bench static).
#pragma once
#include "manylights/result.h"
#include "shadows/static/raster_dual.h"

#include <functional>
#include <memory>
#include <string>

namespace ml {

class GpuDualRenderer {
  public:
    // Makes its own device (validation when ML_VALIDATION=1).
    static Result<std::unique_ptr<GpuDualRenderer>> create();
    ~GpuDualRenderer();
    // Perspective frusta only (shadows/gpu/dual_depth_gpu.h); `progress` gets the fraction of tiles done.
    Result<DualDepthMap> render(const CasterTriangles& casters, const LightFrustum& frustum,
                                uint32_t resolution, uint32_t maxTile = 4096,
                                const std::function<void(float)>& progress = {});
    // "gpu: NAME, driver D, vendor V, device I": recorded in bake parts (another driver may rasterise
    // differently).
    std::string deviceDescription() const;

  private:
    struct State;
    explicit GpuDualRenderer(std::unique_ptr<State> s);
    std::unique_ptr<State> s_;
};

} // namespace ml
