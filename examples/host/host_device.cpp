// The example host's instance and device (host_device.h).
#include "host_device.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {
std::atomic<uint32_t> messages{0};

VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                         VkDebugUtilsMessageTypeFlagsEXT type,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    // Errors and warnings of the validation and general kinds count; performance hints are printed only.
    const bool counted = (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                                      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)) &&
                         !(type & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT);
    if (counted) messages++;
    std::fprintf(stderr, "host_example: validation%s: %s\n", counted ? "" : " (not counted)", data->pMessage);
    return VK_FALSE;
}

[[noreturn]] void die(const char* what) {
    std::fprintf(stderr, "host_example: %s\n", what);
    std::exit(1);
}
} // namespace

uint32_t hostValidationMessages() {
    return messages.load();
}

ml::DeviceBorrow HostDevice::borrow() const {
    return {instance,    physicalDevice,
            device,      queue,
            queueFamily, 0,
            &features,   {VK_EXT_MESH_SHADER_EXTENSION_NAME, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME}};
}

void createHostDevice(HostDevice& h, bool sync) {
    const char* layer = "VK_LAYER_KHRONOS_validation";
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    bool found = false;
    for (const auto& l : layers) found = found || std::strcmp(l.layerName, layer) == 0;
    if (!found) die("the validation layer VK_LAYER_KHRONOS_validation is not installed");

    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mi.pfnUserCallback = onMessage;
    VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT vf{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT, &mi};
    vf.enabledValidationFeatureCount = sync ? 1u : 0u;
    vf.pEnabledValidationFeatures = enables;
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "host_example";
    app.apiVersion = VK_API_VERSION_1_3;
    const char* ext = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, &vf};
    ici.pApplicationInfo = &app;
    ici.enabledLayerCount = 1;
    ici.ppEnabledLayerNames = &layer;
    ici.enabledExtensionCount = 1;
    ici.ppEnabledExtensionNames = &ext;
    if (vkCreateInstance(&ici, nullptr, &h.instance) != VK_SUCCESS) die("vkCreateInstance failed");
    auto createMessenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(h.instance, "vkCreateDebugUtilsMessengerEXT"));
    if (!createMessenger || createMessenger(h.instance, &mi, nullptr, &h.messenger) != VK_SUCCESS)
        die("vkCreateDebugUtilsMessengerEXT failed");

    // The first Vulkan 1.3 device with a graphics + compute queue family that has timestamps.
    vkEnumeratePhysicalDevices(h.instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(h.instance, &count, devices.data());
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(pd, &p);
        if (p.apiVersion < VK_API_VERSION_1_3) continue;
        uint32_t families = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(pd, &families, nullptr);
        std::vector<VkQueueFamilyProperties> fp(families);
        vkGetPhysicalDeviceQueueFamilyProperties(pd, &families, fp.data());
        for (uint32_t f = 0; f < families && !h.physicalDevice; ++f)
            if ((fp[f].queueFlags & VK_QUEUE_GRAPHICS_BIT) && (fp[f].queueFlags & VK_QUEUE_COMPUTE_BIT) &&
                fp[f].timestampValidBits > 0) {
                h.physicalDevice = pd;
                h.queueFamily = f;
            }
        if (h.physicalDevice) break;
    }
    if (!h.physicalDevice) die("no Vulkan 1.3 device with a graphics + compute queue with timestamps");

    // Exactly the module's requirements (manylights/device.h), as the host's own device would enable them
    // beside its own needs.
    h.mesh.meshShader = h.mesh.taskShader = VK_TRUE;
    h.f13.dynamicRendering = h.f13.synchronization2 = h.f13.maintenance4 = VK_TRUE;
    h.f12.shaderBufferInt64Atomics = h.f12.shaderSharedInt64Atomics = h.f12.hostQueryReset = VK_TRUE;
    h.f12.scalarBlockLayout = h.f12.storageBuffer8BitAccess = h.f12.drawIndirectCount = VK_TRUE;
    h.features.features.shaderInt64 = h.features.features.multiDrawIndirect = VK_TRUE;
    h.features.features.fragmentStoresAndAtomics = h.features.features.drawIndirectFirstInstance = VK_TRUE;
    h.features.features.shaderClipDistance = VK_TRUE;
    const char* deviceExtensions[] = {VK_EXT_MESH_SHADER_EXTENSION_NAME,
                                      VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = h.queueFamily;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &h.features};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = 2;
    dci.ppEnabledExtensionNames = deviceExtensions;
    if (vkCreateDevice(h.physicalDevice, &dci, nullptr, &h.device) != VK_SUCCESS)
        die("vkCreateDevice failed (mesh shaders and push descriptors are required)");
    vkGetDeviceQueue(h.device, h.queueFamily, 0, &h.queue);
}

void destroyHostDevice(HostDevice& h) {
    vkDestroyDevice(h.device, nullptr);
    auto destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(h.instance, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroyMessenger) destroyMessenger(h.instance, h.messenger, nullptr);
    vkDestroyInstance(h.instance, nullptr);
}
