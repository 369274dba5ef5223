#include "engine/device.h"

#include <GLFW/glfw3.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ml {

namespace {
std::atomic<uint32_t> gValidationErrors{0};
std::atomic<uint32_t> gValidationPerf{0};

// Messages that are known layer defects of the Debian 1.3.239 layers against a Vulkan 1.4 driver and
// say nothing about our usage. Each is listed with its reason; nothing else is filtered.
bool ignoredMessage(const VkDebugUtilsMessengerCallbackDataEXT* data) {
    (void)data;
    return false;
}

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT type,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
    if (ignoredMessage(data)) return VK_FALSE;
    bool perf = (type & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT) &&
                !(type & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT);
    const char* kind = perf ? "performance" : (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error"
                                                                                                      : "warning";
    std::fprintf(stderr, "validation %s: %s\n", kind, data->pMessage);
    if (perf) gValidationPerf++;
    else gValidationErrors++;
    return VK_FALSE;
}

bool envFlag(const char* name) {
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0;
}

bool hasLayer(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

bool hasDeviceExtension(VkPhysicalDevice pd, const char* name) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> exts(count);
    vkEnumerateDeviceExtensionProperties(pd, nullptr, &count, exts.data());
    for (auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}
} // namespace

uint32_t validationErrors() { return gValidationErrors.load(); }
uint32_t validationPerfWarnings() { return gValidationPerf.load(); }
void resetValidationCounters() {
    gValidationErrors = 0;
    gValidationPerf = 0;
}

const char* vkResultName(VkResult r) {
    switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    default: return "VkResult(other)";
    }
}

