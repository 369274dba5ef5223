// Memory placement by role: which memory type a buffer or image gets, chosen by what the CPU and GPU do
// with it, as a pure function of the device's VkPhysicalDeviceMemoryProperties (so the MemoryPlacement
// tests run it over recorded tables of devices this machine does not have).
//
//   GpuOnly   written and read by the GPU only (cluster lists, VSM page state, images), or written by
//             the host at load time through a staging copy (uploadBuffer: geometry, static bakes):
//             DEVICE_LOCAL, never mapped. Preferred without HOST_VISIBLE, so a ReBAR/BAR heap is left
//             to uploads.
//   Upload    written by the host every frame, read by the GPU (per-slot frame constants, lights,
//             instances, VSM maps): mapped and coherent. DEVICE_LOCAL | HOST_VISIBLE where that heap is
//             large (ReBAR, integrated GPUs, lavapipe) or the buffer small against it (a 256 MiB BAR
//             with ReBAR off takes buffers up to kBarUploadFraction of it); else host memory the GPU
//             reads across the bus.
//   Readback  written by the GPU, read by the host (frame counters, VSM counters and probes, readback
//             and staging-read buffers): mapped, HOST_CACHED | HOST_COHERENT where the device has it
//             (CPU reads of uncached memory are slow), else HOST_COHERENT.
//   Staging   host-written source of a copy (uploadBuffer, uploadImage): HOST_VISIBLE | HOST_COHERENT,
//             preferably not DEVICE_LOCAL (the BAR is kept for per-frame uploads).
// Mapped roles always require HOST_COHERENT: the module never flushes or invalidates ranges. Types with
// PROTECTED, LAZILY_ALLOCATED or the AMD device-coherent bits are never chosen (slow or special).
#pragma once
#include "manylights/device.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>

namespace ml {

enum class MemoryRole : uint8_t { GpuOnly, Upload, Readback, Staging };
constexpr uint32_t kMemoryRoleCount = 4; // MemoryUsage::roleBytes has one entry per role
const char* memoryRoleName(MemoryRole role);
inline bool roleIsMapped(MemoryRole role) {
    return role != MemoryRole::GpuOnly;
}

// A BAR heap (host-visible device-local) smaller than half the largest device-local heap is "small"
// (ReBAR off: 256 MiB); uploads go there only up to 1/32 of it each (8 MiB of 256 MiB), so a few
// per-frame buffers cannot exhaust it and the rest of the driver's BAR users keep room.
constexpr uint32_t kBarUploadFraction = 32;

struct MemoryChoice {
    uint32_t type = ~0u; // ~0u: no type the resource allows fits the role
    MemoryKind kind = MemoryKind::Host;
};

// The memory type for a resource of `size` bytes whose allowed types are `typeBits`
// (VkMemoryRequirements::memoryTypeBits), in the role; pure (no Vulkan calls).
MemoryChoice selectMemoryType(const VkPhysicalDeviceMemoryProperties& props, uint32_t typeBits,
                              MemoryRole role, VkDeviceSize size);
// The kind of a memory type, by its flags (stats: bytes per kind).
MemoryKind memoryKindOf(VkMemoryPropertyFlags flags);
// One line: where each role lands on this device (size: a small buffer), e.g.
// "gpu-only -> type 0 (device-local, heap 0 8192 MiB); upload -> type 3 (...)...".
std::string describePlacement(const VkPhysicalDeviceMemoryProperties& props);

} // namespace ml
