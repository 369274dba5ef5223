// The module's frame as a list of passes (recordFrame, engine/frame_passes.cpp; Module::record runs it):
// each entry says what records the pass, whether it runs this frame and under which timer. The frame
// loop (runFrame) is the one place that times passes: a timed pass is recorded between its timestamps,
// or in Fenced mode submitted on its own and timed; an untimed one (barriers, clears, probes, views) is
// only kept in order with them. The features (culling/, shadows/virtual/, lights/, engine/gbuffer)
// record commands and declare their passes' timers (gpu/pass_timer.h); they know nothing of the
// profiler or of this list.
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

#include <functional>
#include <span>

namespace ml {

// What the frame's own passes (frame begin, evaluation outputs, frame end; engine/frame_passes.cpp) read
// and write, and the slot the frame is timed in.
// StagedCopy (gpu/resources.h): a host-to-GPU copy recorded at the frame's start (its first pass):
// load-time data (meshes, static shadow words) written into a staging buffer reaches its GPU-only buffer
// without a host wait, ordered before every pass by the frame barrier. Destinations are new buffers or
// ranges no frame has read.
struct FrameOwnInputs {
    uint32_t slot = 0;                  // frame-in-flight index: the profiler's query pairs for this frame
    const Buffer* counters = nullptr;   // FrameCounters: cleared at the frame's begin (atomics; the host
                                        // reads them one frame later)
    std::span<const StagedCopy> copies; // recorded first, by the frame-begin pass
    const FrameSetup* setup = nullptr;  // fills and copies queued while the frame was prepared (first too)
    // Rewritten whole each frame, so discarded (UNDEFINED -> GENERAL) before the evaluation. The module's
    // images: full-size with its own targets; with the host's, a 1x1 image never written, kept so the
    // outputs barrier and the evaluation's descriptors always have an image (engine/module_targets.cpp).
    // The host's output arrives GENERAL and is not transitioned here.
    const Image* hdr = nullptr;
    const Image* output = nullptr;
};

// What the passes of one frame read and write (filled by Module::Impl::frameContext,
// engine/frame_write.cpp): which passes run, and one input struct per pass, each naming its resources by
// field. A resource is named in the struct of every pass that binds it and nowhere else here, so a pass
// that needs a new input adds a field to its own struct (and the line that fills it), not to this one.
struct FrameContext {
    const Device* device = nullptr;
    VkCommandBuffer cmd = VK_NULL_HANDLE; // the current pass's (its own one when timing is Fenced)

    // Which passes run (recordFrame's switches, with what the structs say: the G-buffer pass runs when
    // gbuffer.targets is set, the VSM path when the state has active maps for vsm.slot, no debug view
    // when evaluate.targets.outputs is HdrOnly).
    CullingMode culling = CullingMode::Clustered;
    bool statistics = false;
    DebugView view = DebugView::Shaded;

    FrameOwnInputs own{};
    GBufferInputs gbuffer{}; // the module's own G-buffer draw
    BoundsInputs bounds{};
    AssignInputs assign{};
    VsmFrameInputs vsm{};
    EvaluateInputs evaluate{}; // (and the host include's bindings, engine/host_shader.cpp)
    StatisticsInputs stats{};  // the optional statistics pass (`statistics` says whether it runs)
    ViewInputs views{};        // the light-count views (the VSM page view's target is vsm.viewOutput)
};

// One entry of the frame's list (recordFrame, engine/frame_passes.cpp): what records the pass, whether it
// runs this frame, and the timer it runs under (the feature's constant, declared beside the function
// that records the pass; none for barriers, clears, probes and views).
struct FramePass {
    using Record = std::function<void(FrameContext&)>; // into frame.cmd
    // A pass of several timed steps (the VSM path): hands each step to `step`, under the step's own timer.
    using Steps = std::function<Result<void>(FrameContext&, const VsmPasses::StepRunner& step)>;
    FramePass(const PassTimer* t, bool on, Record r) : timer(t), enabled(on), record(std::move(r)) {}
    FramePass(bool on, Steps s) : enabled(on), steps(std::move(s)) {}
    const PassTimer* timer = nullptr;
    bool enabled = true;
    Record record;
    Steps steps;
};

// Records the enabled passes in order, each under its timer (or untimed).
Result<void> runFrame(Profiler& profiler, FrameContext& frame, std::span<const FramePass> passes);

// The features whose passes the frame records, owned here (one per module, Module::Impl::features) and
// created and destroyed together (engine/frame_passes.cpp, beside the list that records them): a new
// feature is one member here, its lines in create and destroy, and its entries in recordFrame's list.
struct FrameFeatures {
    GBufferPass gbuffer;
    LightCulling cull;
    VirtualShadowMaps vsm; // state: settings, map slots, page tables, pool; its passes are vsmPasses
    VsmPasses vsmPasses;   // created only when the VSM is enabled
    EvaluatePass evaluate;
    StatisticsPass statistics;

    // In this order; out of memory returns the error, what was made left for destroy (every destroy
    // takes empty handles).
    Result<void> create(const Device& device, const VsmSettings& vsmSettings, uint32_t framesInFlight);
    void destroy(const Device& device); // the device idle
};

// The module's frame: its list of passes, in order, run by runFrame.
Result<void> recordFrame(Profiler& profiler, FrameContext& frame, FrameFeatures& features);

} // namespace ml
