// Per-pass GPU times of a frame (FrameReport::times), one slot per Pass.
#pragma once
#include <array>
#include <cstdint>

namespace ml {

// Every timed pass of the module's frame, in recording order (passName gives each its report name).
enum class Pass : uint32_t {
    GBuffer,
    ClusterBounds,
    LightAssign,
    // Virtual shadow maps, one scope per step: VsmMark..VsmExpand are the bookkeeping
    // (PassTimes::vsmBookkeepingMs), VsmDraw the page draws.
    VsmMark,      // pages from the depth buffer
    VsmSort,      // vsm_list, vsm_sort: the request list closed and sorted by priority rank
    VsmAlloc,     // vsm_scan, vsm_alloc, vsm_avail, vsm_assign (caching, invalidation, LRU)
    VsmHpb,       // hierarchical page buffer
    VsmGroupCull, // vsm_groups, vsm_pairs: caster groups' bounds, the (group, dirty map) pairs kept
    VsmCull,      // vertex path: instance culling of the pairs into per-mip draw lists
    VsmExpand,    // mesh path: the same culling, expanded into per-mip meshlet lists
    VsmDraw,      // clear and draw the dirty pages
    Evaluate,
    Statistics, // per-pixel light counts (optional)
    Count
};
constexpr uint32_t kPassCount = uint32_t(Pass::Count);
const char* passName(Pass pass);

struct PassTimes {
    std::array<double, kPassCount> ms{}; // GPU milliseconds per pass
    std::array<double, kPassCount>
        startMs{};                      // pass start on the GPU clock (ms; only differences mean anything)
    std::array<bool, kPassCount> ran{}; // the pass was recorded this frame
    double totalMs() const;
    // The VSM bookkeeping: the steps VsmMark..VsmExpand that ran (their sum is what the maps cost
    // besides drawing pages).
    double vsmBookkeepingMs() const;
};
// Whether a pass is one of the VSM bookkeeping steps (VsmMark..VsmExpand).
constexpr bool vsmBookkeeping(Pass p) {
    return uint32_t(p) >= uint32_t(Pass::VsmMark) && uint32_t(p) <= uint32_t(Pass::VsmExpand);
}

// Timestamps: vkCmdWriteTimestamp2 pairs (GPUs). Fenced: each pass is submitted on its own and timed
// with the host clock from submit to completion: what a CPU device needs, whose timestamps need not
// bracket compute dispatches, while its wall time for a pass is its device time.
enum class TimingMode : uint32_t { Timestamps, Fenced };

} // namespace ml
