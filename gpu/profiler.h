// GPU profiler (internal): a timestamp pair around every timed pass, with a debug label per pass. Generic:
// the caller gives the timer slots' names at creation and times a pass by its slot index (the module's
// frame loop, engine/frame.h, passes its Pass enum), so the base knows no feature. Each frame-in-flight
// slot has its own query range. record() must never wait for the GPU, and vkGetQueryPoolResults may:
// lavapipe's waits for the whole device to go idle (so the frame in flight on the other slot), even
// without VK_QUERY_RESULT_WAIT_BIT. So the frame itself copies its timestamps into a host-visible buffer
// (vkCmdCopyQueryPoolResults) and then sets an event; read() looks at the event (vkGetEventStatus never
// blocks) and reads the buffer only once the event is set. Nothing on the host side ever waits.
#pragma once
#include "gpu/device.h"
#include "gpu/resources.h"

#include <functional>
#include <string>
#include <vector>

namespace ml {

class Profiler {
  public:
    // Fenced: each pass is submitted on its own and timed with the host clock from submit to completion
    // (lavapipe: its timestamps do not bracket compute, manylights/pass_times.h TimingMode).
    bool fenced = false;
    // Out of memory for the query pool is an error (the profiler is then destroyable, empty); so is
    // a fenced run's command buffer or submission (run / runUntimed return it, the body not recorded).
    Result<void> create(const Device& device, uint32_t frameSlots, std::vector<std::string> timerNames);
    void destroy(const Device& device);
    // Resets the slot's queries; call before the first pass of the frame.
    void beginFrame(VkCommandBuffer cmd, uint32_t slot);
    // Records `body` as timer `timer`'s pass: into cmd between timestamps, or (fenced) into its own
    // submission, timed. runUntimed does the same for work that must stay in order with the passes.
    Result<void> run(VkCommandBuffer cmd, uint32_t timer, const std::function<void(VkCommandBuffer)>& body);
    Result<void> runUntimed(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& body);
    // Last command of the frame: copies the slot's timestamps to its results buffer and sets its event
    // (after all of the frame's commands, their writes made visible to the host).
    void endFrame(VkCommandBuffer cmd);

    // Per timer: GPU milliseconds, start on the GPU clock (only differences mean anything), recorded.
    struct Times {
        std::vector<double> ms, startMs;
        std::vector<bool> ran;
    };
    // Reads the slot's timestamps without waiting. False while the slot's frame has not completed (its
    // event is not set); true once, after which the slot's event is reset for its next frame. A true
    // read also means every host-visible result of that frame (counters) is complete.
    bool read(uint32_t slot, Times& out);

  private:
    void setFenced(uint32_t timer, double startMs, double ms);
    uint32_t timers() const { return uint32_t(names_.size()); }
    const Device* device_ = nullptr;
    VkQueryPool pool_ = VK_NULL_HANDLE;
    std::vector<VkEvent> done_;   // per frame slot: set by the GPU at the end of the slot's frame
    std::vector<Buffer> results_; // per frame slot: {value, availability} per query, 64-bit
    uint32_t slots_ = 0, current_ = 0;
    std::vector<std::string> names_;
    std::vector<std::vector<bool>> recorded_; // per frame slot, per timer
    std::vector<Times> fenced_;
};

} // namespace ml
