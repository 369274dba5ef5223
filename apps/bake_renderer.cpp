#include "apps/bake_renderer.h"

namespace ml {

Result<BakeRenderer> parseRenderer(const cli::Args& args) {
    const std::string name = args.get("--renderer", "gpu");
    if (name != "gpu" && name != "cpu") return fail("--renderer: '" + name + "' is not gpu or cpu");
    return name == "gpu" ? BakeRenderer::Gpu : BakeRenderer::Cpu;
}

Result<BakeRendering> makeRendering(BakeRenderer kind) {
    BakeRendering r;
    r.render = cpuDualRenderer();
    if (kind == BakeRenderer::Cpu) return r;
    auto gpu = GpuDualRenderer::create();
    if (!gpu) return fail(gpu.error());
    r.gpu = std::move(gpu.value());
    GpuDualRenderer* p = r.gpu.get();
    // The Vulkan renderer is perspective only: orthographic (directional) maps use the CPU rasteriser.
    r.render = [p, cpu = r.render](const CasterTriangles& c, const LightFrustum& f, uint32_t res) {
        return f.orthographic() ? cpu(c, f, res) : p->render(c, f, res);
    };
    return r;
}

} // namespace ml
