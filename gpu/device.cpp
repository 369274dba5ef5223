#include "gpu/device.h"

#include "gpu/memory.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ml {

namespace {
std::atomic<uint32_t> gValidationErrors{0};
std::atomic<uint32_t> gValidationPerf{0};

VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT type,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
    bool perf = (type & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT) &&
                !(type & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT);
    const char* kind = perf                                                         ? "performance"
                       : (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ? "error"
                                                                                    : "warning";
    std::fprintf(stderr, "validation %s: %s\n", kind, data->pMessage);
    if (perf)
        gValidationPerf++;
    else
        gValidationErrors++;
    return VK_FALSE;
}

bool envFlag(const char* name) {
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0;
}

// The layer's spec version, or 0 when it is not installed.
uint32_t layerVersion(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return l.specVersion;
    return 0;
}
bool hasLayer(const char* name) {
    return layerVersion(name) != 0;
}

// An instance extension a layer provides (VK_EXT_validation_features comes with the validation layer).
bool hasLayerExtension(const char* layer, const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceExtensionProperties(layer, &count, nullptr);
    std::vector<VkExtensionProperties> exts(count);
    vkEnumerateInstanceExtensionProperties(layer, &count, exts.data());
    for (auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
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

// The features the module needs, as a chain of the structs that hold them. One instance reads what a
// physical device supports, another what create() enables or what a host says it enabled.
struct FeatureChain {
    VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES, &mesh};
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, &f13};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    FeatureChain() = default;
    FeatureChain(const FeatureChain&) = delete; // the pNext links point into this object
};

// THE table: create() enables every row, borrow() checks every row; device.h lists the names (tested).
struct FeatureRow {
    const char* name;
    VkBool32* (*field)(FeatureChain&);
};
#define ML_FEATURE(part, member)                                                                             \
    {                                                                                                        \
#member, [](FeatureChain & c) { return &c.part.member; }                                             \
    }
const FeatureRow kRequiredFeatures[] = {
    ML_FEATURE(f13, dynamicRendering),         // G-buffer and dual-depth passes without render passes
    ML_FEATURE(f13, synchronization2),         // every barrier and timestamp
    ML_FEATURE(f13, maintenance4),             // LocalSizeId: workgroup sizes from config.h constants
    ML_FEATURE(f12, shaderBufferInt64Atomics), // 64-bit atomicAdd on the frame counters
    ML_FEATURE(f12,
               shaderSharedInt64Atomics),     // no shader uses it today (kept: the module always required it)
    ML_FEATURE(f12, hostQueryReset),          // the profiler resets its queries from the host
    ML_FEATURE(f12, scalarBlockLayout),       // shaders/shared structs are laid out as in C++
    ML_FEATURE(f12, storageBuffer8BitAccess), // no shader uses it today (kept: the module always required it)
    ML_FEATURE(f2.features, shaderInt64),     // 64-bit counters
    ML_FEATURE(f2.features, multiDrawIndirect),         // one indirect multi-draw per G-buffer
    ML_FEATURE(f2.features, fragmentStoresAndAtomics),  // dual depth bake, shadow pages: atomics in fragments
    ML_FEATURE(f2.features, drawIndirectFirstInstance), // shadow-page draws: firstInstance indexes drawInfo
    ML_FEATURE(f12, drawIndirectCount),                 // two indirect-count draws per shadow-page mip
    ML_FEATURE(mesh, meshShader),                       // no mesh/task shader yet: the virtual shadow maps'
    ML_FEATURE(mesh, taskShader),                // culling is planned on them (Device::cmdDrawMeshTasks)
    ML_FEATURE(f2.features, shaderClipDistance), // shadow-page draws clipped to their page (both paths)
};
#undef ML_FEATURE
const char* const kRequiredExtensions[] = {VK_EXT_MESH_SHADER_EXTENSION_NAME,
                                           VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};

// Names of the rows not set in `chain`, comma-separated (empty when all are).
std::string missingFeatures(FeatureChain& chain) {
    std::string missing;
    for (const FeatureRow& row : kRequiredFeatures)
        if (!*row.field(chain)) missing += (missing.empty() ? "" : ", ") + std::string(row.name);
    return missing;
}

// Reads a host's enabled-feature chain into `out`: the aggregate structs are copied whole, the
// individual (promoted) structs set their members.
void readEnabledChain(const VkPhysicalDeviceFeatures2* host, FeatureChain& out) {
    for (auto* s = reinterpret_cast<const VkBaseInStructure*>(host); s; s = s->pNext) {
        switch (s->sType) {
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2:
            out.f2.features = reinterpret_cast<const VkPhysicalDeviceFeatures2*>(s)->features;
            break;
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES: {
            void* next = out.f12.pNext;
            out.f12 = *reinterpret_cast<const VkPhysicalDeviceVulkan12Features*>(s);
            out.f12.pNext = next;
            break;
        }
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES: {
            void* next = out.f13.pNext;
            out.f13 = *reinterpret_cast<const VkPhysicalDeviceVulkan13Features*>(s);
            out.f13.pNext = next;
            break;
        }
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT: {
            auto* m = reinterpret_cast<const VkPhysicalDeviceMeshShaderFeaturesEXT*>(s);
            out.mesh.meshShader = m->meshShader;
            out.mesh.taskShader = m->taskShader;
            break;
        }
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES:
            out.f13.dynamicRendering =
                reinterpret_cast<const VkPhysicalDeviceDynamicRenderingFeatures*>(s)->dynamicRendering;
            break;
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES:
            out.f13.synchronization2 =
                reinterpret_cast<const VkPhysicalDeviceSynchronization2Features*>(s)->synchronization2;
            break;
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_4_FEATURES:
            out.f13.maintenance4 =
                reinterpret_cast<const VkPhysicalDeviceMaintenance4Features*>(s)->maintenance4;
            break;
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_INT64_FEATURES: {
            auto* a = reinterpret_cast<const VkPhysicalDeviceShaderAtomicInt64Features*>(s);
            out.f12.shaderBufferInt64Atomics = a->shaderBufferInt64Atomics;
            out.f12.shaderSharedInt64Atomics = a->shaderSharedInt64Atomics;
            break;
        }
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_HOST_QUERY_RESET_FEATURES:
            out.f12.hostQueryReset =
                reinterpret_cast<const VkPhysicalDeviceHostQueryResetFeatures*>(s)->hostQueryReset;
            break;
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SCALAR_BLOCK_LAYOUT_FEATURES:
            out.f12.scalarBlockLayout =
                reinterpret_cast<const VkPhysicalDeviceScalarBlockLayoutFeatures*>(s)->scalarBlockLayout;
            break;
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_8BIT_STORAGE_FEATURES:
            out.f12.storageBuffer8BitAccess =
                reinterpret_cast<const VkPhysicalDevice8BitStorageFeatures*>(s)->storageBuffer8BitAccess;
            break;
        default:
            break;
        }
    }
}

// A queue family the module can use: graphics + compute on one queue, timestamps for the profiler.
bool usableQueueFamily(const VkQueueFamilyProperties& q) {
    constexpr VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    return (q.queueFlags & need) == need && q.timestampValidBits > 0;
}
} // namespace

