#include "apps/window.h"

#include "gpu/vk_check.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

namespace ml {

namespace {
// One image layout transition (synchronization2), the window's own: it works on the module's device
// through the public handles only.
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 src, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dst,
                  VkAccessFlags2 dstAccess) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = src;
    b.srcAccessMask = srcAccess;
    b.dstStageMask = dst;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &dep);
}
} // namespace

Result<void> Window::prepareDevice(DeviceOptions& options) {
    if (!glfwInit())
        return fail("--window: GLFW could not initialise (no display? DISPLAY is unset or unreachable)");
    options.window = true;
    options.windowExtensions = &glfwGetRequiredInstanceExtensions;
    return {};
}

Result<std::unique_ptr<Window>> Window::open(Module& module, uint32_t width, uint32_t height) {
    std::unique_ptr<Window> w(new Window());
    w->module_ = &module;
    w->width_ = width;
    w->height_ = height;
    const DeviceInfo d = module.deviceInfo();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    w->window_ = glfwCreateWindow(int(width), int(height), "manylights", nullptr, nullptr);
    if (!w->window_) return fail("--window: could not open a window (no display?)");
    glfwSetWindowUserPointer(w->window_, w.get());
    glfwSetKeyCallback(w->window_, &Window::onKey);
    glfwSetMouseButtonCallback(w->window_, &Window::onButton);
    if (glfwCreateWindowSurface(d.instance, w->window_, nullptr, &w->surface_) != VK_SUCCESS)
        return fail("--window: could not create a Vulkan surface for the window");
    VkBool32 supported = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(d.physicalDevice, d.queueFamily, w->surface_, &supported);
    if (!supported) return fail("--window: the device's queue cannot present to this window");
    VkSurfaceCapabilitiesKHR caps;
    vkGetPhysicalDeviceSurfaceCapabilitiesKHR(d.physicalDevice, w->surface_, &caps);
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        return fail("--window: swapchain images cannot be blit targets on this surface");
    uint32_t nf = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(d.physicalDevice, w->surface_, &nf, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(nf);
    vkGetPhysicalDeviceSurfaceFormatsKHR(d.physicalDevice, w->surface_, &nf, formats.data());
    VkSurfaceFormatKHR format = formats[0];
    for (auto f : formats)
        if (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) format = f;
    w->extent_ = caps.currentExtent.width != ~0u ? caps.currentExtent : VkExtent2D{width, height};
    VkSwapchainCreateInfoKHR sci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    sci.surface = w->surface_;
    sci.minImageCount = std::max(2u, caps.minImageCount);
    if (caps.maxImageCount) sci.minImageCount = std::min(sci.minImageCount, caps.maxImageCount);
    sci.imageFormat = format.format;
    sci.imageColorSpace = format.colorSpace;
    sci.imageExtent = w->extent_;
    sci.imageArrayLayers = 1;
    sci.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    sci.preTransform = caps.currentTransform;
    sci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    sci.presentMode = VK_PRESENT_MODE_FIFO_KHR;
    sci.clipped = VK_TRUE;
    ML_VK_CHECK(vkCreateSwapchainKHR(d.device, &sci, nullptr, &w->swapchain_));
    uint32_t ni = 0;
    vkGetSwapchainImagesKHR(d.device, w->swapchain_, &ni, nullptr);
    w->images_.resize(ni);
    vkGetSwapchainImagesKHR(d.device, w->swapchain_, &ni, w->images_.data());
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = d.queueFamily;
    ML_VK_CHECK(vkCreateCommandPool(d.device, &pci, nullptr, &w->pool_));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = w->pool_;
    ai.commandBufferCount = 1;
    ML_VK_CHECK(vkAllocateCommandBuffers(d.device, &ai, &w->cmd_));
    VkSemaphoreCreateInfo semi{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    ML_VK_CHECK(vkCreateSemaphore(d.device, &semi, nullptr, &w->acquired_));
    ML_VK_CHECK(vkCreateSemaphore(d.device, &semi, nullptr, &w->rendered_));
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fi.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    ML_VK_CHECK(vkCreateFence(d.device, &fi, nullptr, &w->fence_));
    return w;
}

Window::~Window() {
    if (!module_) return;
    const DeviceInfo d = module_->deviceInfo();
    vkDeviceWaitIdle(d.device);
    if (fence_) vkDestroyFence(d.device, fence_, nullptr);
    if (acquired_) vkDestroySemaphore(d.device, acquired_, nullptr);
    if (rendered_) vkDestroySemaphore(d.device, rendered_, nullptr);
    if (pool_) vkDestroyCommandPool(d.device, pool_, nullptr);
    if (swapchain_) vkDestroySwapchainKHR(d.device, swapchain_, nullptr);
    if (surface_) vkDestroySurfaceKHR(d.instance, surface_, nullptr);
    if (window_) glfwDestroyWindow(window_);
}

bool Window::shouldClose() const {
    return glfwWindowShouldClose(window_);
}
void Window::close() {
    glfwSetWindowShouldClose(window_, GLFW_TRUE);
}
void Window::setTitle(const std::string& title) {
    glfwSetWindowTitle(window_, title.c_str());
}

void Window::onKey(GLFWwindow* window, int key, int, int action, int) {
    if (action == GLFW_PRESS) static_cast<Window*>(glfwGetWindowUserPointer(window))->pressed_.push_back(key);
}

// A drag starts where the button went down, even when the press and the first movement arrive
// between two polls (slow frames on CPU devices).
void Window::onButton(GLFWwindow* window, int, int action, int) {
    auto* self = static_cast<Window*>(glfwGetWindowUserPointer(window));
    if (action != GLFW_PRESS) return;
    glfwGetCursorPos(window, &self->cursorX_, &self->cursorY_);
    self->dragging_ = true;
}

Window::Input Window::poll() {
    glfwPollEvents();
    Input in;
    in.pressed.swap(pressed_);
    auto held = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS ? 1.0f : 0.0f; };
    in.fly.forward = held(GLFW_KEY_W) - held(GLFW_KEY_S);
    in.fly.right = held(GLFW_KEY_D) - held(GLFW_KEY_A);
    in.fly.up = held(GLFW_KEY_E) - held(GLFW_KEY_Q);
    in.fly.fast = held(GLFW_KEY_LEFT_SHIFT) + held(GLFW_KEY_RIGHT_SHIFT) > 0.0f;
    // Mouse look while the left or right button is held: the movement since the press or the
    // previous poll.
    double x, y;
    glfwGetCursorPos(window_, &x, &y);
    bool down = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS ||
                glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    if (down && dragging_) {
        in.fly.lookX = float(x - cursorX_);
        in.fly.lookY = float(y - cursorY_);
    }
    dragging_ = down;
    cursorX_ = x;
    cursorY_ = y;
    return in;
}

Result<void> Window::frame(Module& module) {
    const DeviceInfo d = module.deviceInfo();
    ML_VK_CHECK(vkWaitForFences(d.device, 1, &fence_, VK_TRUE, UINT64_MAX));
    ML_VK_CHECK(vkResetFences(d.device, 1, &fence_));
    uint32_t index = 0;
    ML_VK_CHECK(vkAcquireNextImageKHR(d.device, swapchain_, UINT64_MAX, acquired_, VK_NULL_HANDLE, &index));
    ML_VK_CHECK(vkResetCommandBuffer(cmd_, 0));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    ML_VK_CHECK(vkBeginCommandBuffer(cmd_, &bi));
    if (auto r = module.record(cmd_); !r) return r;
    VkImage target = images_[index];
    imageBarrier(cmd_, module.outputImage(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    imageBarrier(cmd_, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 VK_PIPELINE_STAGE_2_BLIT_BIT, 0, VK_PIPELINE_STAGE_2_BLIT_BIT,
                 VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkImageBlit blit{};
    blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.srcOffsets[1] = {int32_t(width_), int32_t(height_), 1};
    blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.dstOffsets[1] = {int32_t(extent_.width), int32_t(extent_.height), 1};
    vkCmdBlitImage(cmd_, module.outputImage(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
    imageBarrier(cmd_, module.outputImage(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                 VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                 VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
    imageBarrier(cmd_, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                 VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
    ML_VK_CHECK(vkEndCommandBuffer(cmd_));
    VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &acquired_;
    si.pWaitDstStageMask = &waitStage;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd_;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &rendered_;
    ML_VK_CHECK(vkQueueSubmit(d.queue, 1, &si, fence_));
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &rendered_;
    pi.swapchainCount = 1;
    pi.pSwapchains = &swapchain_;
    pi.pImageIndices = &index;
    VkResult r = vkQueuePresentKHR(d.queue, &pi);
    if (r != VK_SUCCESS && r != VK_SUBOPTIMAL_KHR)
        return fail(std::string("present failed: ") + vkResultName(r));
    return {};
}

} // namespace ml
