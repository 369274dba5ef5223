// The one evaluation pass (lights/evaluate.comp) and the optional statistics pass
// (lights/statistics.comp): per pixel, every light of its cluster list, static bake x virtual shadow
// map x shading; and the per-pixel light counts. The module's frame (engine/frame.h) records and times
// them in this order after culling and the virtual shadow map passes; both read the G-buffer and the
// cluster lists.
#pragma once
#include "gpu/pass_timer.h"
#include "gpu/program.h"

namespace ml {

// What the evaluation reads, by name; each is bound at its shader's named binding
// (lights/evaluate_bindings.h).
struct ShadingInputs {
    const Buffer* frame;  // FrameConstants (uniform)
    const Buffer* slices; // cluster slice boundaries
    const Buffer* lights; // visible GpuLights
    const Buffer* ranges; // cluster lists (culling/culling.h)
    const Buffer* pool;
    VkImageView depth, normal, albedo; // SHADER_READ_ONLY_OPTIMAL
    uint32_t width = 0, height = 0;
    // The evaluation's optional material target (RG8: roughness, metalness; SHADER_READ_ONLY_OPTIMAL):
    // set, it shades with GGX (shaders/shared/brdf.h); VK_NULL_HANDLE, with Lambert + Blinn-Phong.
    VkImageView material = VK_NULL_HANDLE;
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

// Which images the evaluation writes (shaders' kSpecOutput): the module-owned targets in LDR mode write
// both (tests read the HDR image), the others write only what is read, into a 1x1 stub on the other
// binding (a storage binding needs a valid image even when the shader never stores to it).
enum class EvaluateOutputs : uint32_t { Both = 0, HdrOnly = 1, ToneOnly = 2 };
constexpr uint32_t kEvaluateOutputModes = 3;

// What the evaluation writes: both views valid images in GENERAL, `hdr` RGBA16F and `output` RGBA8
// storage, written as `outputs` says.
struct EvaluateTargets {
    EvaluateOutputs outputs = EvaluateOutputs::Both;
    VkImageView hdr = VK_NULL_HANDLE;
    VkImageView output = VK_NULL_HANDLE;
};

// What the evaluation pass reads and writes, as it takes it (EvaluatePass::record). The buffers of
// `shading` and `shadows` are also the ones a host's own shaders bind (manylights/host_bindings.h).
struct EvaluateInputs {
    ShadingInputs shading;
    ShadowInputs shadows;
    EvaluateTargets targets;
};

class EvaluatePass {
  public:
    // Checks the device's subgroup support: with arithmetic subgroup operations in compute it loads the
    // build with the wave-uniform light loop (evaluate.comp's ML_WAVE_LOOP; kUniformLoop off unless the
    // environment has ML_UNIFORM_LOOP=1 or setUniformLoop(true)), without them the plain build, with a
    // line on stderr.
    Result<void> create(const Device& device);
    // The light loop: wave-uniform (true) or per lane; same image bit for bit. Returns whether the
    // choice took (false: the device has no subgroup arithmetic, the loop stays per lane). prepare()
    // builds the chosen variant.
    bool setUniformLoop(bool on);
    bool uniformLoop() const { return uniform_; }
    bool uniformLoopSupported() const { return waveBuild_; }
    void destroy(const Device& device);
    // Builds the mode's pipeline on first use (a mode switch costs one pipeline build, no device wait);
    // pbr: the GGX variant (kSpecPbr), which record() takes when ShadingInputs::material is set.
    Result<void> prepare(const Device& device, EvaluateOutputs outputs, bool pbr = false);
    // Writes in.targets; prepare(in.targets.outputs) must have run.
    static constexpr PassTimer kTimer{"evaluate"};
    void record(const Device& device, VkCommandBuffer cmd, const EvaluateInputs& in) const;

  private:
    uint32_t programIndex(EvaluateOutputs outputs, bool pbr) const {
        return (uint32_t(outputs) * 2 + pbr) * 2 + uniform_;
    }
    ShaderModule shader_;
    bool waveBuild_ = false, uniform_ = false;
    Program programs_[kEvaluateOutputModes * 2 * 2]; // [(mode * 2 + pbr) * 2 + uniform loop]
};

// What the statistics pass reads and writes, by name (its shader's ML_STATS_* bindings): the evaluation's
// cluster lists and depth, no shadows, and the frame's counters, which it adds to.
struct StatisticsInputs {
    const Buffer* frame;  // FrameConstants (uniform)
    const Buffer* slices; // cluster slice boundaries
    const Buffer* lights; // visible GpuLights
    const Buffer* ranges; // cluster lists (culling/culling.h)
    const Buffer* pool;
    VkImageView depth; // SHADER_READ_ONLY_OPTIMAL
    uint32_t width = 0, height = 0;
    const Buffer* counters; // FrameCounters: the per-pixel sums are added to its atomics
};

class StatisticsPass {
  public:
    Result<void> create(const Device& device);
    void destroy(const Device& device);
    // Adds the frame's per-pixel counts to `in.counters` (FrameCounters) and makes them visible to the host.
    static constexpr PassTimer kTimer{"statistics"};
    void record(const Device& device, VkCommandBuffer cmd, const StatisticsInputs& in) const;

  private:
    ShaderModule shader_;
    Program program_;
};

} // namespace ml
