// The virtual shadow map passes of a frame (vsm.h has the algorithm), one function per pass; the module's
// frame (engine/frame.h) orders and times them. Every barrier names the hazard it orders; the frame-begin
// barrier (engine/frame.cpp) orders this frame's first writes after the previous frame's reads.
#include "shadows/virtual/vsm_passes.h"

#include <algorithm>
#include <cstddef>

namespace ml {

namespace {
constexpr auto C = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr auto R = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr auto W = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
constexpr auto kIndirect = VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
constexpr auto kTask = VK_PIPELINE_STAGE_2_TASK_SHADER_BIT_EXT;
Descriptor sampled(VkImageView view) {
    return Descriptor(Image{.view = view}, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}
} // namespace

Result<void> VsmPasses::create(const Device& device, const VirtualShadowMaps& state) {
    state_ = &state;
    return programs_.create(device, state.meshPath());
}

void VsmPasses::destroy(const Device& device) {
    programs_.destroy(device);
}

void VsmPasses::recordReset(VkCommandBuffer c) const {
    const VsmPages& pg = state_->pages();
    // Per-frame state: marks, dirty-mip flags, draw counts (the frame-begin barrier ordered these clears
    // after the previous frame's reads).
    const size_t usedEntries = size_t(state_->mapsInUse()) * state_->layout().entriesPerMap;
    const VkDeviceSize used = std::max<VkDeviceSize>((usedEntries + 31) / 32 * 4, 4);
    vkCmdFillBuffer(c, pg.marks.buffer, 0, used, 0);
    vkCmdFillBuffer(c, pg.marks.buffer, VkDeviceSize(state_->layout().markWords) * 4, used, 0);
    vkCmdFillBuffer(c, pg.dirtyMips.buffer, 0, std::max<VkDeviceSize>(state_->mapsInUse() * 4u, 4), 0);
    vkCmdFillBuffer(c, pg.drawCounts.buffer, 0, VK_WHOLE_SIZE, 0);
    if (state_->meshPath()) vkCmdFillBuffer(c, pg.meshTasks.buffer, 0, VK_WHOLE_SIZE, 0); // no task groups
    // Cleared marks, flags and counts -> the passes' atomics and the indirect draws' counts.
    memoryBarrier(c, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, C | kIndirect,
                  R | W | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
}

void VsmPasses::recordMark(const Device& d, VkCommandBuffer c, uint32_t slotIndex,
                           const VsmFrameInputs& in) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const auto* fc = in.frame->as<gpu::FrameConstants>();
    dispatch(d, c, programs_.mark, fc->size.x, fc->size.y, NoPush{},
             {*in.frame, *in.slices, *in.lights, *in.ranges, *in.pool, sampled(in.depth), sampled(in.normal),
              slot.constants, slot.maps, slot.coverage, pg.marks});
    memoryBarrier(c, C, W, C, R); // marks -> scan, alloc, assign
}

void VsmPasses::recordAlloc(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const uint64_t blocks = (uint64_t(slot.orderEntries) + ML_VSM_BLOCK - 1) / ML_VSM_BLOCK;
    // One workgroup per block, in rows of at most maxComputeWorkGroupCount[0] (vsmBlockIndex).
    const GroupGrid grid = linearGroupGrid(blocks, d.properties.limits.maxComputeWorkGroupCount[0]);
    dispatch(d, c, programs_.scan, grid.x * ML_VSM_BLOCK, grid.y, NoPush{},
             {slot.constants, slot.runs, slot.maps, slot.stale, pg.table, pg.marks, pg.lastUsed,
              pg.blockCounts, slot.counters});
    memoryBarrier(c, C, W, C, R | W); // table, last use, block counts -> alloc, assign
    dispatch(d, c, programs_.alloc, ML_VSM_BLOCK, 1, NoPush{},
             {slot.constants, slot.runs, pg.marks, pg.owners, pg.lastUsed, pg.blockCounts, pg.avail,
              slot.counters});
    memoryBarrier(c, C, W, C, R | W); // block ranks, avail list -> assign
    dispatch(d, c, programs_.assign, grid.x * ML_VSM_BLOCK, grid.y, NoPush{},
             {slot.constants, slot.runs, pg.table, pg.marks, pg.owners, pg.lastUsed, pg.blockCounts, pg.avail,
              pg.rendered, pg.dirtyMips, slot.counters});
    // Page table (DIRTY), dirty mips, rendered list and the clear's dispatch size -> HPB, cull, clear.
    memoryBarrier(c, C, W, C | kIndirect, R | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
}

void VsmPasses::recordHpb(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    // Rewritten whole for the maps read this frame: the previous frame's contents are discarded, after
    // its reads (culling: compute; mesh path: task shaders). Level 1 also binds mip 0 as its source
    // (never read there, but a storage read for the validation layer): reads and writes follow.
    firstUseBarrier(c, pg.hpb, VK_IMAGE_LAYOUT_GENERAL, C | kTask, 0, C, R | W);
    for (uint32_t level = 1; level <= state_->layout().hpbLevels; ++level) {
        const uint32_t mip = level - 1;
        // A thread per texel of the level, one group layer per active map.
        dispatch(d, c, programs_.hpb, pg.hpb.mipWidth(mip), pg.hpb.mipHeight(mip), slot.activeCount,
                 gpu::VsmHpbPush{level, slot.activeCount},
                 {slot.constants, slot.active, pg.table, Descriptor(pg.hpb.mipView(level > 1 ? mip - 1 : 0)),
                  Descriptor(pg.hpb.mipView(mip))});
        // Level l -> level l + 1 (storage reads) and the culling's fetches (sampled reads).
        imageBarrier(c, pg.hpb, mip, 1, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL, C, W, C | kTask,
                     R | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    }
}

void VsmPasses::recordCull(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const gpu::VsmCullPush push{slot.casterCount, slot.activeCount, state_->settings().maxDrawsPerMip};
    dispatch(d, c, programs_.cull, slot.casterCount, slot.activeCount, push,
             {slot.constants, slot.maps, slot.active, pg.table, Descriptor(pg.hpb.view), slot.casters,
              pg.dirtyMips, pg.draws, pg.drawInfo, pg.drawCounts, slot.counters});
    // Draw lists and counts -> indirect draws; draw info -> vertex shader.
    memoryBarrier(c, C, W, kIndirect | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
                  VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | R);
}

void VsmPasses::recordExpand(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const gpu::VsmCullPush push{slot.casterCount, slot.activeCount, state_->settings().maxMeshletsPerMip};
    dispatch(d, c, programs_.expand, slot.casterCount, slot.activeCount, push,
             {slot.constants, slot.maps, slot.active, pg.table, Descriptor(pg.hpb.view), slot.casters,
              pg.dirtyMips, pg.meshletList, pg.meshTasks, slot.counters});
    // Task counts -> indirect draws; lists, and the page table and HPB (written by earlier compute
    // passes) -> task and mesh shaders.
    memoryBarrier(c, C, W, kIndirect | kTask | VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT,
                  VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | R);
}

void VsmPasses::recordDraw(const Device& d, VkCommandBuffer c, uint32_t slotIndex,
                           const VsmFrameInputs& in) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    // One group per rendered page: vsm_assign counted them into the dispatch size.
    dispatchIndirect(d, c, programs_.clear, slot.counters, offsetof(gpu::VsmCounters, dispatchX), NoPush{},
                     {slot.constants, pg.rendered, pg.pool});
    memoryBarrier(c, C, W, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, R | W); // cleared pages -> atomic min
    for (uint32_t m = 0; m < state_->layout().mips; ++m) {
        const uint32_t res = state_->settings().resolution >> m;
        beginAttachmentless(c, res, {res, res});
        const gpu::VsmDrawPush push{m, state_->settings().maxMeshletsPerMip};
        if (state_->meshPath()) {
            // Spot and point maps of every light at this mip, and at mip 0 every directional clip level.
            bindProgram(d, c, programs_.mesh, push,
                        {*in.vertices, *in.instances, pg.meshletList, slot.maps, slot.constants, pg.table,
                         pg.pool, *in.meshlets, *in.meshletVertices, *in.meshletTriangles,
                         Descriptor(pg.hpb.view), pg.meshTasks, slot.counters});
            d.cmdDrawMeshTasksIndirect(c, pg.meshTasks.buffer, VkDeviceSize(m) * 16, 1, 16);
        } else {
            bindProgram(
                d, c, programs_.draw, push,
                {*in.vertices, *in.instances, pg.drawInfo, slot.maps, slot.constants, pg.table, pg.pool});
            vkCmdBindIndexBuffer(c, in.indices->buffer, 0, VK_INDEX_TYPE_UINT32);
            vkCmdDrawIndexedIndirectCount(
                c, pg.draws.buffer,
                VkDeviceSize(m) * state_->settings().maxDrawsPerMip * sizeof(VkDrawIndexedIndirectCommand),
                pg.drawCounts.buffer, VkDeviceSize(m) * 4, state_->settings().maxDrawsPerMip,
                sizeof(VkDrawIndexedIndirectCommand));
        }
        vkCmdEndRendering(c);
    }
    // Physical pages -> the evaluation pass's lookups.
    memoryBarrier(c, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, W, C, R);
}

void VsmPasses::recordProbe(const Device& d, VkCommandBuffer cmd, uint32_t slotIndex,
                            const VsmFrameInputs& in) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const auto* fc = in.frame->as<gpu::FrameConstants>();
    dispatch(d, cmd, programs_.probe, fc->size.x, fc->size.y, NoPush{},
             {*in.frame, *in.slices, *in.lights, *in.ranges, *in.pool, sampled(in.depth), sampled(in.normal),
              slot.constants, slot.maps, slot.coverage, pg.table, pg.pool, slot.probes});
    memoryBarrier(cmd, C, W, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT); // probes -> host
}

void VsmPasses::recordView(const Device& d, VkCommandBuffer cmd, uint32_t slotIndex, const VsmFrameInputs& in,
                           VkImageView output) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const auto* fc = in.frame->as<gpu::FrameConstants>();
    // The evaluation pass's output -> read and overwritten here.
    memoryBarrier(cmd, C, W, C, R | W);
    dispatch(d, cmd, programs_.view, fc->size.x, fc->size.y, NoPush{},
             {*in.frame, *in.slices, *in.lights, *in.ranges, *in.pool, sampled(in.depth), sampled(in.normal),
              slot.constants, slot.maps, slot.coverage, pg.table, pg.pool,
              Descriptor(Image{.view = output})});
    // The view's output -> the host's reads after record().
    memoryBarrier(cmd, C, W, kOutputReaderStages, kOutputReads);
}

} // namespace ml
