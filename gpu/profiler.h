// GPU profiler (internal): a timestamp pair around every timed pass, with a debug label per pass. Generic:
// the caller gives the timer slots' names at creation and times a pass by its slot index (the module's
// frame loop, engine/frame.h, passes its Pass enum), so the base knows no feature. Each frame-in-flight
// slot has its own query range; results are read without waiting, when the host reuses the slot (its
// previous frame is then known to be complete).
#pragma once
#include "gpu/device.h"

#include <functional>
#include <string>
#include <vector>

namespace ml {

class Profiler {
  public:
    // Fenced: each pass is submitted on its own and timed with the host clock from submit to completion
    // (lavapipe: its timestamps do not bracket compute, engine/pass_times.h TimingMode).
    bool fenced = false;
    // Out of memory for the query pool is an error (the profiler is then destroyable, empty). Fenced
    // runs use the aborting one-off command buffers (a profiling mode, not the module's default path).
    Result<void> create(const Device& device, uint32_t frameSlots, std::vector<std::string> timerNames);
    void destroy(const Device& device);
    // Resets the slot's queries; call before the first pass of the frame.
    void beginFrame(VkCommandBuffer cmd, uint32_t slot);
    // Records `body` as timer `timer`'s pass: into cmd between timestamps, or (fenced) into its own
    // submission, timed. runUntimed does the same for work that must stay in order with the passes.
    void run(VkCommandBuffer cmd, uint32_t timer, const std::function<void(VkCommandBuffer)>& body);
    void runUntimed(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& body);

    // Per timer: GPU milliseconds, start on the GPU clock (only differences mean anything), recorded.
    struct Times {
        std::vector<double> ms, startMs;
        std::vector<bool> ran;
    };
    // Reads the slot's timestamps without waiting. False when any recorded pass is not available yet.
    bool read(uint32_t slot, Times& out) const;

  private:
    void setFenced(uint32_t timer, double startMs, double ms);
    uint32_t timers() const { return uint32_t(names_.size()); }
    const Device* device_ = nullptr;
    VkQueryPool pool_ = VK_NULL_HANDLE;
    uint32_t slots_ = 0, current_ = 0;
    std::vector<std::string> names_;
    std::vector<std::vector<bool>> recorded_; // per frame slot, per timer
    std::vector<Times> fenced_;
};

} // namespace ml
