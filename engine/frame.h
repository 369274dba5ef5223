// The module's frame as a list of pass objects (Module::record): every pass has one interface,
// record(FrameContext&), and says whether it runs this frame and under which Pass timer. The frame loop
// (runFrame) is the one place that times passes: a timed pass is recorded between its timestamps, or in
// Fenced mode submitted on its own and timed; an untimed one (barriers, clears, probes, views) is only
// kept in order with them. Passes wrap the features (culling/, shadows/virtual/, lights/, engine/gbuffer),
// which record commands and know nothing of the profiler or of this list.
//
// Order (each pass's barriers order its hazards; the frame-begin barrier orders the frame after the
// previous one): frame begin, G-buffer (module targets only), cluster bounds, light assignment (culling on),
// VSM reset / mark / sort / alloc / HPB / group cull / cull or expand / draw, evaluation outputs, evaluation,
// VSM probe, statistics, debug view, frame end.
#pragma once
#include "culling/culling.h"
#include "engine/gbuffer.h"
#include "manylights/manylights.h"
#include "gpu/profiler.h"
#include "lights/evaluate_pass.h"
#include "shadows/virtual/vsm_passes.h"

#include <optional>
#include <span>
#include <vector>

namespace ml {

// What the passes of one frame read and write, as named fields (filled by Module::record).
// StagedCopy (gpu/resources.h): a host-to-GPU copy recorded at the frame's start (FrameBeginPass):
// load-time data (meshes, static shadow words) written into a staging buffer reaches its GPU-only buffer
// without a host wait, ordered before every pass by the frame barrier. Destinations are new buffers or
// ranges no frame has read.

struct FrameContext {
    const Device* device = nullptr;
    VkCommandBuffer cmd = VK_NULL_HANDLE; // the current pass's (its own one when timing is Fenced)
    uint32_t slot = 0;                    // frame-in-flight index of the per-slot buffers
    CullingMode culling = CullingMode::Clustered;
    bool statistics = false;
    DebugView view = DebugView::Shaded;
    bool hdrOutput = false; // the host's output takes HDR radiance (no tone-mapped output, no views)

    // Targets. gbuffer: the module's own G-buffer (it draws it), null for the host's. The G-buffer views
    // (in `shading`) are SHADER_READ_ONLY_OPTIMAL in the compute passes; hdr and output are rewritten
    // whole each frame.
    const GBufferTargets* gbuffer = nullptr;
    const Image* hdrImage = nullptr;     // the module's: full-size (own targets) or a 1x1 stub
    const Image* outputImage = nullptr;  // likewise (the host's output arrives GENERAL)
    VkImageView output = VK_NULL_HANDLE; // the debug views' target
    const Buffer* counters = nullptr;    // FrameCounters (atomics; read by the host one frame later)
    std::span<const StagedCopy> copies;  // recorded first, by FrameBeginPass
    const FrameSetup* setup = nullptr;   // fills and copies queued while the frame was prepared (first too)

    // What each feature's pass reads and writes, by name: the slot's buffers (written by the host just
    // before), the geometry, the cluster lists and the G-buffer views, grouped as each pass takes them.
    GBufferInputs geometry{};
    BoundsInputs bounds{};
    AssignInputs assign{};
    ShadingInputs shading{}; // evaluation, statistics and the light-count views
    ShadowInputs shadows{};
    EvaluateTargets evaluation{};
    VsmFrameInputs vsm{};
};

class FramePass {
  public:
    explicit FramePass(std::optional<Pass> timer = std::nullopt) : timer_(timer) {}
    virtual ~FramePass() = default;
    // The Pass it is timed as (FrameReport::times), none for untimed work.
    std::optional<Pass> timer() const { return timer_; }
    virtual bool enabled(const FrameContext&) const { return true; }
    virtual void record(FrameContext& frame) = 0;
    // Records the pass under its timer (or untimed) into the frame's command buffer, or a fenced run's
    // own; a pass of several timed steps times each step instead.
    virtual Result<void> run(Profiler& profiler, FrameContext& frame);

