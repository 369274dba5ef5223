// GPU profiler: a timestamp pair around every pass, indexed by the Pass enum (no magic slot numbers),
// with a debug label per pass. Each frame-in-flight slot has its own query range; results are read
// without waiting, when the host reuses the slot (its previous frame is then known to be complete).
#pragma once
#include "engine/device.h"

#include <array>
#include <functional>

namespace ml {

// Every pass the module records. Later passes (shadows) add entries here and a name in passName().
enum class Pass : uint32_t {
    GBuffer,
    ClusterBounds,
    LightAssign,
    VsmMark,   // virtual shadow maps: pages from the depth buffer
    VsmAlloc,  // scan, allocate, assign (caching, invalidation, LRU)
    VsmHpb,    // hierarchical page buffer
    VsmCull,   // instance culling into per-mip draw lists
    VsmExpand, // mesh path: instance culling and expansion into per-mip meshlet lists
    VsmDraw,   // clear and draw the dirty pages
    Evaluate,
    Statistics, // per-pixel light counts (optional)
    Count
};
constexpr uint32_t kPassCount = uint32_t(Pass::Count);
const char* passName(Pass pass);

struct PassTimes {
    std::array<double, kPassCount> ms{};    // GPU milliseconds per pass
    std::array<double, kPassCount> startMs{}; // pass start on the GPU clock (ms; only differences mean anything)
    std::array<bool, kPassCount> ran{};     // the pass was recorded this frame
    double totalMs() const;
};

// Timestamps: vkCmdWriteTimestamp2 pairs (GPUs). Fenced: each pass is submitted on its own and timed
// with the host clock from submit to completion. lavapipe needs Fenced: llvmpipe writes timestamps from
// its rasteriser bins, so they do not bracket compute dispatches (measured: a 700 ms evaluation pass
// read as 0.03 ms), while on a CPU device a pass's wall time is its device time.
enum class TimingMode : uint32_t { Timestamps, Fenced };

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
