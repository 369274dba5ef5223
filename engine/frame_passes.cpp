// The pass objects of the module's frame (engine/frame.h) and the frame loop that orders and times them.
#include "engine/frame.h"

namespace ml {

namespace {
constexpr auto C = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr auto R = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr auto W = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
} // namespace

std::vector<std::string> passTimerNames() {
    std::vector<std::string> names;
    for (uint32_t p = 0; p < kPassCount; ++p) names.emplace_back(passName(Pass(p)));
    return names;
}

Result<void> runFrame(Profiler& profiler, FrameContext& f, std::span<FramePass* const> passes) {
    const VkCommandBuffer frameCmd = f.cmd;
    profiler.beginFrame(frameCmd, f.slot);
    for (FramePass* pass : passes) {
        if (!pass->enabled(f)) continue;
        // Only fenced runs can fail (their own command buffer or submission); the frame then stops
        // there, its later passes unrecorded, and record() returns the error.
        if (auto ran = pass->run(profiler, f); !ran) return ran;
    }
    profiler.endFrame(frameCmd); // the frame's completion, readable by the host without waiting
    return {};
}

Result<void> FramePass::run(Profiler& profiler, FrameContext& f) {
    const VkCommandBuffer frameCmd = f.cmd;
    auto body = [&](VkCommandBuffer c) {
        f.cmd = c;
        record(f);
    };
    auto ran =
        timer() ? profiler.run(frameCmd, uint32_t(*timer()), body) : profiler.runUntimed(frameCmd, body);
    f.cmd = frameCmd;
    return ran;
}

void FrameBeginPass::record(FrameContext& f) {
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
    if (f.setup) {
        f.setup->record(f.cmd, f.copies);
    } else {
        for (const StagedCopy& c : f.copies)
            vkCmdCopyBuffer(f.cmd, c.source, c.destination, uint32_t(c.regions.size()), c.regions.data());
    }
    memoryBarrier(f.cmd, frameStages, frameWrites, frameStages, frameAccesses);
    vkCmdFillBuffer(f.cmd, f.counters->buffer, 0, VK_WHOLE_SIZE, 0);
    memoryBarrier(f.cmd, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, C, R | W); // counters: clear -> atomics
}

void FrameEndPass::record(FrameContext& f) {
    memoryBarrier(f.cmd, C, W, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT); // counters -> host
}

void GBufferDrawPass::record(FrameContext& f) {
    gbuffer.record(*f.device, f.cmd, *f.gbuffer, f.geometry);
}

void ClusterBoundsPass::record(FrameContext& f) {
    cull.recordBounds(*f.device, f.cmd, f.bounds);
}

void LightAssignPass::record(FrameContext& f) {
    cull.recordAssign(*f.device, f.cmd, f.assign);
}

void VsmResetPass::record(FrameContext& f) {
    passes.recordReset(f.cmd);
}

void VsmPathPass::record(FrameContext& f) {
    // Every step straight into the frame's command buffer (run() times each instead); nothing here can
    // fail, since only a fenced run has a submission of its own.
    (void)passes.recordPath(*f.device, f.slot, f.vsm,
                            [&](Pass, const std::function<void(VkCommandBuffer)>& body) -> Result<void> {
                                body(f.cmd);
                                return {};
                            });
}

Result<void> VsmPathPass::run(Profiler& profiler, FrameContext& f) {
    const VkCommandBuffer frameCmd = f.cmd;
    return passes.recordPath(*f.device, f.slot, f.vsm,
                             [&](Pass timer, const std::function<void(VkCommandBuffer)>& body) {
                                 return profiler.run(frameCmd, uint32_t(timer), body);
                             });
}

void EvaluationOutputsPass::record(FrameContext& f) {
    // The HDR and output images are rewritten whole: their old contents are discarded. Write-after-read
    // and write-after-write against the previous frame's evaluation and debug views (compute): its
    // storage writes are in the source scope, so the layout transition is ordered after them (two frames
    // in one command buffer: SyncValidation.TwoFramesInOneCommandBuffer). The host's reads of them
    // (copies, blits) reach the compute stage through the frame-begin barrier.
    imageBarrier(f.cmd, f.hdrImage->image, f.hdrImage->aspect, VK_IMAGE_LAYOUT_UNDEFINED,
                 VK_IMAGE_LAYOUT_GENERAL, C, W, C, W);
    imageBarrier(f.cmd, f.outputImage->image, f.outputImage->aspect, VK_IMAGE_LAYOUT_UNDEFINED,
                 VK_IMAGE_LAYOUT_GENERAL, C, W, C, W);
}

void EvaluationPass::record(FrameContext& f) {
    evaluate.record(*f.device, f.cmd, f.shading, f.shadows, f.evaluation);
}

void VsmProbePass::record(FrameContext& f) {
    passes.recordProbe(*f.device, f.cmd, f.slot, f.vsm);
}

void StatisticsFramePass::record(FrameContext& f) {
    statistics.record(*f.device, f.cmd, f.shading, *f.counters);
}

bool DebugViewPass::enabled(const FrameContext& f) const {
    // The views write RGBA8 colours: none in HDR mode (the output is RGBA16F radiance).
    if (f.hdrOutput) return false;
    return (f.view == DebugView::Vsm && vsm.enabled()) || f.view == DebugView::LightsEvaluated ||
           f.view == DebugView::LightsReaching;
}

void DebugViewPass::record(FrameContext& f) {
    if (f.view == DebugView::Vsm)
        passes.recordView(*f.device, f.cmd, f.slot, f.vsm, f.output);
    else
        cull.recordView(*f.device, f.cmd,
                        {f.shading.frame, f.shading.slices, f.shading.lights, f.shading.depth, f.output,
                         f.shading.width, f.shading.height, f.view == DebugView::LightsReaching});
}

} // namespace ml
