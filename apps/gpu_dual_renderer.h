// The Vulkan dual depth renderer (shadows/tools/gpu_dual_renderer.h, its own device) as a DualRenderFn
// for the bake driver: used by bake / verify and bench static --need.
#pragma once
#include "bake/bake.h"
#include "shadows/tools/gpu_dual_renderer.h"

#include <memory>

namespace ml {

struct GpuRendererFn {
    std::unique_ptr<GpuDualRenderer> renderer;
    Result<DualRenderFn> make() {
        auto r = GpuDualRenderer::create();
        if (!r) return fail(r.error());
        renderer = std::move(r.value());
        GpuDualRenderer* p = renderer.get();
        // The Vulkan renderer is perspective only: orthographic (directional) maps use the CPU rasteriser.
        return DualRenderFn(
            [p, cpu = cpuDualRenderer()](const CasterTriangles& c, const LightFrustum& f, uint32_t res) {
                return f.orthographic() ? cpu(c, f, res) : p->render(c, f, res);
            });
    }
};

} // namespace ml
