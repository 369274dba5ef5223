// GPU profiler (internal): a timestamp pair around every timed pass, with a debug label per pass. Generic:
// the caller times a pass under a PassTimer (gpu/pass_timer.h), which gets its query pair on its first
// run, so the base knows no feature and no list of timers. Each frame-in-flight slot has its own query
// range. record() must never wait for the GPU, and vkGetQueryPoolResults may:
// lavapipe's waits for the whole device to go idle (so the frame in flight on the other slot), even
// without VK_QUERY_RESULT_WAIT_BIT. So the frame itself copies its timestamps into a host-visible buffer
// (vkCmdCopyQueryPoolResults) and then sets an event; read() looks at the event (vkGetEventStatus never
// blocks) and reads the buffer only once the event is set. Nothing on the host side ever waits.
#pragma once
#include "gpu/device.h"
#include "gpu/pass_timer.h"
#include "gpu/resources.h"
#include "manylights/pass_times.h"

#include <functional>
#include <string>
#include <vector>

namespace ml {

class Profiler {
  public:
    // Fenced: each pass is submitted on its own and timed with the host clock from submit to completion
    // (lavapipe: its timestamps do not bracket compute, manylights/pass_times.h TimingMode).
    bool fenced = false;
    // The most timers one profiler gives query pairs to (2 timestamps each per frame slot); a timer past
    // them is refused by run().
    static constexpr uint32_t kMaxTimers = 32;
    // Out of memory for the query pool is an error (the profiler is then destroyable, empty); so is
    // a fenced run's command buffer or submission (run / runUntimed return it, the body not recorded).
    Result<void> create(const Device& device, uint32_t frameSlots);
    void destroy(const Device& device);
    // Resets the slot's queries; call before the first pass of the frame.
    void beginFrame(VkCommandBuffer cmd, uint32_t slot);
    // Records `body` as timer `timer`'s pass: into cmd between timestamps, or (fenced) into its own
    // submission, timed. runUntimed does the same for work that must stay in order with the passes. A
    // timer runs at most once a frame (a second run is refused, as is a timer past kMaxTimers).
    Result<void> run(VkCommandBuffer cmd, const PassTimer& timer,
                     const std::function<void(VkCommandBuffer)>& body);
    Result<void> runUntimed(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& body);
    // Last command of the frame: copies the slot's timestamps to its results buffer and sets its event
    // (after all of the frame's commands, their writes made visible to the host).
    void endFrame(VkCommandBuffer cmd);

    // Reads the slot's times without waiting: the timers its frame ran, in the order they ran. False
    // while the slot's frame has not completed (its event is not set); true once, after which the slot's
    // event is reset for its next frame. A true read also means every host-visible result of that frame
    // (counters) is complete.
    bool read(uint32_t slot, PassTimes& out);

  private:
    // The timer's index (its query pair), given on its first run; refused past kMaxTimers and on a
    // second run in the same frame.
    Result<uint32_t> begin(const PassTimer& timer);
    const Device* device_ = nullptr;
    VkQueryPool pool_ = VK_NULL_HANDLE;
    std::vector<VkEvent> done_;   // per frame slot: set by the GPU at the end of the slot's frame
    std::vector<Buffer> results_; // per frame slot: {value, availability} per query, 64-bit
    uint32_t slots_ = 0, current_ = 0;
    std::vector<PassTimer> timers_;          // in the order of their first run; index = query pair
    std::vector<std::vector<uint32_t>> ran_; // per frame slot: the timers its frame ran, in order
    std::vector<PassTimes> fenced_;          // per frame slot (fenced): the times, in order
};

} // namespace ml
