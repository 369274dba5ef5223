// A timed scope of the module's frame: declared once, as a constant of the class whose function records
// the pass (GBufferPass::kTimer, LightCulling::kBoundsTimer, VsmPasses::kMarkTimer, ...), and handed to
// the profiler (gpu/profiler.h) by the frame's list (engine/frame_passes.cpp) or by the feature's own
// path of timed steps (VsmPasses::recordPath). The profiler gives it a query pair on its first run, so
// no list of timers is kept anywhere else.
#pragma once

namespace ml {

struct PassTimer {
    // The pass's name in FrameReport::times and the reports (stats.json, frames.csv, the trace).
    const char* name;
    // The sum it counts in (PassTimes::groupMs), empty for none. Both are string literals: the profiler
    // keeps the pointers for the module's lifetime.
    const char* group = "";
};

} // namespace ml
