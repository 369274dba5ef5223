// Device: the Vulkan instance, physical device, logical device and one graphics+compute queue.
//
// Headless by default (lavapipe on machines without a GPU). The module either creates these itself or
// borrows a host engine's handles (DeviceBorrow). Requirements: a Vulkan 1.3 physical device, a queue
// family with graphics, compute and timestamps, and exactly these features and extensions (one table in
// device.cpp: create() enables it, borrow() checks it, requiredDeviceFeatures() returns it; the test
// DeviceBorrow.DocumentedListEqualsTable reads the lines below and fails when they differ):
//   features: dynamicRendering synchronization2 maintenance4
//   features: shaderBufferInt64Atomics shaderSharedInt64Atomics hostQueryReset scalarBlockLayout
//   features: storageBuffer8BitAccess shaderInt64 multiDrawIndirect fragmentStoresAndAtomics
//   features: drawIndirectFirstInstance drawIndirectCount
//   features: meshShader taskShader
//   extensions: VK_EXT_mesh_shader VK_KHR_push_descriptor
// A device that lacks one is refused with one line naming every missing item.
//
// Validation: on when DeviceOptions::validation is set or the environment has ML_VALIDATION=1. Every
// validation error or warning is printed and counted (validationErrors()); tests fail on a non-zero
// count. Performance warnings are printed and counted apart (validationPerfWarnings()), not failed.
// Synchronization validation (hazards between commands that no barrier orders, SYNC-HAZARD-* messages,
// counted as errors) is on with DeviceOptions::validationSync or ML_VALIDATION_SYNC=1; either also
// turns validation on. It is off by default because it slows every command down.
#pragma once
#include "engine/result.h"
#include "engine/vk_check.h"

#include <atomic>
#include <memory>
#include <string>
#include <vector>

struct GLFWwindow;

namespace ml {

struct DeviceOptions {
    bool validation = false;   // also on when ML_VALIDATION=1
    bool validationSync = false; // synchronization validation (implies validation); also ML_VALIDATION_SYNC=1
    bool window = false;       // create surface-capable instance (GLFW); needs a display
    std::string preferDevice;  // substring of the device name; empty = first suitable
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

class Device {
  public:
    static Result<std::unique_ptr<Device>> create(const DeviceOptions& options);
    static Result<std::unique_ptr<Device>> borrow(const DeviceBorrow& handles);
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkPhysicalDeviceProperties properties{};
    VkPhysicalDeviceMemoryProperties memoryProperties{};
    std::string name;
    float timestampPeriodNs = 1.0f;

    // Command helpers for setup work and tests: record into a one-off command buffer, submit, wait.
    VkCommandBuffer beginOneTime() const;
    void endOneTime(VkCommandBuffer cmd) const;

    // Debug labels (no-ops without VK_EXT_debug_utils).
    void beginLabel(VkCommandBuffer cmd, const char* name) const;
    void endLabel(VkCommandBuffer cmd) const;
    void setName(VkObjectType type, uint64_t handle, const char* name) const;

    uint32_t memoryType(uint32_t typeBits, VkMemoryPropertyFlags flags) const;
    bool validationEnabled() const { return validation_; }
    bool synchronizationValidationEnabled() const { return validationSync_; }

    PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet = nullptr;
    PFN_vkCmdDrawMeshTasksEXT cmdDrawMeshTasks = nullptr;
    PFN_vkCmdDrawMeshTasksIndirectEXT cmdDrawMeshTasksIndirect = nullptr; // VSM mesh path (null: vertex path)

  private:
    Device() = default;
    Result<void> loadFunctions();
    bool owned_ = false;
    bool validation_ = false;
    bool validationSync_ = false;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkCommandPool setupPool_ = VK_NULL_HANDLE;
    PFN_vkCmdBeginDebugUtilsLabelEXT beginLabel_ = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT endLabel_ = nullptr;
    PFN_vkSetDebugUtilsObjectNameEXT setName_ = nullptr;
};

// Validation message counters, process-wide (the messenger callback has no other home).
uint32_t validationErrors();
uint32_t validationPerfWarnings();
void resetValidationCounters();

} // namespace ml
