// GPU profiler (internal; the API types Pass, PassTimes and TimingMode are gpu/pass_times.h): a timestamp
// pair around every pass, indexed by the Pass enum (no magic slot numbers), with a debug label per pass. Each
// frame-in-flight slot has its own query range; results are read without waiting, when the host reuses the
// slot (its previous frame is then known to be complete).
#pragma once
#include "gpu/device.h"
#include "gpu/pass_times.h"

#include <array>
#include <functional>

namespace ml {

class Profiler {
  public:
    TimingMode mode = TimingMode::Timestamps;
    // Fenced mode: the host-measured time of a pass in the current slot.
    void setFenced(Pass pass, double startMs, double ms);
    void create(const Device& device, uint32_t slots);
    void destroy(const Device& device);
    // Resets the slot's queries; call before the first pass of the frame.
    void beginFrame(VkCommandBuffer cmd, uint32_t slot);
    // Records `body` as the pass: into cmd between timestamps, or (Fenced) into its own submission,
    // timed. runUntimed does the same for setup work that must stay in order with the passes.
    void run(VkCommandBuffer cmd, Pass pass, const std::function<void(VkCommandBuffer)>& body);
    void runUntimed(VkCommandBuffer cmd, const std::function<void(VkCommandBuffer)>& body);
    void begin(VkCommandBuffer cmd, Pass pass);
    void end(VkCommandBuffer cmd, Pass pass);
    // Reads the slot's timestamps without waiting. False when any recorded pass is not available yet.
    bool read(uint32_t slot, PassTimes& out) const;

  private:
    const Device* device_ = nullptr;
    VkQueryPool pool_ = VK_NULL_HANDLE;
    uint32_t slots_ = 0, current_ = 0;
    std::vector<std::array<bool, kPassCount>> recorded_;
    std::vector<PassTimes> fenced_;
};

} // namespace ml