Result<std::unique_ptr<Device>> Device::create(const DeviceOptions& options) {
    std::unique_ptr<Device> d(new Device());
    d->owned_ = true;
    d->validation_ = options.validation || envFlag("ML_VALIDATION");

    std::vector<const char*> layers;
    std::vector<const char*> extensions = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    if (d->validation_) {
        if (!hasLayer("VK_LAYER_KHRONOS_validation"))
            return fail("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                        "(Debian package vulkan-validationlayers)");
        layers.push_back("VK_LAYER_KHRONOS_validation");
    }
    if (options.window) {
        if (!glfwInit()) return fail("--window: GLFW could not initialise (no display? DISPLAY is unset or unreachable)");
        uint32_t n = 0;
        const char** glfwExt = glfwGetRequiredInstanceExtensions(&n);
        if (!glfwExt) return fail("--window: GLFW found no Vulkan surface support on this display");
        for (uint32_t i = 0; i < n; ++i) extensions.push_back(glfwExt[i]);
    }

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "manylights";
    app.apiVersion = VK_API_VERSION_1_3;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    ici.enabledLayerCount = uint32_t(layers.size());
    ici.ppEnabledLayerNames = layers.data();
    ici.enabledExtensionCount = uint32_t(extensions.size());
    ici.ppEnabledExtensionNames = extensions.data();
    VkResult r = vkCreateInstance(&ici, nullptr, &d->instance);
    if (r != VK_SUCCESS)
        return fail(std::string("vkCreateInstance failed: ") + vkResultName(r) +
                    " (is a Vulkan driver installed? setup installs Mesa lavapipe: tools/setup.sh)");

    auto createMessenger = (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
        d->instance, "vkCreateDebugUtilsMessengerEXT");
    if (d->validation_ && createMessenger) {
        VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
        mci.pfnUserCallback = debugCallback;
        VK_CHECK(createMessenger(d->instance, &mci, nullptr, &d->messenger_));
    }

    uint32_t count = 0;
    vkEnumeratePhysicalDevices(d->instance, &count, nullptr);
    if (count == 0) return fail("no Vulkan device found (setup installs Mesa lavapipe from bookworm-backports)");
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(d->instance, &count, devices.data());

    std::string rejected;
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(pd, &props);
        if (!options.preferDevice.empty() && !std::strstr(props.deviceName, options.preferDevice.c_str())) continue;
        std::string why;
        if (props.apiVersion < VK_API_VERSION_1_3) why = "Vulkan 1.3 not supported";
        else if (!hasDeviceExtension(pd, VK_EXT_MESH_SHADER_EXTENSION_NAME))
            why = "no VK_EXT_mesh_shader (bookworm's Mesa 22 lacks it; install Mesa 25 from bookworm-backports)";
        else if (!hasDeviceExtension(pd, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) why = "no VK_KHR_push_descriptor";
        else if (!props.limits.timestampComputeAndGraphics) why = "no timestamps on graphics/compute queues";
        if (why.empty()) {
            d->physicalDevice = pd;
            d->properties = props;
            break;
        }
        rejected += std::string(" ") + props.deviceName + ": " + why + ";";
    }
    if (!d->physicalDevice) return fail("no suitable Vulkan device:" + rejected);
    d->name = d->properties.deviceName;
    d->timestampPeriodNs = d->properties.limits.timestampPeriod;
    vkGetPhysicalDeviceMemoryProperties(d->physicalDevice, &d->memoryProperties);

    uint32_t qcount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d->physicalDevice, &qcount, nullptr);
    std::vector<VkQueueFamilyProperties> qprops(qcount);
    vkGetPhysicalDeviceQueueFamilyProperties(d->physicalDevice, &qcount, qprops.data());
    d->queueFamily = ~0u;
    for (uint32_t i = 0; i < qcount; ++i)
        if ((qprops[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
                (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT) &&
            qprops[i].timestampValidBits > 0) {
            d->queueFamily = i;
            break;
        }
    if (d->queueFamily == ~0u) return fail(d->name + ": no graphics+compute queue with timestamps");

    // Features: check what we need, then enable exactly that.
    VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES, &mesh};
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &f13};
    VkPhysicalDeviceVulkan11Features f11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES, &f12};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f11};
    vkGetPhysicalDeviceFeatures2(d->physicalDevice, &f2);
    if (!mesh.meshShader || !mesh.taskShader) return fail(d->name + ": mesh and task shaders not supported");
    if (!f13.dynamicRendering || !f13.synchronization2 || !f13.maintenance4)
        return fail(d->name + ": dynamic rendering / synchronization2 / maintenance4 missing");
    if (!f12.shaderBufferInt64Atomics || !f12.shaderSharedInt64Atomics || !f12.hostQueryReset ||
        !f12.scalarBlockLayout || !f12.storageBuffer8BitAccess || !f12.drawIndirectCount)
        return fail(d->name + ": 64-bit atomics, host query reset, scalar layout, 8-bit storage or draw indirect count missing");
    if (!f2.features.shaderInt64 || !f2.features.multiDrawIndirect || !f2.features.fragmentStoresAndAtomics ||
        !f2.features.drawIndirectFirstInstance)
        return fail(d->name + ": shaderInt64 / multiDrawIndirect / fragmentStoresAndAtomics / drawIndirectFirstInstance missing");

    VkPhysicalDeviceMeshShaderFeaturesEXT meshOn{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
    meshOn.meshShader = VK_TRUE;
    meshOn.taskShader = VK_TRUE;
    VkPhysicalDeviceVulkan13Features on13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES, &meshOn};
    on13.dynamicRendering = on13.synchronization2 = on13.maintenance4 = VK_TRUE;
    VkPhysicalDeviceVulkan12Features on12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &on13};
    on12.shaderBufferInt64Atomics = on12.shaderSharedInt64Atomics = on12.hostQueryReset = VK_TRUE;
    on12.scalarBlockLayout = on12.storageBuffer8BitAccess = on12.drawIndirectCount = VK_TRUE;
    on12.shaderInt8 = f12.shaderInt8;
    VkPhysicalDeviceVulkan11Features on11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES, &on12};
    on11.shaderDrawParameters = f11.shaderDrawParameters;
    on11.storageBuffer16BitAccess = f11.storageBuffer16BitAccess;
    VkPhysicalDeviceFeatures2 on2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &on11};
    on2.features.shaderInt64 = on2.features.multiDrawIndirect = on2.features.fragmentStoresAndAtomics = VK_TRUE;
    on2.features.drawIndirectFirstInstance = VK_TRUE;
    on2.features.shaderInt16 = f2.features.shaderInt16;

    std::vector<const char*> devExt = {VK_EXT_MESH_SHADER_EXTENSION_NAME, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    if (options.window) devExt.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = d->queueFamily;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &on2};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = uint32_t(devExt.size());
    dci.ppEnabledExtensionNames = devExt.data();
    r = vkCreateDevice(d->physicalDevice, &dci, nullptr, &d->device);
    if (r != VK_SUCCESS) return fail(d->name + ": vkCreateDevice failed: " + vkResultName(r));
    vkGetDeviceQueue(d->device, d->queueFamily, 0, &d->queue);
    if (auto res = d->loadFunctions(); !res) return fail(res.error());
    return d;
}

