// A host's device for the borrowing tests (tests/gpu/device_borrow_test.cpp, and the pipeline-cache
// check in tests/record_queue): created on the module's physical device the way a host engine would.
#pragma once
#include "gpu/device.h"
#include "manylights/device.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ml::test {

// A host's device on the module's physical device, created the way a host engine would: the
// Vulkan 1.2/1.3 feature structs and the mesh shader struct, all required features on except `without`.
struct HostDevice {
    VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES, &mesh};
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &f13};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    std::vector<std::string> extensions = {VK_EXT_MESH_SHADER_EXTENSION_NAME,
                                           VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;

    explicit HostDevice(const Device& d, const std::string& without = "") {
        mesh.meshShader = mesh.taskShader = VK_TRUE;
        f13.dynamicRendering = f13.synchronization2 = f13.maintenance4 = VK_TRUE;
        f12.shaderBufferInt64Atomics = f12.shaderSharedInt64Atomics = f12.hostQueryReset = VK_TRUE;
        f12.scalarBlockLayout = f12.storageBuffer8BitAccess = VK_TRUE;
        f2.features.shaderInt64 = f2.features.multiDrawIndirect = f2.features.fragmentStoresAndAtomics =
            VK_TRUE;
        f2.features.drawIndirectFirstInstance = f12.drawIndirectCount = VK_TRUE;
        f2.features.shaderClipDistance = VK_TRUE;
        VkBool32* named[] = {&f13.dynamicRendering,
                             &f13.synchronization2,
                             &f13.maintenance4,
                             &f12.shaderBufferInt64Atomics,
                             &f12.shaderSharedInt64Atomics,
                             &f12.hostQueryReset,
                             &f12.scalarBlockLayout,
                             &f12.storageBuffer8BitAccess,
                             &f2.features.shaderInt64,
                             &f2.features.multiDrawIndirect,
                             &f2.features.fragmentStoresAndAtomics,
                             &f2.features.drawIndirectFirstInstance,
                             &f12.drawIndirectCount,
                             &mesh.meshShader,
                             &mesh.taskShader,
                             &f2.features.shaderClipDistance};
        auto names = requiredDeviceFeatures(); // same order as `named` (checked by the test above)
        for (size_t i = 0; i < names.size() && i < std::size(named); ++i)
            if (names[i] == without) *named[i] = VK_FALSE;
        if (without == "meshShader") mesh.taskShader = VK_FALSE; // task shaders require mesh shaders
        std::vector<const char*> ext;
        for (auto& e : extensions) ext.push_back(e.c_str());
        float priority = 1.0f;
        VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        qci.queueFamilyIndex = d.queueFamily;
        qci.queueCount = 1;
        qci.pQueuePriorities = &priority;
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &f2};
        dci.queueCreateInfoCount = 1;
        dci.pQueueCreateInfos = &qci;
        dci.enabledExtensionCount = uint32_t(ext.size());
        dci.ppEnabledExtensionNames = ext.data();
        EXPECT_EQ(vkCreateDevice(d.physicalDevice, &dci, nullptr, &device), VK_SUCCESS);
        vkGetDeviceQueue(device, d.queueFamily, 0, &queue);
    }
    ~HostDevice() { vkDestroyDevice(device, nullptr); }
    DeviceBorrow borrow(const Device& d) const {
        DeviceBorrow b{d.instance, d.physicalDevice, device, queue, d.queueFamily, 0, &f2, extensions};
        return b;
    }
};

} // namespace ml::test
