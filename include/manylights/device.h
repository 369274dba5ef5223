// Device API types (manylights/module.h): how the module gets its device (its own, DeviceOptions, or the
// host's, DeviceBorrow), the plain handles a host reads back (DeviceInfo), the required features and the
// validation counters. No Vulkan wrapper classes.
//
// Requirements: a Vulkan 1.3 physical device, a queue family with graphics, compute and timestamps, and
// exactly these features and extensions (create() enables them, borrow() checks them,
// requiredDeviceFeatures() and requiredDeviceExtensions() return them; a test keeps this list equal to the
// module's table):
//   features: dynamicRendering synchronization2 maintenance4
//   features: shaderBufferInt64Atomics shaderSharedInt64Atomics hostQueryReset scalarBlockLayout
//   features: storageBuffer8BitAccess shaderInt64 multiDrawIndirect fragmentStoresAndAtomics
//   features: drawIndirectFirstInstance drawIndirectCount
//   features: meshShader taskShader shaderClipDistance
//   extensions: VK_EXT_mesh_shader VK_KHR_push_descriptor
// A device that lacks one is refused with one line naming every missing item.
//
// Validation: on when DeviceOptions::validation is set or the environment has ML_VALIDATION=1. Every
// validation error or warning is printed and counted (validationErrors()); tests fail on a non-zero
// count. Performance warnings are printed and counted apart (validationPerfWarnings()), not failed.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

namespace ml {

struct DeviceOptions {
    bool validation = false;     // also on when ML_VALIDATION=1
    bool validationSync = false; // synchronization validation (implies validation); also ML_VALIDATION_SYNC=1
    bool window = false;         // create surface-capable instance; needs windowExtensions
    // The instance extensions a window needs, from the host's window library (the demo passes
    // glfwGetRequiredInstanceExtensions after glfwInit): the module itself links no window library.
    const char** (*windowExtensions)(uint32_t* count) = nullptr;
    std::string preferDevice; // substring of the device name; empty = first suitable
};

// Handles a host engine already owns. The host keeps ownership; the module never destroys them, and
// the host destroys the module before them. Vulkan cannot report which features and extensions a
// device was created with, so the host passes what it gave vkCreateDevice: enabledFeatures is the
// VkPhysicalDeviceFeatures2 chain (VkDeviceCreateInfo::pNext; the Vulkan11/12/13 feature structs, the
// individual promoted structs, VkPhysicalDeviceMeshShaderFeaturesEXT are read; a host that used
// pEnabledFeatures puts those in VkPhysicalDeviceFeatures2::features) and enabledExtensions its
// ppEnabledExtensionNames. Both are read by borrow() only; they need not outlive it.
struct DeviceBorrow {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE; // must be vkGetDeviceQueue(device, queueFamily, queueIndex)
    uint32_t queueFamily = 0;       // graphics + compute + timestamps
    uint32_t queueIndex = 0;        // a queue the host created in that family
    const VkPhysicalDeviceFeatures2* enabledFeatures = nullptr; // required
    std::vector<std::string> enabledExtensions;
};

// The features (Vulkan structure member names) and extensions every device must have enabled.
std::vector<std::string> requiredDeviceFeatures();
std::vector<std::string> requiredDeviceExtensions();

// The device the module runs on (its own or the borrowed one), as plain handles: for the host's own
// work on the same device (swapchain, G-buffer, command pools). The module keeps ownership of a device it
// created; the host must destroy what it made on it before destroying the module.
struct DeviceInfo {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    std::string name;            // VkPhysicalDeviceProperties::deviceName
    bool validation = false;     // the module's own device was made with the validation layer
    std::string memoryPlacement; // where each buffer role's memory lands (memory type flags), one line
};

// Where the module's memory lives (the module chooses a type per buffer role), by memory type flags:
//   DeviceLocal     DEVICE_LOCAL, not host-visible (GPU-only data on a discrete GPU)
//   DeviceMappable  DEVICE_LOCAL | HOST_VISIBLE (a BAR or ReBAR heap; all memory of integrated GPUs and
//                   CPU devices)
//   Host            HOST_VISIBLE, not device-local, uncached (system memory the GPU reads over the bus)
//   HostCached      HOST_VISIBLE | HOST_CACHED, not device-local (readbacks)
enum class MemoryKind : uint8_t { DeviceLocal, DeviceMappable, Host, HostCached };
constexpr uint32_t kMemoryKindCount = 4;
const char* memoryKindName(MemoryKind kind); // "device_local", "device_mappable", "host", "host_cached"
// Bytes of the module's live allocations (buffers and images) per kind (Module::memoryUsage, stats.json).
struct MemoryUsage {
    uint64_t bytes[kMemoryKindCount] = {};
    uint64_t roleBytes[4] = {}; // by role: gpu-only, upload, readback, staging
};

// Validation message counters, process-wide (the messenger callback has no other home).
uint32_t validationErrors();
uint32_t validationPerfWarnings();
void resetValidationCounters();

} // namespace ml