Result<std::unique_ptr<Device>> Device::borrow(const DeviceBorrow& h) {
    if (!h.instance || !h.physicalDevice || !h.device || !h.queue)
        return fail("DeviceBorrow: instance, physicalDevice, device and queue must all be set");
    std::unique_ptr<Device> d(new Device());
    d->owned_ = false;
    d->instance = h.instance;
    d->physicalDevice = h.physicalDevice;
    d->device = h.device;
    d->queue = h.queue;
    d->queueFamily = h.queueFamily;
    vkGetPhysicalDeviceProperties(d->physicalDevice, &d->properties);
    vkGetPhysicalDeviceMemoryProperties(d->physicalDevice, &d->memoryProperties);
    d->name = d->properties.deviceName;
    d->timestampPeriodNs = d->properties.limits.timestampPeriod;
    if (!hasDeviceExtension(d->physicalDevice, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME))
        return fail(d->name + ": borrowed device lacks VK_KHR_push_descriptor");
    if (auto res = d->loadFunctions(); !res) return fail(res.error());
    return d;
}

Result<void> Device::loadFunctions() {
    cmdPushDescriptorSet = (PFN_vkCmdPushDescriptorSetKHR)vkGetDeviceProcAddr(device, "vkCmdPushDescriptorSetKHR");
    cmdDrawMeshTasks = (PFN_vkCmdDrawMeshTasksEXT)vkGetDeviceProcAddr(device, "vkCmdDrawMeshTasksEXT");
    cmdDrawMeshTasksIndirect =
        (PFN_vkCmdDrawMeshTasksIndirectEXT)vkGetDeviceProcAddr(device, "vkCmdDrawMeshTasksIndirectEXT");
    if (!cmdPushDescriptorSet) return fail(name + ": vkCmdPushDescriptorSetKHR not available (extension not enabled?)");
    beginLabel_ = (PFN_vkCmdBeginDebugUtilsLabelEXT)vkGetInstanceProcAddr(instance, "vkCmdBeginDebugUtilsLabelEXT");
    endLabel_ = (PFN_vkCmdEndDebugUtilsLabelEXT)vkGetInstanceProcAddr(instance, "vkCmdEndDebugUtilsLabelEXT");
    setName_ = (PFN_vkSetDebugUtilsObjectNameEXT)vkGetInstanceProcAddr(instance, "vkSetDebugUtilsObjectNameEXT");
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queueFamily;
    VK_CHECK(vkCreateCommandPool(device, &pci, nullptr, &setupPool_));
    return {};
}

Device::~Device() {
    if (device) vkDeviceWaitIdle(device);
    if (setupPool_) vkDestroyCommandPool(device, setupPool_, nullptr);
    if (!owned_) return;
    if (device) vkDestroyDevice(device, nullptr);
    if (messenger_) {
        auto destroy = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(instance,
                                                                                 "vkDestroyDebugUtilsMessengerEXT");
        destroy(instance, messenger_, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
}

VkCommandBuffer Device::beginOneTime() const {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = setupPool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd;
    VK_CHECK(vkAllocateCommandBuffers(device, &ai, &cmd));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    return cmd;
}

void Device::endOneTime(VkCommandBuffer cmd) const {
    VK_CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    VK_CHECK(vkQueueSubmit(queue, 1, &si, VK_NULL_HANDLE));
    VK_CHECK(vkQueueWaitIdle(queue));
    vkFreeCommandBuffers(device, setupPool_, 1, &cmd);
}

void Device::beginLabel(VkCommandBuffer cmd, const char* label) const {
    if (!beginLabel_) return;
    VkDebugUtilsLabelEXT l{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    l.pLabelName = label;
    beginLabel_(cmd, &l);
}
void Device::endLabel(VkCommandBuffer cmd) const {
    if (endLabel_) endLabel_(cmd);
}
void Device::setName(VkObjectType type, uint64_t handle, const char* objName) const {
    if (!setName_) return;
    VkDebugUtilsObjectNameInfoEXT ni{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    ni.objectType = type;
    ni.objectHandle = handle;
    ni.pObjectName = objName;
    setName_(device, &ni);
}

uint32_t Device::memoryType(uint32_t typeBits, VkMemoryPropertyFlags flags) const {
    for (uint32_t i = 0; i < memoryProperties.memoryTypeCount; ++i)
        if ((typeBits & (1u << i)) && (memoryProperties.memoryTypes[i].propertyFlags & flags) == flags) return i;
    return ~0u;
}

} // namespace ml
