// The virtual shadow map passes of a frame (vsm.h has the algorithm), one function per pass; recordPath
// puts them in order and names each step's timer, the module's frame (engine/frame.h) runs the timers.
// Every barrier names the hazard it orders; the frame-begin barrier (engine/frame_passes.cpp) orders this
// frame's first writes after the previous frame's reads.
#include "shadows/virtual/vsm_passes.h"

#include "gpu/bindings.h"
#include "shadows/virtual/vsm_alloc_bindings.h"
#include "shadows/virtual/vsm_bindings.h"

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>

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

namespace {
// vsm_allocate_short_list's shared memory: the keys, vsmBlockScan3's rows and their totals (uvec3 at a
// 16-byte stride, as a device may lay them out), four words: 20,752 bytes at 4,096 keys.
constexpr uint32_t kShortListSharedBytes = ML_VSM_ONE_GROUP_LIST * 4 + ML_VSM_BLOCK * 16 + 16 * 16 + 16;

// The longest list one workgroup allocates on this device: 0 where it lacks the workgroup's shared
// memory or invocations; ML_VSM_ALLOC_SHORT_LIST=N (0..ML_VSM_ONE_GROUP_LIST) lowers it (tests, benches).
Result<uint32_t> deviceShortListLimit(const Device& d) {
    const VkPhysicalDeviceLimits& l = d.properties.limits;
    const bool fits = l.maxComputeSharedMemorySize >= kShortListSharedBytes &&
                      l.maxComputeWorkGroupInvocations >= ML_VSM_BLOCK &&
                      l.maxComputeWorkGroupSize[0] >= ML_VSM_BLOCK;
    uint32_t limit = fits ? ML_VSM_ONE_GROUP_LIST : 0u;
    const char* env = std::getenv("ML_VSM_ALLOC_SHORT_LIST");
    if (!env || !*env) return limit;
    char* end = nullptr;
    const unsigned long v = std::strtoul(env, &end, 10);
    if (*end != '\0' || v > ML_VSM_ONE_GROUP_LIST)
        return fail(
            "ML_VSM_ALLOC_SHORT_LIST must be 0.." + std::to_string(ML_VSM_ONE_GROUP_LIST) +
            " (the longest request list one workgroup allocates; 0: the multi-dispatch passes alone)");
    return std::min(limit, uint32_t(v));
}
} // namespace

