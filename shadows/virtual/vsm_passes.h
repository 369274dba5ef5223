// The virtual shadow map passes (vsm.h has the algorithm) over the state VirtualShadowMaps keeps: one
// function per pass, their programs (vsm_programs.h). The frame (engine/frame.h) records reset (per-frame
// clears, untimed), then, when the slot has active maps (state.active()), the path from marked page to
// drawn page that recordPath lists in order, each step under its timer (the k...Timer constants beside
// the steps' functions: every step before the draws counts in the VSM bookkeeping); after the evaluation
// the probe (state.probing()) and the debug view.
#pragma once
#include "gpu/pass_timer.h"
#include "manylights/pass_times.h"
#include "shadows/virtual/vsm.h"
#include "shadows/virtual/vsm_programs.h"

#include <functional>

namespace ml {

// What the VSM passes read and write besides the state's own buffers (VirtualShadowMaps: page table,
// pool, marks, lists; the slot's maps, constants and counters), by name; each is bound at its shader's
// named binding (shadows/virtual/vsm_bindings.h).
struct VsmFrameInputs {
    // Frame-in-flight index: which of the state's per-slot buffers (VirtualShadowMaps::slot) this frame's
    // passes bind, written by prepare() for the same slot.
    uint32_t slot = 0;
    const Buffer* frame = nullptr;  // FrameConstants (uniform)
    const Buffer* slices = nullptr; // slice boundaries
    const Buffer* lights = nullptr; // visible GpuLights (info.y = first map, from prepare())
    const Buffer* ranges = nullptr; // cluster lists (culling/culling.h)
    const Buffer* pool = nullptr;
    VkImageView depth = VK_NULL_HANDLE, normal = VK_NULL_HANDLE; // G-buffer, SHADER_READ_ONLY_OPTIMAL
    const Buffer* vertices = nullptr;
    const Buffer* indices = nullptr;
    const Buffer* instances = nullptr; // GpuInstance per module instance
    // Mesh path (shadows/virtual/vsm_meshlets.h): GpuMeshlet, vertex lists, packed triangles.
    const Buffer* meshlets = nullptr;
    const Buffer* meshletVertices = nullptr;
    const Buffer* meshletTriangles = nullptr;
    // Clustered culling's receiver bounds (ClusterReceivers) and tile masks (culling/culling.h), for
    // marking per cluster (VsmSettings::clusterMarking); without them the pages are marked per pixel.
    const Buffer* clusterReceivers = nullptr;
    const Buffer* tileMasks = nullptr;
    // The page view's target (recordView): the RGBA8 output, storage, GENERAL, after the evaluation.
    VkImageView viewOutput = VK_NULL_HANDLE;
};

class VsmPasses {
  public:
    // Programs for the state's raster path (state.meshPath()); the state outlives the passes.
    Result<void> create(const Device& device, const VirtualShadowMaps& state);
    void destroy(const Device& device);
    void recordReset(VkCommandBuffer cmd) const;
    // The longest request list one workgroup allocates (vsm_allocate_short_list; 0: every list goes to the
    // multi-dispatch passes): ML_VSM_ONE_GROUP_LIST where the device has the shared memory and
    // invocations, lowered by ML_VSM_ALLOC_SHORT_LIST=N (0 restores the multi-dispatch path alone).
    uint32_t shortListLimit() const { return shortList_; }
    // Which allocation passes a frame records. Auto: vsm_allocate_short_list alone when the slot's last
    // list had at most shortListLimit() entries (it then takes any length: a list that outgrew the limit
    // is sorted in the list buffers), else it and the multi-dispatch passes, which a long list runs (9
    // dispatches, each behind a barrier, left out for a short one). Tests force either.
    enum class Sequence { Auto, OneWorkgroup, Both };
    void setSequence(Sequence s) { sequence_ = s; }
    bool oneWorkgroupOnly(uint32_t slot) const;
    // Runs one step of the path under its timer: `body` records the step into the command buffer it is
    // given (the frame's, or a fenced run's own). A failed run (fenced runs only) stops the path there.
    using StepRunner =
        std::function<Result<void>(const PassTimer& timer, const std::function<void(VkCommandBuffer)>& body)>;
    // The path from marked page to drawn page, in order, for a slot with active maps
    // (state.active(in.slot)).
    Result<void> recordPath(const Device& device, const VsmFrameInputs& in, const StepRunner& step) const;
    // The probe pass: records the lookups into the slot's probe buffer.
    void recordProbe(const Device& device, VkCommandBuffer cmd, const VsmFrameInputs& in) const;
    // demo --view vsm: colours in.viewOutput by the page each pixel's first shadowed light reads
    // (vsm_view.comp).
    void recordView(const Device& device, VkCommandBuffer cmd, const VsmFrameInputs& in) const;

  private:
    // The steps that bind the frame's buffers take its inputs; the others bind the state's alone and
    // take the slot (in.slot) whose buffers they use.
    static constexpr PassTimer kMarkTimer{"vsm_mark", kVsmBookkeeping};
    void recordMark(const Device& device, VkCommandBuffer cmd, const VsmFrameInputs& in) const;
    static constexpr PassTimer kSortTimer{"vsm_sort", kVsmBookkeeping}; // vsm_list, vsm_sort
    void recordSort(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    // vsm_scan (with invalidation), vsm_alloc, vsm_avail, vsm_assign (caching, invalidation, LRU); none
    // of them where vsm_allocate_short_list runs alone (oneWorkgroupOnly), the scope then empty
    static constexpr PassTimer kAllocTimer{"vsm_alloc", kVsmBookkeeping};
    void recordAlloc(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    // vsm_hpb; only its barrier where vsm_allocate_short_list ran alone and set the bits (oneWorkgroupOnly)
    static constexpr PassTimer kHpbTimer{"vsm_hpb", kVsmBookkeeping};
    void recordHpb(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    // Ahead of vsm_cull / vsm_expand: vsm_groups (the bounds of each 64 casters of the culling order),
    // vsm_pairs (the (group, dirty map) pairs inside the frustum, and the culling's dispatch size).
    static constexpr PassTimer kGroupCullTimer{"vsm_group_cull", kVsmBookkeeping};
    void recordGroupCull(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    static constexpr PassTimer kCullTimer{"vsm_cull", kVsmBookkeeping}; // vertex path
    void recordCull(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    static constexpr PassTimer kExpandTimer{"vsm_expand", kVsmBookkeeping}; // mesh path
    void recordExpand(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    static constexpr PassTimer kDrawTimer{"vsm_draw"}; // clear and draw the dirty pages
    void recordClear(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    void recordDraw(const Device& device, VkCommandBuffer cmd, const VsmFrameInputs& in) const;

    const VirtualShadowMaps* state_ = nullptr;
    VsmPrograms programs_;
    uint32_t shortList_ = 0;
    Sequence sequence_ = Sequence::Auto;
};

} // namespace ml
