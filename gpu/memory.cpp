#include "gpu/memory.h"

#include <algorithm>
#include <span>

namespace ml {

namespace {
constexpr VkMemoryPropertyFlags DL = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
constexpr VkMemoryPropertyFlags HV = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
constexpr VkMemoryPropertyFlags HC = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkMemoryPropertyFlags CACHED = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
// Never chosen: protected memory needs protected submissions, lazily allocated memory is for transient
// attachments, AMD's device-coherent/uncached types bypass caches (slow for everything the module does).
constexpr VkMemoryPropertyFlags kAvoid =
    VK_MEMORY_PROPERTY_PROTECTED_BIT | VK_MEMORY_PROPERTY_LAZILY_ALLOCATED_BIT |
    VK_MEMORY_PROPERTY_DEVICE_COHERENT_BIT_AMD | VK_MEMORY_PROPERTY_DEVICE_UNCACHED_BIT_AMD;

// One preference: types with all of `need` and none of `without`; `fits` filters by heap (BAR uploads).
struct Want {
    VkMemoryPropertyFlags need, without;
    bool barRule = false;
};

// The largest device-local heap (the VRAM of a discrete GPU; the one heap of an integrated GPU).
VkDeviceSize largestDeviceHeap(const VkPhysicalDeviceMemoryProperties& p) {
    VkDeviceSize best = 0;
    for (uint32_t h = 0; h < p.memoryHeapCount; ++h)
        if (p.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            best = std::max(best, p.memoryHeaps[h].size);
    return best;
}

// A host-visible device-local type takes an upload when its heap is large (ReBAR, unified memory) or the
// buffer small against it (kBarUploadFraction).
bool barFits(const VkPhysicalDeviceMemoryProperties& p, uint32_t type, VkDeviceSize size) {
    const VkDeviceSize heap = p.memoryHeaps[p.memoryTypes[type].heapIndex].size;
    if (heap >= largestDeviceHeap(p) / 2) return true;
    return size <= heap / kBarUploadFraction;
}
} // namespace

const char* memoryRoleName(MemoryRole role) {
    switch (role) {
    case MemoryRole::GpuOnly:
        return "gpu-only";
    case MemoryRole::Upload:
        return "upload";
    case MemoryRole::Readback:
        return "readback";
    case MemoryRole::Staging:
        return "staging";
    }
    return "?";
}

const char* memoryKindName(MemoryKind kind) {
    switch (kind) {
    case MemoryKind::DeviceLocal:
        return "device_local";
    case MemoryKind::DeviceMappable:
        return "device_mappable";
    case MemoryKind::Host:
        return "host";
    case MemoryKind::HostCached:
        return "host_cached";
    }
    return "?";
}

MemoryKind memoryKindOf(VkMemoryPropertyFlags f) {
    if (f & DL) return (f & HV) ? MemoryKind::DeviceMappable : MemoryKind::DeviceLocal;
    return (f & CACHED) ? MemoryKind::HostCached : MemoryKind::Host;
}

MemoryChoice selectMemoryType(const VkPhysicalDeviceMemoryProperties& p, uint32_t typeBits, MemoryRole role,
                              VkDeviceSize size) {
    // Preferences in order (the first type meeting one wins).
    static constexpr Want kGpuOnly[] = {
        {DL, HV}, {DL, 0}, {0, 0}}; // the BAR left to uploads; any as a last resort
    static constexpr Want kUpload[] = {{DL | HV | HC, CACHED, true},
                                       {DL | HV | HC, 0, true}, // BAR, by its rule
                                       {HV | HC, DL | CACHED},
                                       {HV | HC, DL},
                                       {HV | HC, 0}}; // write-combined host
    static constexpr Want kReadback[] = {
        {HV | HC | CACHED, DL}, {HV | HC | CACHED, 0}, {HV | HC, DL}, {HV | HC, 0}};
    static constexpr Want kStaging[] = {{HV | HC, DL | CACHED}, {HV | HC, DL}, {HV | HC, 0}};
    std::span<const Want> wants = role == MemoryRole::GpuOnly    ? std::span<const Want>(kGpuOnly)
                                  : role == MemoryRole::Upload   ? std::span<const Want>(kUpload)
                                  : role == MemoryRole::Readback ? std::span<const Want>(kReadback)
                                                                 : std::span<const Want>(kStaging);
    for (const Want& w : wants)
        for (uint32_t i = 0; i < p.memoryTypeCount && i < 32; ++i) {
            const VkMemoryPropertyFlags f = p.memoryTypes[i].propertyFlags;
            if (!(typeBits & (1u << i)) || (f & kAvoid) || (f & w.need) != w.need || (f & w.without))
                continue;
            if (w.barRule && !barFits(p, i, size)) continue;
            return {i, memoryKindOf(f)};
        }
    return {};
}

std::string describePlacement(const VkPhysicalDeviceMemoryProperties& p) {
    std::string out;
    for (uint32_t r = 0; r < kMemoryRoleCount; ++r) {
        const MemoryRole role = MemoryRole(r);
        const MemoryChoice c = selectMemoryType(p, ~0u, role, 1 << 16);
        out += std::string(r ? "; " : "") + memoryRoleName(role) + " -> ";
        if (c.type == ~0u) {
            out += "none";
            continue;
        }
        const VkMemoryHeap& heap = p.memoryHeaps[p.memoryTypes[c.type].heapIndex];
        out += "type " + std::to_string(c.type) + " (" + memoryKindName(c.kind) + ", heap " +
               std::to_string(p.memoryTypes[c.type].heapIndex) + " " + std::to_string(heap.size >> 20) +
               " MiB)";
    }
    return out;
}

} // namespace ml
