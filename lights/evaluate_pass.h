// The one evaluation pass (shaders/evaluate.comp) and the optional statistics pass
// (shaders/statistics.comp): per pixel, every light of its cluster list, static bake x virtual shadow
// map x shading; and the per-pixel light counts. The module's frame (engine/frame.h) records and times
// them in this order after culling and the virtual shadow map passes; both read the G-buffer and the
// cluster lists.
#pragma once
#include "gpu/program.h"

namespace ml {

// What both passes read, in the shaders' binding order.
struct ShadingInputs {
    const Buffer* frame;  // FrameConstants (uniform)
    const Buffer* slices; // cluster slice boundaries
    const Buffer* lights; // visible GpuLights
    const Buffer* ranges; // cluster lists (culling/culling.h)
    const Buffer* pool;
    VkImageView depth, normal, albedo; // SHADER_READ_ONLY_OPTIMAL
    uint32_t width = 0, height = 0;
};
// Static bakes and virtual shadow maps (vsm_common.glsl's buffers; any valid buffers when VSM is off).
struct ShadowInputs {
    const Buffer* staticWords;
    const Buffer* shadowRecords;
    const Buffer* vsmConstants; // uniform
    const Buffer* vsmMaps;
    const Buffer* vsmCoverage;
    const Buffer* vsmTable;
    const Buffer* vsmPool;
};

class EvaluatePass {
  public:
    // hdrOnly: the pass writes HDR radiance only (the host tone-maps); else HDR and the tone-mapped output.
    Result<void> create(const Device& device, bool hdrOnly);
    void destroy(const Device& device);
    // Writes `hdr` (RGBA16F storage, GENERAL) and, unless hdrOnly, `output` (RGBA8 storage, GENERAL).
    void record(const Device& device, VkCommandBuffer cmd, const ShadingInputs& in,
                const ShadowInputs& shadows, VkImageView hdr, VkImageView output) const;

  private:
    ShaderModule shader_;
    Program program_;
};

class StatisticsPass {
  public:
    Result<void> create(const Device& device);
    void destroy(const Device& device);
    // Adds the frame's per-pixel counts to `counters` (FrameCounters) and makes them visible to the host.
    void record(const Device& device, VkCommandBuffer cmd, const ShadingInputs& in,
                const Buffer& counters) const;

  private:
    ShaderModule shader_;
    Program program_;
};

} // namespace ml
