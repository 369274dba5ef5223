#include "engine/limits.h"

#include "engine/manylights_diagnostics.h"

#include "gpu/device.h"
#include "shaders/shared/config.h"
#include "shaders/shared/gpu_types.h"
#include "shadows/virtual/vsm_types.h"

#include <algorithm>
#include <bit>

namespace ml {

DeviceLimitTable deviceLimitTable(const Device& device) {
    const VkPhysicalDeviceLimits& l = device.properties.limits;
    DeviceLimitTable t;
    for (int k = 0; k < 3; ++k) t.maxWorkGroupCount[k] = l.maxComputeWorkGroupCount[k];
    t.maxStorageBufferRange = l.maxStorageBufferRange;
    t.maxImageDimension2D = l.maxImageDimension2D;
    t.maxImageArrayLayers = l.maxImageArrayLayers;
    t.maxDrawIndirectCount = l.maxDrawIndirectCount;
    VkPhysicalDeviceMaintenance4Properties m4{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_4_PROPERTIES};
    VkPhysicalDeviceMaintenance3Properties m3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    const bool v13 = device.properties.apiVersion >= VK_API_VERSION_1_3;
    m3.pNext = v13 ? &m4 : nullptr;
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &m3};
    vkGetPhysicalDeviceProperties2(device.physicalDevice, &p2);
    t.maxMemoryAllocationSize = m3.maxMemoryAllocationSize;
    t.maxBufferSize = v13 ? m4.maxBufferSize : m3.maxMemoryAllocationSize;
    const VkPhysicalDeviceMemoryProperties& mp = device.memoryProperties;
    for (uint32_t h = 0; h < mp.memoryHeapCount; ++h)
        if (mp.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            t.deviceLocalHeap = std::max<uint64_t>(t.deviceLocalHeap, mp.memoryHeaps[h].size);
    return t;
}

namespace {
std::string mib(uint64_t bytes) {
    return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}
// The clustered grid (the largest: tiled mode has one slice) of a target size.
uint64_t clustersOf(uint32_t width, uint32_t height) {
    const uint64_t tiles =
        uint64_t((width + ML_TILE_SIZE - 1) / ML_TILE_SIZE) * ((height + ML_TILE_SIZE - 1) / ML_TILE_SIZE);
    return tiles * ML_CLUSTER_SLICES;
}
} // namespace

uint64_t targetBytes(uint32_t width, uint32_t height, bool ownTargets) {
    const uint64_t px = uint64_t(width) * height, clusters = clustersOf(width, height);
    // depth 4 + normal 8 + albedo 4 + material 2 (owned G-buffer), HDR 8, output 4, readback 4 bytes per
    // pixel.
    const uint64_t images = px * ((ownTargets ? 18 : 0) + 8 + 4 + 4);
    // Cluster bounds, ranges, counts; the pool (16 entries per cluster) and its hits (a quarter, 8 B).
    const uint64_t pool = clusters * ML_POOL_PER_CLUSTER;
    const uint64_t culling =
        clusters * (sizeof(gpu::ClusterBounds) + 8 + 4) + pool * 4 + pool / ML_HITS_PER_POOL_ENTRY_DIV * 8;
    return images + culling;
}

Result<void> checkTargetLimits(const DeviceLimitTable& l, uint32_t width, uint32_t height, bool ownTargets) {
    const std::string size = "size " + std::to_string(width) + "x" + std::to_string(height);
    const uint32_t side = std::max(width, height);
    if (side > l.maxImageDimension2D)
        return fail(size + ": an image side of " + std::to_string(side) + " exceeds the device's " +
                    "maxImageDimension2D " + std::to_string(l.maxImageDimension2D));
    const uint64_t px = uint64_t(width) * height;
    // The largest image per pixel: HDR (and the owned normal target), RGBA16F, 8 bytes.
    if (px * 8 > l.maxMemoryAllocationSize)
        return fail(size + ": the HDR image needs " + mib(px * 8) + ", past the device's " +
                    "maxMemoryAllocationSize " + mib(l.maxMemoryAllocationSize));
    // The per-cluster buffers are bound whole; the largest is the bounds (32 B per cluster; the pool
    // is reduced to fit: fitClusterPool).
    const uint64_t bounds = clustersOf(width, height) * sizeof(gpu::ClusterBounds);
    if (bounds > l.maxStorageBufferRange)
        return fail(size + ": the cluster bounds need " + mib(bounds) + " in one storage buffer, past " +
                    "the device's maxStorageBufferRange " + mib(l.maxStorageBufferRange));
    const uint64_t tiles = clustersOf(width, height) / ML_CLUSTER_SLICES;
    const uint64_t allocGroups = (tiles + ML_ALLOC_GROUP - 1) / ML_ALLOC_GROUP;
    if (allocGroups > l.maxWorkGroupCount[0])
        return fail(size + ": the light-list allocation needs " + std::to_string(allocGroups) +
                    " workgroups in one dimension, past the device's maxComputeWorkGroupCount " +
                    std::to_string(l.maxWorkGroupCount[0]));
    const uint64_t total = targetBytes(width, height, ownTargets);
    if (l.deviceLocalHeap && total > l.deviceLocalHeap / 2)
        return fail(size + ": the targets and cluster buffers need " + mib(total) + ", past half the " +
                    "device-local memory heap (" + mib(l.deviceLocalHeap) + ")");
    return {};
}

Result<VsmSettings> fitVsmSettings(const DeviceLimitTable& l, const VsmSettings& in,
                                   std::vector<std::string>& notes) {
    VsmSettings s = in;
    if (!s.enabled) return s;
    const uint64_t range = std::min(l.maxStorageBufferRange, l.maxMemoryAllocationSize);
    const uint32_t s0 = s.resolution / s.pageSize;
    const uint32_t mips = uint32_t(std::countr_zero(s0)) + 1;
    uint64_t entriesPerMap = 0;
    for (uint32_t m = 0; m < mips; ++m) entriesPerMap += uint64_t(s0 >> m) * (s0 >> m);
    const std::string res =
        std::to_string(s.resolution) + "^2 maps of " + std::to_string(s.pageSize) + "^2 pages";
    // The page table holds every map slot's entries (4 B each) in one binding.
    const uint64_t maxMaps = range / (entriesPerMap * 4);
    if (maxMaps < 1)
        return fail("vsm: the page table of one map (" + res + ") needs " + mib(entriesPerMap * 4) +
                    ", past the device's maxStorageBufferRange " + mib(range));
    // The default maxMaps (VsmSettings) means "as many as the device holds": reduced without a note; a
    // host's own value that does not fit is reduced with one. Lights past the slots are counted
    // (lights_without_slot) either way.
    if (s.maxMaps > maxMaps) {
        if (in.maxMaps != VsmSettings{}.maxMaps)
            notes.push_back("vsm: map slots " + std::to_string(s.maxMaps) + " -> " + std::to_string(maxMaps) +
                            ": the page table of " + res + " fits the device's maxStorageBufferRange " +
                            mib(range) + " for that many (lights past them get no map, counted)");
        s.maxMaps = uint32_t(maxMaps);
    }
    // The physical pool (4 B per texel) is one binding too.
    const uint64_t pageBytes = uint64_t(s.pageSize) * s.pageSize * 4 * (s.staticLayer ? 2 : 1); // and twin
    const uint64_t maxPool = std::min<uint64_t>(range / pageBytes, ML_VSM_PHYS_MASK);
    if (s.poolPages > maxPool) {
        notes.push_back("vsm: pool pages " + std::to_string(s.poolPages) + " -> " + std::to_string(maxPool) +
                        ": " + std::to_string(s.pageSize) + "^2 pages" +
                        (s.staticLayer ? " and their static twins" : "") + " fit the device's " +
                        "maxStorageBufferRange " + mib(range) +
                        " that many times (past them, coarser pages, "
                        "counted as fallbacks)");
        s.poolPages = uint32_t(maxPool);
    }
    const uint64_t probes = 16 + uint64_t(s.probeCapacity) * sizeof(gpu::GpuVsmProbe);
    if (s.probeCapacity && probes > range)
        return fail("vsm: probe capacity " + std::to_string(s.probeCapacity) + " needs " + mib(probes) +
                    ", past the device's maxStorageBufferRange " + mib(range));
    const uint64_t meshlets = uint64_t(mips) * s.maxMeshletsPerMip * 12;
    if (s.raster != VsmRaster::Vertex && meshlets > range)
        return fail("vsm: max meshlets per mip " + std::to_string(s.maxMeshletsPerMip) + " needs " +
                    mib(meshlets) + ", past the device's maxStorageBufferRange " + mib(range));
    const uint64_t draws = uint64_t(mips) * s.maxDrawsPerMip * 20;
    if (draws > range)
        return fail("vsm: max draws per mip " + std::to_string(s.maxDrawsPerMip) + " needs " + mib(draws) +
                    ", past the device's maxStorageBufferRange " + mib(range));
    if (s.maxDrawsPerMip > l.maxDrawIndirectCount)
        return fail("vsm: max draws per mip " + std::to_string(s.maxDrawsPerMip) + " exceeds the device's " +
                    "maxDrawIndirectCount " + std::to_string(l.maxDrawIndirectCount));
    return s;
}

uint64_t diag::targetBytes(uint32_t width, uint32_t height, bool ownTargets) {
    return ml::targetBytes(width, height, ownTargets);
}

} // namespace ml
