// Time per static shadow lookup, isolated from the frame (shadows/tools/bench_lookup.comp): the same
// (receiver, light) pairs, N lookups each, timed at 1 and 1 + K lookups per pair; the difference over
// K * pairs is the cost of one lookup. K grows (x4) until the difference is >= 40 ms. Used by `bench static`
// for every method, resolution and PCF size in one run. Owns its Vulkan device (the lookups need no scene
// and no module). Part of shadows/tools/ (see gpu_dual_renderer.h): GPU tools of the static shadow
// commands, below apps/, which include only their headers.
#pragma once
#include "manylights/result.h"
#include "shaders/shared/gpu_types.h"

#include <glm/glm.hpp>

#include <memory>
#include <vector>

namespace ml {

struct LookupPair {
    glm::vec3 p, n;
    uint32_t record; // index into the records
};

struct LookupTiming {
    uint32_t radius = 0;        // PCF radius (0 one tap, 1 3x3 ... 4 9x9)
    double nsPerLookup = 0;     // min over repetitions of (T(1 + K) - T(1)) / (K * pairs)
    double spread = 0;          // (max - min) / min of the repetitions' per-lookup figures
    uint64_t cpuMismatches = 0; // pairs whose one-lookup GPU value differs from the CPU twin
    uint32_t lookups = 0;       // K used: grown from the caller's until K lookups take >= 40 ms
};

class LookupTimer {
  public:
    // Makes its own device (DeviceOptions: validation when ML_VALIDATION=1).
    static Result<std::unique_ptr<LookupTimer>> create();
    ~LookupTimer();
    // The device's maxStorageBufferRange: `words` larger than this cannot be bound.
    uint64_t maxStorageBufferRange() const;
    // records' base words index into `words`. Pairs are uploaded once per call.
    Result<std::vector<LookupTiming>> measure(const std::vector<gpu::GpuShadowRecord>& records,
                                              const std::vector<uint32_t>& words,
                                              const std::vector<LookupPair>& pairs,
                                              const std::vector<uint32_t>& radii, uint32_t extraLookups,
                                              uint32_t repetitions);

  private:
    struct State;
    explicit LookupTimer(std::unique_ptr<State> s);
    std::unique_ptr<State> s_;
};

} // namespace ml
