// Device limits checked where the module chooses sizes: the render targets' size (createTargets /
// setTargets) and the virtual shadow maps' settings (Module::create). Pure functions over a table of
// limits, so they are unit-tested on recorded tables (tests/apps/limits_test.cpp: lavapipe and a
// desktop GPU) without a device. A size past a limit is refused with one line naming the setting, its
// value, what it needs and the limit; a capacity that only bounds how much fits in a frame (the VSM
// pool and map slots here; the light-list pool in culling/culling.cpp) is reduced to what the device
// holds, with a line saying so.
#pragma once
#include "manylights/result.h"
#include "manylights/vsm_settings.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ml {

struct Device;

// The limits used (VkPhysicalDeviceLimits; maintenance3/4's allocation and buffer sizes; the largest
// device-local memory heap). Defaults: Vulkan's required minimums, heap unknown (0: not checked).
struct DeviceLimitTable {
    uint32_t maxWorkGroupCount[3] = {65535, 65535, 65535};
    uint64_t maxStorageBufferRange = uint64_t(1) << 27;
    uint32_t maxImageDimension2D = 4096;
    uint32_t maxImageArrayLayers = 256;
    uint64_t maxMemoryAllocationSize = uint64_t(1) << 30;
    uint64_t maxBufferSize = uint64_t(1) << 30;
    uint64_t deviceLocalHeap = 0;
    uint32_t maxDrawIndirectCount =
        65535; // the VSM page draws' indirect count (vkCmdDrawIndexedIndirectCount)
};

DeviceLimitTable deviceLimitTable(const Device& device);

// Bytes the module allocates for targets of width x height (G-buffer when the module owns it, HDR and
// output images, the cluster buffers, the readback), for the heap check and `--max-memory` estimates.
uint64_t targetBytes(uint32_t width, uint32_t height, bool ownTargets);

// Refuses a target size whose images or per-pixel buffers pass a limit: image side (maxImageDimension2D),
// one image's bytes (maxMemoryAllocationSize), the per-cluster buffers (maxStorageBufferRange), the
// light-list allocation's one-dimensional dispatch (maxComputeWorkGroupCount[0]), all targets together
// (the device-local heap). "size WxH: ..." one line.
Result<void> checkTargetLimits(const DeviceLimitTable& limits, uint32_t width, uint32_t height,
                               bool ownTargets);

// The VSM settings as the device holds them: map slots and pool pages reduced to what one storage
// buffer binding holds (each reduction one line in `notes`); probe records, meshlet and draw lists past
// it and draws per mip past maxDrawIndirectCount refused naming the setting. The default maxMaps is
// reduced without a note (it means "as many as the device holds").
Result<VsmSettings> fitVsmSettings(const DeviceLimitTable& limits, const VsmSettings& settings,
                                   std::vector<std::string>& notes);

} // namespace ml
