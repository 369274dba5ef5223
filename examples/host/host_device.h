// The example host's own Vulkan instance and device, made the way an engine makes them and then lent to
// the module (ModuleOptions::borrow): Vulkan 1.3, the validation layer with a message counter of the
// host's own (the module installs no messenger on a borrowed instance), synchronization validation on
// request, and a device with exactly the features and extensions manylights/device.h lists.
#pragma once
#include <manylights/manylights.h>

#include <vulkan/vulkan.h>

#include <cstdint>

struct HostDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    // The feature chain given to vkCreateDevice (the module's borrow() reads it).
    VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES, &mesh};
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &f13};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};

    ml::DeviceBorrow borrow() const;
};

// Exits with a one-line reason when no suitable device or no validation layer is found. `sync`: also
// synchronization validation (hazards between the host's and the module's commands).
void createHostDevice(HostDevice& host, bool sync);
void destroyHostDevice(HostDevice& host);
// Validation errors and warnings the host's messenger received (each also printed on stderr).
uint32_t hostValidationMessages();