  private:
    std::optional<Pass> timer_;
};

// Records the enabled passes in order, timing each under its Pass (or untimed).
Result<void> runFrame(Profiler& profiler, FrameContext& frame, std::span<FramePass* const> passes);
// The profiler's timer names: one per Pass, in enum order.
std::vector<std::string> passTimerNames();

// --- the passes (engine/frame_passes.cpp) ---

// Frame boundary: orders this frame's accesses after the previous frame's, and clears the counters.
struct FrameBeginPass final : FramePass {
    void record(FrameContext& f) override;
};
// Counters -> host, unless the statistics pass did it.
struct FrameEndPass final : FramePass {
    bool enabled(const FrameContext& f) const override { return !f.statistics; }
    void record(FrameContext& f) override;
};
struct GBufferDrawPass final : FramePass {
    explicit GBufferDrawPass(const GBufferPass& g) : FramePass(Pass::GBuffer), gbuffer(g) {}
    bool enabled(const FrameContext& f) const override { return f.gbuffer != nullptr; }
    void record(FrameContext& f) override;
    const GBufferPass& gbuffer;
};
// Cluster bounds, then light assignment into the cluster lists (culling on).
struct ClusterBoundsPass final : FramePass {
    explicit ClusterBoundsPass(LightCulling& c) : FramePass(Pass::ClusterBounds), cull(c) {}
    bool enabled(const FrameContext& f) const override { return f.culling != CullingMode::None; }
    void record(FrameContext& f) override;
    LightCulling& cull;
};
struct LightAssignPass final : FramePass {
    explicit LightAssignPass(LightCulling& c) : FramePass(Pass::LightAssign), cull(c) {}
    bool enabled(const FrameContext& f) const override { return f.culling != CullingMode::None; }
    void record(FrameContext& f) override;
    LightCulling& cull;
};
// The virtual shadow maps' per-frame clears (untimed, VSM on).
struct VsmResetPass final : FramePass {
    VsmResetPass(const VirtualShadowMaps& v, const VsmPasses& p) : vsm(v), passes(p) {}
    bool enabled(const FrameContext&) const override { return vsm.enabled(); }
    void record(FrameContext& f) override;
    const VirtualShadowMaps& vsm;
    const VsmPasses& passes;
};
// The VSM's path from marked page to drawn page (VsmPasses::recordPath), while the slot has active maps:
// each step under the timer recordPath names for it.
struct VsmPathPass final : FramePass {
    VsmPathPass(const VirtualShadowMaps& v, const VsmPasses& p) : vsm(v), passes(p) {}
    bool enabled(const FrameContext& f) const override { return vsm.active(f.slot); }
    void record(FrameContext& f) override; // the steps untimed
    Result<void> run(Profiler& profiler, FrameContext& f) override;
    const VirtualShadowMaps& vsm;
    const VsmPasses& passes;
};
// The evaluation's HDR and output images: old contents discarded (layout transition), ordered after
// the previous frame's writes.
struct EvaluationOutputsPass final : FramePass {
    void record(FrameContext& f) override;
};
struct EvaluationPass final : FramePass {
    explicit EvaluationPass(const EvaluatePass& e) : FramePass(Pass::Evaluate), evaluate(e) {}
    void record(FrameContext& f) override;
    const EvaluatePass& evaluate;
};
struct VsmProbePass final : FramePass {
    VsmProbePass(const VirtualShadowMaps& v, const VsmPasses& p) : vsm(v), passes(p) {}
    bool enabled(const FrameContext&) const override { return vsm.probing(); }
    void record(FrameContext& f) override;
    const VirtualShadowMaps& vsm;
    const VsmPasses& passes;
};
struct StatisticsFramePass final : FramePass {
    explicit StatisticsFramePass(const StatisticsPass& s) : FramePass(Pass::Statistics), statistics(s) {}
    bool enabled(const FrameContext& f) const override { return f.statistics; }
    void record(FrameContext& f) override;
    const StatisticsPass& statistics;
};
// demo --view: the VSM page view, or the light-complexity views (culling/culling.h), over the output.
struct DebugViewPass final : FramePass {
    DebugViewPass(LightCulling& c, const VirtualShadowMaps& v, const VsmPasses& p)
        : cull(c), vsm(v), passes(p) {}
    bool enabled(const FrameContext& f) const override;
    void record(FrameContext& f) override;
    LightCulling& cull;
    const VirtualShadowMaps& vsm;
    const VsmPasses& passes;
};

// Every pass object of the module, built once over its features; each timed pass names its timer here
// or in its class, once.
struct FramePasses {
    FramePasses(const GBufferPass& g, LightCulling& c, const VirtualShadowMaps& v, const VsmPasses& vp,
                const EvaluatePass& e, const StatisticsPass& s)
        : gbuffer(g), clusterBounds(c), lightAssign(c), vsmReset(v, vp), vsmPath(v, vp), evaluate(e),
          vsmProbe(v, vp), statistics(s), debugView(c, v, vp) {}
    FrameBeginPass begin;
    GBufferDrawPass gbuffer;
    ClusterBoundsPass clusterBounds;
    LightAssignPass lightAssign;
    VsmResetPass vsmReset;
    VsmPathPass vsmPath;
    EvaluationOutputsPass evaluationOutputs;
    EvaluationPass evaluate;
    VsmProbePass vsmProbe;
    StatisticsFramePass statistics;
    DebugViewPass debugView;
    FrameEndPass end;
};

} // namespace ml
