// G-buffer raster pass (module-owned targets): depth D32, world normal RGBA16F (w: shadow receiver, 1 or
// ML_NOT_A_RECEIVER), albedo RGBA8, material RG8 (perceptual roughness, metalness). One
// indexed indirect multi-draw over all instances; vertices are pulled from a storage buffer.
#pragma once
#include "gpu/pass_timer.h"
#include "gpu/program.h"

namespace ml {

struct GBufferTargets {
    Image depth, normal, albedo, material;
};

// What the G-buffer draw reads and writes: the frame's constants and the scene's geometry, by name (each
// bound at gbuffer.vert's named binding, engine/gbuffer_bindings.h), and the targets it draws.
struct GBufferInputs {
    // The module's own G-buffer; null where the host draws its own (setTargets): the pass does not run.
    const GBufferTargets* targets = nullptr;
    const Buffer* frame = nullptr;     // FrameConstants (uniform)
    const Buffer* vertices = nullptr;  // GpuVertex, pulled by index
    const Buffer* indices = nullptr;   // uint32 indices
    const Buffer* instances = nullptr; // GpuInstance per instance
    const Buffer* draws = nullptr;     // VkDrawIndexedIndirectCommand per instance
    uint32_t drawCount = 0;
};

class GBufferPass {
  public:
    static constexpr PassTimer kTimer{"gbuffer"}; // record()
    Result<void> create(const Device& device);
    void destroy(const Device& device);
    // On failure `out` holds what was made (destroy each image).
    Result<void> createTargets(const Device& device, uint32_t width, uint32_t height,
                               GBufferTargets& out) const;
    // Draws in.targets (set), leaving depth, normal, albedo and material in SHADER_READ_ONLY_OPTIMAL.
    void record(const Device& device, VkCommandBuffer cmd, const GBufferInputs& in) const;

  private:
    ShaderModule vs_, fs_;
    Program program_;
};

} // namespace ml