std::vector<std::string> requiredDeviceFeatures() {
    std::vector<std::string> names;
    for (const FeatureRow& row : kRequiredFeatures) names.push_back(row.name);
    return names;
}
std::vector<std::string> requiredDeviceExtensions() {
    return {std::begin(kRequiredExtensions), std::end(kRequiredExtensions)};
}

namespace faultInjection {
namespace {
std::atomic<uint64_t> gFailAt{0}, gPassed{0};
}
void failAt(uint64_t n) {
    gFailAt = n;
    gPassed = 0;
}
uint64_t allocationPoints() {
    return gPassed.load();
}
bool injected() {
    const uint64_t n = ++gPassed;
    return gFailAt.load() != 0 && n == gFailAt.load();
}
} // namespace faultInjection

uint32_t validationErrors() {
    return gValidationErrors.load();
}
uint32_t validationPerfWarnings() {
    return gValidationPerf.load();
}
void resetValidationCounters() {
    gValidationErrors = 0;
    gValidationPerf = 0;
}

const char* vkResultName(VkResult r) {
    switch (r) {
    case VK_SUCCESS:
        return "VK_SUCCESS";
    case VK_NOT_READY:
        return "VK_NOT_READY";
    case VK_TIMEOUT:
        return "VK_TIMEOUT";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
        return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
        return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
        return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
        return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_LAYER_NOT_PRESENT:
        return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
        return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
        return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
        return "VK_ERROR_INCOMPATIBLE_DRIVER";
    default:
        return "VkResult(other)";
    }
}

