// The Vulkan dual depth renderer (shadows/gpu/dual_depth_gpu.h) as a DualRenderFn for the bake driver;
// owns its device. Used by bake / verify and bench static --need.
#pragma once
#include "shadows/gpu/dual_depth_gpu.h"
#include "shadows/static/bake.h"

#include <memory>

namespace ml {

struct GpuDualRenderer {
    std::unique_ptr<Device> device;
    std::unique_ptr<DualDepthRenderer> renderer;
    Result<DualRenderFn> make() {
        auto d = Device::create({});
        if (!d) return fail(d.error());
        device = std::move(d.value());
        auto r = DualDepthRenderer::create(*device);
        if (!r) return fail(r.error());
        renderer = std::move(r.value());
        DualDepthRenderer* p = renderer.get();
        // The Vulkan renderer is perspective only: orthographic (directional) maps use the CPU rasteriser.
        return DualRenderFn(
            [p, cpu = cpuDualRenderer()](const CasterTriangles& c, const LightFrustum& f, uint32_t res) {
                return f.orthographic() ? cpu(c, f, res) : p->render(c, f, res);
            });
    }
    ~GpuDualRenderer() {
        renderer.reset(); // before the device it was created on
    }
};

} // namespace ml
