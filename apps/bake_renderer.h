// The renderer of the dual depth maps for the bake driver (bake, verify, bench static --need): the
// CPU rasteriser, or the Vulkan one of shadows/tools/gpu_dual_renderer.h on a device of its own.
#pragma once
#include "apps/cli.h"
#include "bake/bake.h"
#include "shadows/tools/gpu_dual_renderer.h"

#include <memory>

namespace ml {

// --renderer gpu (default) | cpu.
Result<BakeRenderer> parseRenderer(const cli::Args& args);

struct BakeRendering {
    std::unique_ptr<GpuDualRenderer> gpu; // held while `render` is in use; null for the CPU
    DualRenderFn render;
};

// The renderer of that kind: the GPU's device is made here (an error when there is none).
Result<BakeRendering> makeRendering(BakeRenderer kind);

} // namespace ml