Result<std::unique_ptr<Device>> Device::create(const DeviceOptions& options) {
    std::unique_ptr<Device> d(new Device());
    d->owned_ = true;
    const bool sync = options.validationSync || envFlag("ML_VALIDATION_SYNC");
    d->validation_ = options.validation || sync || envFlag("ML_VALIDATION");

    std::vector<const char*> layers;
    std::vector<const char*> extensions = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    // Synchronization validation: the layer tracks every access of every command and reports hazards
    // (read-after-write, write-after-read, write-after-write) no barrier orders. Layer 1.3.239 (bookworm)
    // has no VK_EXT_layer_settings; VkValidationFeaturesEXT turns it on.
    const VkValidationFeatureEnableEXT syncFeature =
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT validationFeatures{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    validationFeatures.enabledValidationFeatureCount = 1;
    validationFeatures.pEnabledValidationFeatures = &syncFeature;
    if (d->validation_) {
        if (!hasLayer("VK_LAYER_KHRONOS_validation"))
            return fail("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                        "(Debian package vulkan-validationlayers)");
        layers.push_back("VK_LAYER_KHRONOS_validation");
        if (sync) {
            if (!hasLayerExtension("VK_LAYER_KHRONOS_validation", VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME))
                return fail(
                    "synchronization validation requested (ML_VALIDATION_SYNC) but the validation layer "
                    "lacks VK_EXT_validation_features");
            extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
            d->validationSync_ = true;
            const uint32_t v = layerVersion("VK_LAYER_KHRONOS_validation");
            std::fprintf(stderr,
                         "manylights: synchronization validation on (VK_LAYER_KHRONOS_validation %u.%u.%u)\n",
                         VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), VK_API_VERSION_PATCH(v));
        }
    }
    if (options.window) {
        if (!options.windowExtensions)
            return fail("--window: DeviceOptions::windowExtensions is not set (the host's window library)");
        uint32_t n = 0;
        const char** windowExt = options.windowExtensions(&n);
        if (!windowExt)
            return fail("--window: the window library found no Vulkan surface support on this display");
        for (uint32_t i = 0; i < n; ++i) extensions.push_back(windowExt[i]);
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
    if (d->validationSync_) ici.pNext = &validationFeatures;
    VkResult r = vkCreateInstance(&ici, nullptr, &d->instance);
    if (r != VK_SUCCESS)
        return fail(std::string("vkCreateInstance failed: ") + vkResultName(r) +
                    " (is a Vulkan driver installed? setup installs Mesa lavapipe: tools/setup.sh)");

    auto createMessenger = (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
        d->instance, "vkCreateDebugUtilsMessengerEXT");
    if (d->validation_ && createMessenger) {
        VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        mci.messageSeverity =
            VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
        mci.pfnUserCallback = debugCallback;
        ML_VK_CHECK(createMessenger(d->instance, &mci, nullptr, &d->messenger_));
    }

    uint32_t count = 0;
    vkEnumeratePhysicalDevices(d->instance, &count, nullptr);
    if (count == 0)
        return fail("no Vulkan device found (setup installs Mesa lavapipe from bookworm-backports)");
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(d->instance, &count, devices.data());

    std::string rejected;
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(pd, &props);
        if (!options.preferDevice.empty() && !std::strstr(props.deviceName, options.preferDevice.c_str()))
            continue;
        std::string why;
        if (props.apiVersion < VK_API_VERSION_1_3)
            why = "Vulkan 1.3 not supported";
        else if (!props.limits.timestampComputeAndGraphics)
            why = "no timestamps on graphics/compute queues";
        for (const char* ext : kRequiredExtensions)
            if (why.empty() && !hasDeviceExtension(pd, ext))
                why = std::string("no ") + ext +
                      (std::strcmp(ext, VK_EXT_MESH_SHADER_EXTENSION_NAME) == 0
                           ? " (bookworm's Mesa 22 lacks it; install Mesa 25 from bookworm-backports)"
                           : "");
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
        if (usableQueueFamily(qprops[i])) {
            d->queueFamily = i;
            break;
        }
    if (d->queueFamily == ~0u) return fail(d->name + ": no graphics+compute queue with timestamps");

    // Features: check the table against what the device supports, then enable exactly the table.
    FeatureChain supported;
    vkGetPhysicalDeviceFeatures2(d->physicalDevice, &supported.f2);
    if (std::string missing = missingFeatures(supported); !missing.empty())
        return fail(d->name + ": required Vulkan features not supported: " + missing);
    FeatureChain enabled;
    for (const FeatureRow& row : kRequiredFeatures) *row.field(enabled) = VK_TRUE;

    std::vector<const char*> devExt(std::begin(kRequiredExtensions), std::end(kRequiredExtensions));
    if (options.window) devExt.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = d->queueFamily;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &enabled.f2};
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
    if (!h.enabledFeatures || h.enabledFeatures->sType != VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2)
        return fail(
            "DeviceBorrow: enabledFeatures must point to the VkPhysicalDeviceFeatures2 chain the device "
            "was created with (Vulkan cannot report a device's enabled features)");
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
    const std::string who = "borrowed device (" + d->name + ")";
    if (d->properties.apiVersion < VK_API_VERSION_1_3) return fail(who + ": Vulkan 1.3 not supported");

    FeatureChain enabled;
    readEnabledChain(h.enabledFeatures, enabled);
    if (std::string missing = missingFeatures(enabled); !missing.empty())
        return fail(who + ": required Vulkan features not enabled: " + missing);
    std::string missingExt;
    for (const char* ext : kRequiredExtensions) {
        bool on = false;
        for (const std::string& e : h.enabledExtensions) on = on || e == ext;
        if (!on) missingExt += (missingExt.empty() ? "" : ", ") + std::string(ext);
    }
    if (!missingExt.empty()) return fail(who + ": required extensions not enabled: " + missingExt);

    uint32_t qcount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d->physicalDevice, &qcount, nullptr);
    std::vector<VkQueueFamilyProperties> qprops(qcount);
    vkGetPhysicalDeviceQueueFamilyProperties(d->physicalDevice, &qcount, qprops.data());
    if (h.queueFamily >= qcount)
        return fail(who + ": queue family " + std::to_string(h.queueFamily) + " does not exist (" +
                    std::to_string(qcount) + " families)");
    if (!usableQueueFamily(qprops[h.queueFamily]))
        return fail(
            who + ": queue family " + std::to_string(h.queueFamily) +
            " lacks graphics, compute or timestamps (the module records both kinds of pass on one queue)");
    if (h.queueIndex >= qprops[h.queueFamily].queueCount)
        return fail(who + ": queue index " + std::to_string(h.queueIndex) + " out of range for family " +
                    std::to_string(h.queueFamily));
    VkQueue expected = VK_NULL_HANDLE;
    vkGetDeviceQueue(d->device, h.queueFamily, h.queueIndex, &expected);
    if (expected != h.queue)
        return fail(who + ": queue is not queue " + std::to_string(h.queueIndex) + " of family " +
                    std::to_string(h.queueFamily) + " of this device");
    if (auto res = d->loadFunctions(); !res) return fail(res.error());
    return d;
}

