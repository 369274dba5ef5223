// Per-pass GPU times of a frame (FrameReport::times): one entry for each timed pass the frame recorded.
#pragma once
#include <cstdint>
#include <string_view>
#include <vector>

namespace ml {

// The group of the virtual shadow maps' bookkeeping steps (vsm_mark, vsm_sort, vsm_alloc, vsm_hpb,
// vsm_group_cull, and vsm_cull or vsm_expand): what the maps cost besides drawing pages (vsm_draw).
inline constexpr const char* kVsmBookkeeping = "vsm_bookkeeping";

// One timed pass, under the name the reports print (stats.json's pass_gpu_ms_mean, frames.csv, the
// trace): "gbuffer", "cluster_bounds", "light_assign", the VSM steps, "evaluate", "statistics". The name
// and group view string literals of the module (static storage, each null-terminated): valid for the
// program's lifetime, and a frame's report allocates no string for them.
struct PassTime {
    std::string_view name;
    std::string_view group; // the sum it counts in (PassTimes::groupMs), empty for none
    double ms = 0;          // GPU milliseconds
    double startMs = 0;     // start on the GPU clock (ms; only differences mean anything)
};

struct PassTimes {
    std::vector<PassTime> passes; // the timed passes the frame recorded, in recording order
    const PassTime* find(std::string_view name) const; // null when the pass did not run
    bool ran(std::string_view name) const { return find(name) != nullptr; }
    double ms(std::string_view name) const; // GPU milliseconds, 0 when the pass did not run
    double totalMs() const;
    double groupMs(std::string_view group) const; // the passes of a group that ran, summed
    // The VSM bookkeeping: the steps of kVsmBookkeeping that ran.
    double vsmBookkeepingMs() const { return groupMs(kVsmBookkeeping); }
};

// Timestamps: vkCmdWriteTimestamp2 pairs (GPUs). Fenced: each pass is submitted on its own and timed
// with the host clock from submit to completion: what a CPU device needs, whose timestamps need not
// bracket compute dispatches, while its wall time for a pass is its device time.
enum class TimingMode : uint32_t { Timestamps, Fenced };

} // namespace ml
