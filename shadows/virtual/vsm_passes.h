// The virtual shadow map passes (vsm.h has the algorithm) over the state VirtualShadowMaps keeps: one
// function per pass, their programs (vsm_programs.h). The module's frame (engine/frame.h) orders and
// times them, one timer per step (manylights/pass_times.h): reset (per-frame clears, untimed), then, when
// the slot has active maps (state.active()), mark, sort (close and sort the request list; a short list is
// allocated there in one workgroup, vsm_allocate_short_list), alloc (invalidate, scan, allocate, assign),
// HPB, group culling (caster groups against the dirty maps), cull (vertex path) or expand (mesh path),
// draw (clear and draw the dirty pages); after the evaluation the probe (state.probing()) and the debug
// view.
#pragma once
#include "shadows/virtual/vsm.h"
#include "shadows/virtual/vsm_programs.h"

namespace ml {

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
    void recordMark(const Device& device, VkCommandBuffer cmd, uint32_t slot, const VsmFrameInputs& in) const;
    void recordSort(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    void recordAlloc(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    void recordHpb(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    // Ahead of vsm_cull / vsm_expand: vsm_groups (the bounds of each 64 casters of the culling order),
    // vsm_pairs (the (group, dirty map) pairs inside the frustum, and the culling's dispatch size).
    void recordGroupCull(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    void recordCull(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    void recordExpand(const Device& device, VkCommandBuffer cmd, uint32_t slot) const;
    void recordDraw(const Device& device, VkCommandBuffer cmd, uint32_t slot, const VsmFrameInputs& in) const;
    // The probe pass: records the lookups into the slot's probe buffer.
    void recordProbe(const Device& device, VkCommandBuffer cmd, uint32_t slot,
                     const VsmFrameInputs& in) const;
    // demo --view vsm: colours the output by the page each pixel's first shadowed light reads
    // (vsm_view.comp). `output` is the RGBA8 output in GENERAL layout, after the evaluation pass.
    void recordView(const Device& device, VkCommandBuffer cmd, uint32_t slot, const VsmFrameInputs& in,
                    VkImageView output) const;

  private:
    const VirtualShadowMaps* state_ = nullptr;
    VsmPrograms programs_;
    uint32_t shortList_ = 0;
};

} // namespace ml