Result<void> Device::loadFunctions() {
    cmdPushDescriptorSet =
        (PFN_vkCmdPushDescriptorSetKHR)vkGetDeviceProcAddr(device, "vkCmdPushDescriptorSetKHR");
    cmdDrawMeshTasks = (PFN_vkCmdDrawMeshTasksEXT)vkGetDeviceProcAddr(device, "vkCmdDrawMeshTasksEXT");
    cmdDrawMeshTasksIndirect =
        (PFN_vkCmdDrawMeshTasksIndirectEXT)vkGetDeviceProcAddr(device, "vkCmdDrawMeshTasksIndirectEXT");
    if (!cmdPushDescriptorSet)
        return fail(name + ": vkCmdPushDescriptorSetKHR not available (extension not enabled?)");
    beginLabel_ =
        (PFN_vkCmdBeginDebugUtilsLabelEXT)vkGetInstanceProcAddr(instance, "vkCmdBeginDebugUtilsLabelEXT");
    endLabel_ = (PFN_vkCmdEndDebugUtilsLabelEXT)vkGetInstanceProcAddr(instance, "vkCmdEndDebugUtilsLabelEXT");
    setName_ =
        (PFN_vkSetDebugUtilsObjectNameEXT)vkGetInstanceProcAddr(instance, "vkSetDebugUtilsObjectNameEXT");
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queueFamily;
    if (VkResult r = vkCreateCommandPool(device, &pci, nullptr, &setupPool_); r != VK_SUCCESS) {
        setupPool_ = VK_NULL_HANDLE;
        return fail(name + ": vkCreateCommandPool for the setup pool failed: " + vkResultName(r));
    }
    return {};
}