Result<void> VsmPasses::create(const Device& device, const VirtualShadowMaps& state) {
    state_ = &state;
    auto limit = deviceShortListLimit(device);
    if (!limit) return fail(limit.error());
    shortList_ = limit.value();
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
    // Marks: a memset of mapsInUse x entries / 8 bytes per region (the passes then walk the request
    // list); the HPB bits of the maps in use likewise (vsm_hpb sets them).
    for (VkDeviceSize region = 0; region < 3; ++region)
        vkCmdFillBuffer(c, pg.marks.buffer, region * state_->layout().markWords * 4, used, 0);
    vkCmdFillBuffer(
        c, pg.hpb.buffer, 0,
        std::max<VkDeviceSize>(VkDeviceSize(state_->mapsInUse()) * state_->layout().hpbWords * 4, 4), 0);
    vkCmdFillBuffer(c, pg.dirtyMips.buffer, 0, std::max<VkDeviceSize>(state_->mapsInUse() * 4u, 4), 0);
    vkCmdFillBuffer(c, pg.drawCounts.buffer, 0, VK_WHOLE_SIZE, 0);
    if (state_->meshPath()) vkCmdFillBuffer(c, pg.meshTasks.buffer, 0, VK_WHOLE_SIZE, 0); // no task groups
    // Cleared marks, flags and counts -> the passes' atomics and the indirect draws' counts.
    memoryBarrier(c, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, C | kIndirect,
                  R | W | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
}

void VsmPasses::recordMark(const Device& d, VkCommandBuffer c, const VsmFrameInputs& in) const {
    const VsmSlot& slot = state_->slot(in.slot);
    const VsmPages& pg = state_->pages();
    const auto* fc = in.frame->as<gpu::FrameConstants>();
    // Per cluster where the frame has cluster bounds and lists of ML_TILE_SIZE tiles (the clustered
    // modes); per pixel for `none` and `tiled`, and when the setting is off.
    const bool clustered = fc->cluster.w == ML_CULL_CLUSTERED || fc->cluster.w == ML_CULL_CLUSTERED_BRUTE;
    if (state_->settings().clusterMarking && clustered && fc->cluster.y == ML_TILE_SIZE &&
        in.clusterReceivers && in.tileMasks)
        dispatch(d, c, programs_.markCluster, fc->size.z * ML_VSM_CLUSTER_LANES, fc->size.w,
                 NoPush{}, // a workgroup per tile
                 {ML_BIND(ML_VSM_MARK_FRAME, *in.frame), ML_BIND(ML_VSM_MARK_SLICES, *in.slices),
                  ML_BIND(ML_VSM_MARK_LIGHTS, *in.lights), ML_BIND(ML_VSM_MARK_RANGES, *in.ranges),
                  ML_BIND(ML_VSM_MARK_LIGHT_POOL, *in.pool), ML_BIND(ML_VSM_MARK_DEPTH, sampled(in.depth)),
                  ML_BIND(ML_VSM_MARK_NORMAL, sampled(in.normal)),
                  ML_BIND(ML_VSM_MARK_CONSTANTS, slot.constants), ML_BIND(ML_VSM_MARK_MAPS, slot.maps),
                  ML_BIND(ML_VSM_MARK_COVERAGE, slot.coverage), ML_BIND(ML_VSM_MARK_MARKS, pg.marks),
                  ML_BIND(ML_VSM_MARK_COUNTERS, slot.counters), ML_BIND(ML_VSM_MARK_RANK_BASE, slot.rankBase),
                  ML_BIND(ML_VSM_MARK_REQUESTS, pg.list[0]),
                  ML_BIND(ML_VSM_MARK_RECEIVERS, *in.clusterReceivers),
                  ML_BIND(ML_VSM_MARK_TILE_MASKS, *in.tileMasks)});
    else
        dispatch(d, c, programs_.mark, fc->size.x, fc->size.y, NoPush{},
                 {ML_BIND(ML_VSM_MARK_FRAME, *in.frame), ML_BIND(ML_VSM_MARK_SLICES, *in.slices),
                  ML_BIND(ML_VSM_MARK_LIGHTS, *in.lights), ML_BIND(ML_VSM_MARK_RANGES, *in.ranges),
                  ML_BIND(ML_VSM_MARK_LIGHT_POOL, *in.pool), ML_BIND(ML_VSM_MARK_DEPTH, sampled(in.depth)),
                  ML_BIND(ML_VSM_MARK_NORMAL, sampled(in.normal)),
                  ML_BIND(ML_VSM_MARK_CONSTANTS, slot.constants), ML_BIND(ML_VSM_MARK_MAPS, slot.maps),
                  ML_BIND(ML_VSM_MARK_COVERAGE, slot.coverage), ML_BIND(ML_VSM_MARK_MARKS, pg.marks),
                  ML_BIND(ML_VSM_MARK_COUNTERS, slot.counters), ML_BIND(ML_VSM_MARK_RANK_BASE, slot.rankBase),
                  ML_BIND(ML_VSM_MARK_REQUESTS, pg.list[0])});
    memoryBarrier(c, C, W, C, R | W); // marks, request list and its count -> the allocation passes
}

namespace {
// Between the sort and allocation passes: each reads or writes the counters (atomics) and the next may
// take its dispatch size from them, so each barrier orders compute writes before compute reads, writes
// and indirect reads.
void nextAllocationPass(VkCommandBuffer c) {
    memoryBarrier(c, C, W, C | kIndirect, R | W | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
}
} // namespace

bool VsmPasses::oneWorkgroupOnly(uint32_t slotIndex) const {
    if (shortList_ == 0 || sequence_ == Sequence::Both) return false;
    // The list's length grows and shrinks with the view, a few hundred entries a frame on the drive path,
    // so the slot's last frame predicts this one's path; a miss past the limit costs one slow frame.
    return sequence_ == Sequence::OneWorkgroup || state_->slot(slotIndex).listBefore <= shortList_;
}

void VsmPasses::recordSort(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const bool alone = oneWorkgroupOnly(slotIndex);
    if (shortList_ != 0) {
        // A list of at most shortList_ entries: closed, sorted and allocated here in one workgroup, and
        // the passes below get 0 groups; a longer one: closed here, the passes below allocate it. Alone
        // (no passes below recorded), any list is allocated here.
        const uint32_t limit = shortList_ | (alone ? ML_VSM_ANY_LENGTH : 0u);
        dispatch(d, c, programs_.allocateShortList, ML_VSM_BLOCK, 1, gpu::VsmSortPush{pg.mergePasses, limit},
                 {ML_BIND(ML_VSM_SHORT_CONSTANTS, slot.constants), ML_BIND(ML_VSM_SHORT_RUNS, slot.runs),
                  ML_BIND(ML_VSM_SHORT_COUNTERS, slot.counters), ML_BIND(ML_VSM_SHORT_REQUESTS, pg.list[0]),
                  ML_BIND(ML_VSM_SHORT_SORTED, pg.list[1]), ML_BIND(ML_VSM_SHORT_SORT_ARGS, pg.sortArgs),
                  ML_BIND(ML_VSM_SHORT_MAPS, slot.maps), ML_BIND(ML_VSM_SHORT_STALE, slot.stale),
                  ML_BIND(ML_VSM_SHORT_TABLE, pg.table), ML_BIND(ML_VSM_SHORT_MARKS, pg.marks),
                  ML_BIND(ML_VSM_SHORT_OWNERS, pg.owners), ML_BIND(ML_VSM_SHORT_LAST_USED, pg.lastUsed),
                  ML_BIND(ML_VSM_SHORT_AVAIL, pg.avail), ML_BIND(ML_VSM_SHORT_RENDERED, pg.rendered),
                  ML_BIND(ML_VSM_SHORT_DIRTY_MIPS, pg.dirtyMips),
                  ML_BIND(ML_VSM_SHORT_DIRTY_MAPS, pg.dirtyMaps), ML_BIND(ML_VSM_SHORT_HPB, pg.hpb)});
        // Short: the table, owners, rendered list, dirty maps, counters -> vsm_hpb and the culling (here
        // when recorded alone, else through the barriers below); long: the list's count and every pass's
        // dispatch size -> indirect reads.
        nextAllocationPass(c);
        if (alone) return;
    } else {
        // The list's count and the sort's dispatch sizes.
        dispatch(d, c, programs_.list, 1, 1, gpu::VsmSortPush{pg.mergePasses, 0},
                 {ML_BIND(ML_VSM_LIST_CONSTANTS, slot.constants),
                  ML_BIND(ML_VSM_LIST_COUNTERS, slot.counters), ML_BIND(ML_VSM_LIST_SORT_ARGS, pg.sortArgs),
                  ML_BIND(ML_VSM_LIST_OWNERS, pg.owners)});
        // The list's count and the owned pages -> the sort's and allocation's dispatch sizes and reads.
        nextAllocationPass(c);
    }
    // Block sort list[0] -> list[1], then merges of 8 runs each (the run width x8 per pass), alternating;
    // vsm_list gave the merges past the list's length no groups (an empty dispatch).
    for (uint32_t pass = 0; pass <= pg.mergePasses; ++pass) {
        const uint32_t width =
            pass == 0 ? 0u : uint32_t(ML_VSM_BLOCK) << (ML_VSM_MERGE_WAYS_LOG2 * (pass - 1));
        const Buffer& src = pg.list[pass % 2];
        const Buffer& dst = pg.list[(pass + 1) % 2];
        dispatchIndirect(d, c, programs_.sort, pg.sortArgs, 4 * (ML_VSM_ARGS_SORT + 3 * VkDeviceSize(pass)),
                         gpu::VsmSortPush{width, 0},
                         {ML_BIND(ML_VSM_SORT_COUNTERS, slot.counters), ML_BIND(ML_VSM_SORT_SRC, src),
                          ML_BIND(ML_VSM_SORT_DST, dst)});
        // This pass's runs -> the next pass; after the last, the sorted list -> the allocation's scan
        // and assignment (and its counters' reads -> vsm_scan's atomics: write-after-read).
        nextAllocationPass(c);
    }
}

void VsmPasses::recordAlloc(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    if (oneWorkgroupOnly(slotIndex)) return; // vsm_allocate_short_list allocated the list (recordSort)
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    // Every pass indirect from sortArgs (words in vsm_types.h): vsm_list or vsm_allocate_short_list sized
    // them (0 groups after a list one workgroup allocated), pool passes to the owned pages only.
    auto at = [](uint32_t word) { return VkDeviceSize(word) * 4; };
    // Invalidation and class counts of the owned pages, and the sorted list's LRU refresh and requests: one
    // dispatch (vsm_scan.comp's two parts are independent). The invalidation needs neither the sorted list
    // nor the sort its results, but runs after the sort (recordSort), which keeps the sort one timed scope.
    dispatchIndirect(
        d, c, programs_.scan, pg.sortArgs, at(ML_VSM_ARGS_SCAN), NoPush{},
        {ML_BIND(ML_VSM_SCAN_CONSTANTS, slot.constants), ML_BIND(ML_VSM_SCAN_RUNS, slot.runs),
         ML_BIND(ML_VSM_SCAN_COUNTERS, slot.counters), ML_BIND(ML_VSM_SCAN_LIST_A, pg.list[0]),
         ML_BIND(ML_VSM_SCAN_TABLE, pg.table), ML_BIND(ML_VSM_SCAN_MARKS, pg.marks),
         ML_BIND(ML_VSM_SCAN_LAST_USED, pg.lastUsed), ML_BIND(ML_VSM_SCAN_BLOCK_COUNTS, pg.blockCounts),
         ML_BIND(ML_VSM_SCAN_LIST_B, pg.list[1]), ML_BIND(ML_VSM_SCAN_SORT_ARGS, pg.sortArgs),
         ML_BIND(ML_VSM_SCAN_MAPS, slot.maps), ML_BIND(ML_VSM_SCAN_STALE, slot.stale),
         ML_BIND(ML_VSM_SCAN_OWNERS, pg.owners), ML_BIND(ML_VSM_SCAN_CLASS_COUNTS, pg.classCounts)});
    // Table, class counts, block counts, last use, counters -> alloc, avail, assign.
    nextAllocationPass(c);
    dispatchIndirect(
        d, c, programs_.alloc, pg.sortArgs, at(ML_VSM_ARGS_ALLOC), NoPush{},
        {ML_BIND(ML_VSM_ALLOC_CONSTANTS, slot.constants), ML_BIND(ML_VSM_ALLOC_COUNTERS, slot.counters),
         ML_BIND(ML_VSM_ALLOC_BLOCK_COUNTS, pg.blockCounts),
         ML_BIND(ML_VSM_ALLOC_CLASS_COUNTS, pg.classCounts), ML_BIND(ML_VSM_ALLOC_SORT_ARGS, pg.sortArgs)});
    // Block ranks, class bases, counters -> avail, assign; vsm_avail's dispatch size -> indirect read.
    nextAllocationPass(c);
    // 0 groups unless some request must evict (vsm_alloc): free pages need no list.
    dispatchIndirect(d, c, programs_.avail, pg.sortArgs, at(ML_VSM_ARGS_AVAIL), NoPush{},
                     {ML_BIND(ML_VSM_AVAIL_CONSTANTS, slot.constants), ML_BIND(ML_VSM_AVAIL_MARKS, pg.marks),
                      ML_BIND(ML_VSM_AVAIL_OWNERS, pg.owners), ML_BIND(ML_VSM_AVAIL_LAST_USED, pg.lastUsed),
                      ML_BIND(ML_VSM_AVAIL_CLASS_BASES, pg.classCounts),
                      ML_BIND(ML_VSM_AVAIL_AVAIL, pg.avail), ML_BIND(ML_VSM_AVAIL_COUNTERS, slot.counters)});
    nextAllocationPass(c); // the available-page list -> assign
    dispatchIndirect(
        d, c, programs_.assign, pg.sortArgs, at(ML_VSM_ARGS_ASSIGN), NoPush{},
        {ML_BIND(ML_VSM_ASSIGN_CONSTANTS, slot.constants), ML_BIND(ML_VSM_ASSIGN_RUNS, slot.runs),
         ML_BIND(ML_VSM_ASSIGN_COUNTERS, slot.counters), ML_BIND(ML_VSM_ASSIGN_LIST_A, pg.list[0]),
         ML_BIND(ML_VSM_ASSIGN_TABLE, pg.table), ML_BIND(ML_VSM_ASSIGN_MARKS, pg.marks),
         ML_BIND(ML_VSM_ASSIGN_OWNERS, pg.owners), ML_BIND(ML_VSM_ASSIGN_LAST_USED, pg.lastUsed),
         ML_BIND(ML_VSM_ASSIGN_BLOCK_RANKS, pg.blockCounts), ML_BIND(ML_VSM_ASSIGN_AVAIL, pg.avail),
         ML_BIND(ML_VSM_ASSIGN_RENDERED, pg.rendered), ML_BIND(ML_VSM_ASSIGN_DIRTY_MIPS, pg.dirtyMips),
         ML_BIND(ML_VSM_ASSIGN_DIRTY_MAPS, pg.dirtyMaps), ML_BIND(ML_VSM_ASSIGN_LIST_B, pg.list[1]),
         ML_BIND(ML_VSM_ASSIGN_SORT_ARGS, pg.sortArgs)});
    // Page table (DIRTY), dirty mips and maps, rendered list, the clear's and the culling's dispatch
    // sizes -> HPB, group culling, cull, clear.
    nextAllocationPass(c); // (the culling passes add to the counters too)
}

void VsmPasses::recordHpb(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    // One thread per listed (wanted) entry; the bits were cleared at the frame's start (recordReset).
    // vsm_allocate_short_list set them where it ran alone (recordSort): no dispatch then, the barrier stays.
    if (!oneWorkgroupOnly(slotIndex))
        dispatchIndirect(d, c, programs_.hpb, slot.counters, offsetof(gpu::VsmCounters, listGroupsX),
                         NoPush{},
                         {ML_BIND(ML_VSM_HPB_CONSTANTS, slot.constants), ML_BIND(ML_VSM_HPB_RUNS, slot.runs),
                          ML_BIND(ML_VSM_HPB_COUNTERS, slot.counters), ML_BIND(ML_VSM_HPB_LIST_A, pg.list[0]),
                          ML_BIND(ML_VSM_HPB_TABLE, pg.table), ML_BIND(ML_VSM_HPB_MARKS, pg.marks),
                          ML_BIND(ML_VSM_HPB_HPB, pg.hpb), ML_BIND(ML_VSM_HPB_LIST_B, pg.list[1]),
                          ML_BIND(ML_VSM_HPB_SORT_ARGS, pg.sortArgs)});
    // HPB bits -> the culling's reads (compute; mesh path: task shaders).
    memoryBarrier(c, C, W, C | kTask, R);
}

void VsmPasses::recordGroupCull(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    // Group bounds: one thread per ML_VSM_CULL_GROUP casters of the culling order.
    const uint32_t groups = (slot.casterCount + ML_VSM_CULL_GROUP - 1) / ML_VSM_CULL_GROUP;
    dispatch(d, c, programs_.groups, groups, 1, gpu::VsmCullPush{slot.casterCount, 0},
             {ML_BIND(ML_VSM_GROUPS_CASTERS, slot.casters), ML_BIND(ML_VSM_GROUPS_ORDER, slot.casterOrder),
              ML_BIND(ML_VSM_GROUPS_GROUPS, slot.casterGroups)});
    memoryBarrier(c, C, W, C, R); // group bounds -> the pair tests
    // (group, dirty map) pairs: x the CPU's group count, y vsm_assign's dirty maps (cullGroups).
    const uint32_t meshlets = state_->meshPath() ? 1u : 0u;
    const std::initializer_list<NamedDescriptor> pairsBound = {
        ML_BIND(ML_VSM_PAIRS_CONSTANTS, slot.constants), ML_BIND(ML_VSM_PAIRS_MAPS, slot.maps),
        ML_BIND(ML_VSM_PAIRS_DIRTY_MAPS, pg.dirtyMaps),  ML_BIND(ML_VSM_PAIRS_DIRTY_MIPS, pg.dirtyMips),
        ML_BIND(ML_VSM_PAIRS_GROUPS, slot.casterGroups), ML_BIND(ML_VSM_PAIRS_PAIRS, slot.cullPairs),
        ML_BIND(ML_VSM_PAIRS_COUNTERS, slot.counters)};
    dispatchIndirect(d, c, programs_.pairs, slot.counters, offsetof(gpu::VsmCounters, cullGroupsX),
                     gpu::VsmPairsPush{slot.casterCount, meshlets, 0, 0, slot.pairCapacity}, pairsBound);
    memoryBarrier(c, C, W, C, R | W); // the pair count (atomics) -> the closing thread
    dispatch(d, c, programs_.pairs, 1, 1,
             gpu::VsmPairsPush{slot.casterCount, meshlets, 1, state_->settings().cullRowWorkgroups,
                               slot.pairCapacity},
             pairsBound);
    // The culling's dispatch size -> indirect read; the pair list -> the culling's reads.
    memoryBarrier(c, C, W, C | kIndirect, R | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
}

void VsmPasses::recordCull(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const gpu::VsmCullPush push{slot.casterCount, state_->settings().maxDrawsPerMip};
    // One workgroup per (caster group, map) pair left: vsm_pairs wrote the dispatch size.
    dispatchIndirect(
        d, c, programs_.cull, slot.counters, offsetof(gpu::VsmCounters, pairGroupsX), push,
        {ML_BIND(ML_VSM_CULL_CONSTANTS, slot.constants), ML_BIND(ML_VSM_CULL_MAPS, slot.maps),
         ML_BIND(ML_VSM_CULL_PAIRS, slot.cullPairs), ML_BIND(ML_VSM_CULL_TABLE, pg.table),
         ML_BIND(ML_VSM_CULL_HPB, pg.hpb), ML_BIND(ML_VSM_CULL_CASTERS, slot.casters),
         ML_BIND(ML_VSM_CULL_DIRTY_MIPS, pg.dirtyMips), ML_BIND(ML_VSM_CULL_DRAWS, pg.draws),
         ML_BIND(ML_VSM_CULL_DRAW_INFO, pg.drawInfo), ML_BIND(ML_VSM_CULL_DRAW_COUNTS, pg.drawCounts),
         ML_BIND(ML_VSM_CULL_COUNTERS, slot.counters), ML_BIND(ML_VSM_CULL_ORDER, slot.casterOrder)});
    // Draw lists and counts -> indirect draws; draw info -> vertex shader.
    memoryBarrier(c, C, W, kIndirect | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
                  VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | R);
}

void VsmPasses::recordExpand(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    const gpu::VsmCullPush push{slot.casterCount, state_->settings().maxMeshletsPerMip};
    dispatchIndirect(
        d, c, programs_.expand, slot.counters, offsetof(gpu::VsmCounters, pairGroupsX), push,
        {ML_BIND(ML_VSM_EXPAND_CONSTANTS, slot.constants), ML_BIND(ML_VSM_EXPAND_MAPS, slot.maps),
         ML_BIND(ML_VSM_EXPAND_PAIRS, slot.cullPairs), ML_BIND(ML_VSM_EXPAND_TABLE, pg.table),
         ML_BIND(ML_VSM_EXPAND_HPB, pg.hpb), ML_BIND(ML_VSM_EXPAND_CASTERS, slot.casters),
         ML_BIND(ML_VSM_EXPAND_DIRTY_MIPS, pg.dirtyMips), ML_BIND(ML_VSM_EXPAND_MESHLET_LIST, pg.meshletList),
         ML_BIND(ML_VSM_EXPAND_MESH_TASKS, pg.meshTasks), ML_BIND(ML_VSM_EXPAND_COUNTERS, slot.counters),
         ML_BIND(ML_VSM_EXPAND_ORDER, slot.casterOrder)});
    // Task counts -> indirect draws; lists, and the page table and HPB (written by earlier compute
    // passes) -> task and mesh shaders.
    memoryBarrier(c, C, W, kIndirect | kTask | VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT,
                  VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | R);
}

void VsmPasses::recordClear(const Device& d, VkCommandBuffer c, uint32_t slotIndex) const {
    const VsmSlot& slot = state_->slot(slotIndex);
    const VsmPages& pg = state_->pages();
    // One group per rendered page: vsm_assign counted them into the dispatch size.
    dispatchIndirect(d, c, programs_.clear, slot.counters, offsetof(gpu::VsmCounters, dispatchX), NoPush{},
                     {ML_BIND(ML_VSM_CLEAR_CONSTANTS, slot.constants),
                      ML_BIND(ML_VSM_CLEAR_RENDERED, pg.rendered), ML_BIND(ML_VSM_CLEAR_PAGE_POOL, pg.pool)});
    memoryBarrier(c, C, W, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, R | W); // cleared pages -> atomic min
}

void VsmPasses::recordDraw(const Device& d, VkCommandBuffer c, const VsmFrameInputs& in) const {
    const VsmSlot& slot = state_->slot(in.slot);
    const VsmPages& pg = state_->pages();
    for (uint32_t m = 0; m < state_->layout().mips; ++m) {
        const uint32_t res = state_->settings().resolution >> m;
        beginAttachmentless(c, res, {res, res});
        const gpu::VsmDrawPush push{m, state_->settings().maxMeshletsPerMip};
        if (state_->meshPath()) {
            // Spot and point maps of every light at this mip, and at mip 0 every directional clip level.
            bindProgram(
                d, c, programs_.mesh, push,
                {ML_BIND(ML_VSM_DRAW_VERTICES, *in.vertices), ML_BIND(ML_VSM_DRAW_INSTANCES, *in.instances),
                 ML_BIND(ML_VSM_DRAW_MESHLET_LIST, pg.meshletList), ML_BIND(ML_VSM_DRAW_MAPS, slot.maps),
                 ML_BIND(ML_VSM_DRAW_CONSTANTS, slot.constants), ML_BIND(ML_VSM_DRAW_TABLE, pg.table),
                 ML_BIND(ML_VSM_DRAW_PAGE_POOL, pg.pool), ML_BIND(ML_VSM_DRAW_COUNTERS, slot.counters),
                 ML_BIND(ML_VSM_DRAW_MESHLET_VERTICES, *in.meshletVertices),
                 ML_BIND(ML_VSM_DRAW_MESHLET_TRIANGLES, *in.meshletTriangles),
                 ML_BIND(ML_VSM_DRAW_HPB, pg.hpb), ML_BIND(ML_VSM_DRAW_MESH_TASKS, pg.meshTasks),
                 ML_BIND(ML_VSM_DRAW_MESHLETS, *in.meshlets)});
            d.cmdDrawMeshTasksIndirect(c, pg.meshTasks.buffer, VkDeviceSize(m) * 16, 1, 16);
        } else {
            // Closed casters with back faces culled, then open ones (vsm_cull.comp's two lists).
            for (uint32_t list = 0; list < 2; ++list) {
                bindProgram(
                    d, c, list == 0 ? programs_.drawClosed : programs_.draw, push,
                    {ML_BIND(ML_VSM_DRAW_VERTICES, *in.vertices),
                     ML_BIND(ML_VSM_DRAW_INSTANCES, *in.instances),
                     ML_BIND(ML_VSM_DRAW_DRAW_INFO, pg.drawInfo), ML_BIND(ML_VSM_DRAW_MAPS, slot.maps),
                     ML_BIND(ML_VSM_DRAW_CONSTANTS, slot.constants), ML_BIND(ML_VSM_DRAW_TABLE, pg.table),
                     ML_BIND(ML_VSM_DRAW_PAGE_POOL, pg.pool), ML_BIND(ML_VSM_DRAW_COUNTERS, slot.counters)});
                vkCmdBindIndexBuffer(c, in.indices->buffer, 0, VK_INDEX_TYPE_UINT32);
                const VkDeviceSize first =
                    VkDeviceSize(list * state_->layout().mips + m) * state_->settings().maxDrawsPerMip;
                vkCmdDrawIndexedIndirectCount(
                    c, pg.draws.buffer, first * sizeof(VkDrawIndexedIndirectCommand), pg.drawCounts.buffer,
                    VkDeviceSize(list * ML_VSM_MAX_MIPS + m) * 4, state_->settings().maxDrawsPerMip,
                    sizeof(VkDrawIndexedIndirectCommand));
            }
        }
        vkCmdEndRendering(c);
    }
    if (state_->settings().staticLayer && state_->settings().caching) {
        // Static twins and dynamic casters' depths -> their minimum in the page (vsm_merge.comp).
        memoryBarrier(c, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, W, C, R | W);
        dispatchIndirect(
            d, c, programs_.merge, slot.counters, offsetof(gpu::VsmCounters, dispatchX), NoPush{},
            {ML_BIND(ML_VSM_MERGE_CONSTANTS, slot.constants), ML_BIND(ML_VSM_MERGE_RENDERED, pg.rendered),
             ML_BIND(ML_VSM_MERGE_PAGE_POOL, pg.pool)});
        memoryBarrier(c, C, W, C, R); // merged pages -> the evaluation pass's lookups
        return;
    }
    // Physical pages -> the evaluation pass's lookups.
    memoryBarrier(c, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, W, C, R);
}

Result<void> VsmPasses::recordPath(const Device& d, const VsmFrameInputs& in, const StepRunner& step) const {
    const uint32_t slot = in.slot;
    // Each receiver pixel (or cluster) marks the pages its lookups will read; first wants are listed.
    ML_TRY(step(kMarkTimer, [&](VkCommandBuffer c) { recordMark(d, c, in); }));
    // The request list closed and sorted by priority rank (a short one also allocated, in one workgroup).
    ML_TRY(step(kSortTimer, [&](VkCommandBuffer c) { recordSort(d, c, slot); }));
    // Invalidation, then a physical page for each wanted entry without one; dirty pages and maps listed.
    // An empty scope where the sort's one workgroup allocated alone: every step keeps its scope each frame.
    ML_TRY(step(kAllocTimer, [&](VkCommandBuffer c) { recordAlloc(d, c, slot); }));
    // The hierarchical page buffer: which regions of each map hold a dirty page.
    ML_TRY(step(kHpbTimer, [&](VkCommandBuffer c) { recordHpb(d, c, slot); }));
    // Caster groups against the dirty maps: the (group, map) pairs left for the culling.
    ML_TRY(step(kGroupCullTimer, [&](VkCommandBuffer c) { recordGroupCull(d, c, slot); }));
    if (!state_->meshPath()) // vertex path: each pair's casters into indirect draws per dirty mip
        ML_TRY(step(kCullTimer, [&](VkCommandBuffer c) { recordCull(d, c, slot); }));
    else // mesh path: each pair's casters into meshlet lists for the task shaders
        ML_TRY(step(kExpandTimer, [&](VkCommandBuffer c) { recordExpand(d, c, slot); }));
    // The dirty pages cleared, then the casters drawn into them (and merged with their static twins).
    return step(kDrawTimer, [&](VkCommandBuffer c) {
        recordClear(d, c, slot);
        recordDraw(d, c, in);
    });
}

void VsmPasses::recordProbe(const Device& d, VkCommandBuffer cmd, const VsmFrameInputs& in) const {
    const VsmSlot& slot = state_->slot(in.slot);
    const VsmPages& pg = state_->pages();
    const auto* fc = in.frame->as<gpu::FrameConstants>();
    dispatch(d, cmd, programs_.probe, fc->size.x, fc->size.y, NoPush{},
             {ML_BIND(ML_VSM_PROBE_FRAME, *in.frame), ML_BIND(ML_VSM_PROBE_SLICES, *in.slices),
              ML_BIND(ML_VSM_PROBE_LIGHTS, *in.lights), ML_BIND(ML_VSM_PROBE_RANGES, *in.ranges),
              ML_BIND(ML_VSM_PROBE_LIGHT_POOL, *in.pool), ML_BIND(ML_VSM_PROBE_DEPTH, sampled(in.depth)),
              ML_BIND(ML_VSM_PROBE_NORMAL, sampled(in.normal)),
              ML_BIND(ML_VSM_PROBE_CONSTANTS, slot.constants), ML_BIND(ML_VSM_PROBE_MAPS, slot.maps),
              ML_BIND(ML_VSM_PROBE_COVERAGE, slot.coverage), ML_BIND(ML_VSM_PROBE_TABLE, pg.table),
              ML_BIND(ML_VSM_PROBE_PAGE_POOL, pg.pool), ML_BIND(ML_VSM_PROBE_PROBES, slot.probes)});
    memoryBarrier(cmd, C, W, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT); // probes -> host
}

void VsmPasses::recordView(const Device& d, VkCommandBuffer cmd, const VsmFrameInputs& in) const {
    const VsmSlot& slot = state_->slot(in.slot);
    const VsmPages& pg = state_->pages();
    const auto* fc = in.frame->as<gpu::FrameConstants>();
    // The evaluation pass's output -> read and overwritten here.
    memoryBarrier(cmd, C, W, C, R | W);
    dispatch(d, cmd, programs_.view, fc->size.x, fc->size.y, NoPush{},
             {ML_BIND(ML_VSM_VIEW_FRAME, *in.frame), ML_BIND(ML_VSM_VIEW_SLICES, *in.slices),
              ML_BIND(ML_VSM_VIEW_LIGHTS, *in.lights), ML_BIND(ML_VSM_VIEW_RANGES, *in.ranges),
              ML_BIND(ML_VSM_VIEW_LIGHT_POOL, *in.pool), ML_BIND(ML_VSM_VIEW_DEPTH, sampled(in.depth)),
              ML_BIND(ML_VSM_VIEW_NORMAL, sampled(in.normal)), ML_BIND(ML_VSM_VIEW_CONSTANTS, slot.constants),
              ML_BIND(ML_VSM_VIEW_MAPS, slot.maps), ML_BIND(ML_VSM_VIEW_COVERAGE, slot.coverage),
              ML_BIND(ML_VSM_VIEW_TABLE, pg.table), ML_BIND(ML_VSM_VIEW_PAGE_POOL, pg.pool),
              ML_BIND(ML_VSM_VIEW_OUTPUT, Image{.view = in.viewOutput})});
    // The view's output -> the host's reads after record().
    memoryBarrier(cmd, C, W, kOutputReaderStages, kOutputReads);
}

} // namespace ml
