// The module's frame as a list of passes (engine/frame.h), the frame loop that orders and times them, the
// untimed passes' barriers, and the features those passes record, created and destroyed together.
#include "engine/frame.h"

#include "gpu/vk_check.h"

namespace ml {

namespace {
constexpr auto C = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr auto R = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr auto W = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
} // namespace

Result<void> runFrame(Profiler& profiler, FrameContext& f, std::span<const FramePass> passes) {
    const VkCommandBuffer frameCmd = f.cmd;
    profiler.beginFrame(frameCmd, f.own.slot);
    for (const FramePass& pass : passes) {
        if (!pass.enabled) continue;
        auto body = [&](VkCommandBuffer c) {
            f.cmd = c;
            pass.record(f);
        };
        auto step = [&](const PassTimer& timer, const std::function<void(VkCommandBuffer)>& stepBody) {
            return profiler.run(frameCmd, timer, stepBody);
        };
        auto ran = pass.steps   ? pass.steps(f, step)
                   : pass.timer ? profiler.run(frameCmd, *pass.timer, body)
                                : profiler.runUntimed(frameCmd, body);
        f.cmd = frameCmd;
        // Only fenced runs can fail (their own command buffer or submission), and a timer the profiler
        // has no query pair for; the frame then stops there, its later passes unrecorded, and record()
        // returns the error.
        if (!ran) return ran;
    }
    profiler.endFrame(frameCmd); // the frame's completion, readable by the host without waiting
    return {};
}

namespace {

void recordFrameBegin(FrameContext& f) {
    // The frame boundary: the previous frame read and wrote the cluster buffers, the persistent VSM
    // state (page table, pool, owners, HPB: read-after-write across frames) and the targets this frame
    // rewrites (write-after-read), in every stage the module uses; later barriers of the frame chain
    // from this one. Only the module's stages and accesses: a host's other work (host reads, ray
    // tracing, video...) on a borrowed queue is not waited for. Host targets arrive already
    // transitioned by the host (HostTargets). Two frames recorded back to back show no hazard under
    // synchronization validation even without this barrier (the passes' own barriers chain across
    // the boundary; SyncValidation.TwoFramesInOneCommandBuffer); it stays for the host's commands
    // before record() that touch module-visible memory in these stages.
    const VkPipelineStageFlags2 frameStages =
        C | kFillStages | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT |
        VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_TASK_SHADER_BIT_EXT |
        VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT |
        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    const VkAccessFlags2 frameWrites = W | VK_ACCESS_2_TRANSFER_WRITE_BIT |
                                       VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    const VkAccessFlags2 frameAccesses =
        frameWrites | VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_UNIFORM_READ_BIT |
        VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT |
        VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
    // Setup first: new buffers' fills and grown buffers' copies (FrameSetup::record orders them among
    // themselves), then the staged uploads, whose destinations are new buffers or unread ranges; the
    // frame barrier below orders their transfer writes before every pass's reads.
    const FrameOwnInputs& own = f.own;
    if (own.setup) {
        own.setup->record(f.cmd, own.copies);
    } else {
        for (const StagedCopy& c : own.copies)
            vkCmdCopyBuffer(f.cmd, c.source, c.destination, uint32_t(c.regions.size()), c.regions.data());
    }
    memoryBarrier(f.cmd, frameStages, frameWrites, frameStages, frameAccesses);
    vkCmdFillBuffer(f.cmd, own.counters->buffer, 0, VK_WHOLE_SIZE, 0);
    memoryBarrier(f.cmd, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, C, R | W); // counters: clear -> atomics
}

void recordFrameEnd(FrameContext& f) {
    memoryBarrier(f.cmd, C, W, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT); // counters -> host
}

void recordEvaluationOutputs(FrameContext& f) {
    // The HDR and output images are rewritten whole: their old contents are discarded. Write-after-read
    // and write-after-write against the previous frame's evaluation and debug views (compute): its
    // storage writes are in the source scope, so the layout transition is ordered after them (two frames
    // in one command buffer: SyncValidation.TwoFramesInOneCommandBuffer). The host's reads of them
    // (copies, blits) reach the compute stage through the frame-begin barrier.
    for (const Image* image : {f.own.hdr, f.own.output})
        imageBarrier(f.cmd, image->image, image->aspect, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                     C, W, C, W);
}

bool debugViewOn(const FrameContext& f, const VirtualShadowMaps& vsm) {
    // The views write RGBA8 colours: none in HDR mode (the output is RGBA16F radiance).
    if (f.evaluate.targets.outputs == EvaluateOutputs::HdrOnly) return false;
    return (f.view == DebugView::Vsm && vsm.enabled()) || f.view == DebugView::LightsEvaluated ||
           f.view == DebugView::LightsReaching;
}

void recordDebugView(FrameContext& f, LightCulling& cull, const VsmPasses& vsmPasses) {
    if (f.view == DebugView::Vsm)
        vsmPasses.recordView(*f.device, f.cmd, f.vsm);
    else
        cull.recordView(*f.device, f.cmd, f.views);
}

} // namespace

Result<void> FrameFeatures::create(const Device& d, const VsmSettings& vsmSettings, uint32_t framesInFlight) {
    ML_TRY(gbuffer.create(d));
    ML_TRY(cull.create(d));
    ML_TRY(vsm.create(d, vsmSettings, framesInFlight));
    if (vsm.enabled()) ML_TRY(vsmPasses.create(d, vsm));
    ML_TRY(evaluate.create(d));
    return statistics.create(d);
}

void FrameFeatures::destroy(const Device& d) {
    gbuffer.destroy(d);
    cull.destroy(d);
    evaluate.destroy(d);
    statistics.destroy(d);
    vsmPasses.destroy(d); // before the state whose layouts and buffers it was made from
    vsm.destroy(d);
}

Result<void> recordFrame(Profiler& profiler, FrameContext& f, FrameFeatures& m) {
    const bool culling = f.culling != CullingMode::None;
    // The frame, in order: one entry a pass (its timer, whether it runs, what records it). A new compute
    // pass of a feature is one more entry here, its timer a constant beside the function that records it.
    const FramePass passes[] = {
        {nullptr, true, recordFrameBegin},                   // frame-begin barrier, counters cleared
        {&GBufferPass::kTimer, f.gbuffer.targets != nullptr, // module-owned targets only
         [&](FrameContext& c) { m.gbuffer.record(*c.device, c.cmd, c.gbuffer); }},
        {&LightCulling::kBoundsTimer, culling, // culling (mode None: skipped): cluster bounds,
         [&](FrameContext& c) { m.cull.recordBounds(*c.device, c.cmd, c.bounds); }},
        {&LightCulling::kAssignTimer, culling, // light lists
         [&](FrameContext& c) { m.cull.recordAssign(*c.device, c.cmd, c.assign); }},
        {nullptr, m.vsm.enabled(), // virtual shadow maps: per-frame clears,
         [&](FrameContext& c) { m.vsmPasses.recordReset(c.cmd); }},
        // then, with active maps, marked page to drawn page (a timer a step)
        {m.vsm.active(f.vsm.slot),
         [&](FrameContext& c, const VsmPasses::StepRunner& step) {
             return m.vsmPasses.recordPath(*c.device, c.vsm, step);
         }},
        {nullptr, true, recordEvaluationOutputs}, // HDR and output discarded
        {&EvaluatePass::kTimer, true,             // the one evaluation pass
         [&](FrameContext& c) { m.evaluate.record(*c.device, c.cmd, c.evaluate); }},
        {nullptr, m.vsm.probing(), // optional lookup probe
         [&](FrameContext& c) { m.vsmPasses.recordProbe(*c.device, c.cmd, c.vsm); }},
        {&StatisticsPass::kTimer, f.statistics, // optional per-pixel light counts
         [&](FrameContext& c) { m.statistics.record(*c.device, c.cmd, c.stats); }},
        {nullptr, debugViewOn(f, m.vsm), // --view lights / lights-reaching / vsm
         [&](FrameContext& c) { recordDebugView(c, m.cull, m.vsmPasses); }},
        {nullptr, !f.statistics, recordFrameEnd}, // counters -> host, unless the statistics pass did it
    };
    return runFrame(profiler, f, passes);
}

} // namespace ml