Device::~Device() {
    if (device) waitDevice();
    if (setupPool_) vkDestroyCommandPool(device, setupPool_, nullptr);
    if (!owned_) return;
    if (device) vkDestroyDevice(device, nullptr);
    if (messenger_) {
        auto destroy = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
            instance, "vkDestroyDebugUtilsMessengerEXT");
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
    ML_VK_CHECK(vkAllocateCommandBuffers(device, &ai, &cmd));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    ML_VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    return cmd;
}

void Device::endOneTime(VkCommandBuffer cmd) const {
    ML_VK_CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    ML_VK_CHECK(submit(si, VK_NULL_HANDLE));
    ML_VK_CHECK(waitQueue());
    vkFreeCommandBuffers(device, setupPool_, 1, &cmd);
}

Result<VkCommandBuffer> Device::tryBeginOneTime(const char* what) const {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = setupPool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    if (VkResult r = ML_VK_ALLOC(vkAllocateCommandBuffers(device, &ai, &cmd)); r != VK_SUCCESS)
        return fail(std::string("vkAllocateCommandBuffers for '") + what + "' failed: " + vkResultName(r));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    ML_VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    return cmd;
}

Result<void> Device::tryEndOneTime(VkCommandBuffer cmd, const char* what) const {
    VkResult r = vkEndCommandBuffer(cmd);
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    const char* call = "vkEndCommandBuffer";
    if (r == VK_SUCCESS) call = "vkQueueSubmit", r = ML_VK_ALLOC(submit(si, VK_NULL_HANDLE));
    if (r == VK_SUCCESS) call = "vkQueueWaitIdle", r = waitQueue();
    vkFreeCommandBuffers(device, setupPool_, 1, &cmd);
    if (r != VK_SUCCESS) return fail(std::string(call) + " for '" + what + "' failed: " + vkResultName(r));
    return {};
}

void Device::countQueueOp(bool isSubmit) const {
    (isSubmit ? submits_ : waits_)++;
    if (recordDepth_) (isSubmit ? recordSubmits_ : recordWaits_)++;
}

VkResult Device::submit(const VkSubmitInfo& info, VkFence fence) const {
    countQueueOp(true);
    return vkQueueSubmit(queue, 1, &info, fence);
}

VkResult Device::waitQueue() const {
    countQueueOp(false);
    return vkQueueWaitIdle(queue);
}

VkResult Device::waitDevice() const {
    countQueueOp(false);
    return vkDeviceWaitIdle(device);
}

VkResult Device::waitFences(uint32_t count, const VkFence* fences) const {
    countQueueOp(false);
    return vkWaitForFences(device, count, fences, VK_TRUE, UINT64_MAX);
}

MemoryUsage Device::memoryUsage() const {
    MemoryUsage u;
    for (uint32_t k = 0; k < kMemoryKindCount; ++k) u.bytes[k] = memoryBytes_[k].load();
    for (uint32_t r = 0; r < 4; ++r) u.roleBytes[r] = roleBytes_[r].load();
    return u;
}

std::string Device::memoryPlacement() const {
    return describePlacement(memoryProperties);
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

} // namespace ml
