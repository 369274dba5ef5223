// Device: the Vulkan instance, physical device, logical device and one graphics+compute queue (internal:
// the module's base layer). The API types (DeviceOptions, DeviceBorrow, DeviceInfo, the requirements and
// the validation counters) are in the public manylights/device.h.
//
// Headless by default (lavapipe on machines without a GPU). The module either creates these itself or
// borrows a host engine's handles (DeviceBorrow).
//
// Validation: on when DeviceOptions::validation is set or the environment has ML_VALIDATION=1. Every
// validation error or warning is printed and counted (validationErrors()); tests fail on a non-zero
// count. Performance warnings are printed and counted apart (validationPerfWarnings()), not failed.
// Synchronization validation (hazards between commands that no barrier orders, SYNC-HAZARD-* messages,
// counted as errors) is on with DeviceOptions::validationSync or ML_VALIDATION_SYNC=1; either also
// turns validation on. It is off by default because it slows every command down.
#pragma once
#include "manylights/device.h"
#include "manylights/result.h"
#include "gpu/vk_check.h"

#include <atomic>
#include <memory>
#include <string>
#include <vector>

struct GLFWwindow;

namespace ml {

struct FrameSetup; // gpu/resources.h

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
    // The try forms are the module's (allocation points: out of memory is an error naming `what`; a
    // failed end frees the command buffer); the plain forms abort on failure (tests, tools, fenced timing).
    VkCommandBuffer beginOneTime() const;
    void endOneTime(VkCommandBuffer cmd) const;
    Result<VkCommandBuffer> tryBeginOneTime(const char* what) const;
    Result<void> tryEndOneTime(VkCommandBuffer cmd, const char* what) const;

    // Queue access (record() never touches the host's queue): every submit and every queue, device or fence
    // wait the module makes goes through these four, which count it; the ones made while record() runs (a
    // RecordScope is open) are counted apart, so a hidden submit or wait behind the host's back cannot go
    // unseen. The source check QueueAccess.OnlyDeviceCallsTheQueue (tests/record_queue) keeps direct calls
    // out of the module.
    VkResult submit(const VkSubmitInfo& info, VkFence fence) const;
    VkResult waitQueue() const;
    VkResult waitDevice() const;
    VkResult waitFences(uint32_t count, const VkFence* fences) const;
    struct QueueCounts {
        uint64_t submits = 0, waits = 0; // vkQueueSubmit; vkQueueWaitIdle, vkDeviceWaitIdle, vkWaitForFences
    };
    QueueCounts queueCounts() const { return {submits_.load(), waits_.load()}; }
    QueueCounts recordQueueCounts() const { return {recordSubmits_.load(), recordWaits_.load()}; }
    // Pipelines created (gpu/program.cpp counts each vkCreate*Pipelines), and those inside record():
    // every pipeline a frame can use is built before it (Module::create, createTargets, setTargets).
    void countPipelineBuild() const {
        pipelines_++;
        if (recordDepth_) recordPipelines_++;
    }
    uint64_t pipelineBuilds() const { return pipelines_.load(); }
    uint64_t recordPipelineBuilds() const { return recordPipelines_.load(); }
    // Open for the whole of Module::record (nested scopes count once).
    class RecordScope {
      public:
        explicit RecordScope(const Device& d) : d_(d) { ++d_.recordDepth_; }
        ~RecordScope() { --d_.recordDepth_; }
        RecordScope(const RecordScope&) = delete;
        RecordScope& operator=(const RecordScope&) = delete;

      private:
        const Device& d_;
    };

    // The module's setup commands for the frame being recorded (gpu/resources.h): while it is set and
    // active, createDeviceBuffer queues its fill there instead of submitting it. Owned by the module.
    FrameSetup* frameSetup = nullptr;
    // The host's pipeline cache (ModuleOptions::pipelineCache), or none: every pipeline is built with it.
    VkPipelineCache pipelineCache = VK_NULL_HANDLE;

    // Bytes of live allocations per memory kind (gpu/resources.cpp counts each allocation and free).
    void countMemory(MemoryKind kind, uint32_t role, int64_t bytes) const {
        memoryBytes_[uint32_t(kind)] += uint64_t(bytes);
        roleBytes_[role] += uint64_t(bytes);
    }
    MemoryUsage memoryUsage() const;
    // Where each buffer role lands on this device (gpu/memory.h), one line; printed once by hosts that
    // want it (the demo) and written to stats.json.
    std::string memoryPlacement() const;

    // Debug labels (no-ops without VK_EXT_debug_utils).
    void beginLabel(VkCommandBuffer cmd, const char* name) const;
    void endLabel(VkCommandBuffer cmd) const;
    void setName(VkObjectType type, uint64_t handle, const char* name) const;

    bool validationEnabled() const { return validation_; }
    bool synchronizationValidationEnabled() const { return validationSync_; }

    PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet = nullptr;
    PFN_vkCmdDrawMeshTasksEXT cmdDrawMeshTasks = nullptr;
    PFN_vkCmdDrawMeshTasksIndirectEXT cmdDrawMeshTasksIndirect = nullptr; // VSM mesh path (null: vertex path)

  private:
    Device() = default;
    Result<void> loadFunctions();
    bool owned_ = false;
    void countQueueOp(bool submit) const;
    mutable std::atomic<uint64_t> submits_ = 0, waits_ = 0, recordSubmits_ = 0, recordWaits_ = 0;
    mutable std::atomic<uint64_t> pipelines_ = 0, recordPipelines_ = 0;
    mutable std::atomic<uint32_t> recordDepth_ = 0;
    mutable std::atomic<uint64_t> memoryBytes_[kMemoryKindCount] = {};
    mutable std::atomic<uint64_t> roleBytes_[4] = {};
    bool validation_ = false;
    bool validationSync_ = false;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkCommandPool setupPool_ = VK_NULL_HANDLE;
    PFN_vkCmdBeginDebugUtilsLabelEXT beginLabel_ = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT endLabel_ = nullptr;
    PFN_vkSetDebugUtilsObjectNameEXT setName_ = nullptr;
};

} // namespace ml
