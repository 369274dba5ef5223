// --window: shows the module's output in a GLFW window (X11/Wayland through lavapipe's WSI) by
// blitting it into the swapchain image each frame. Fails with a clear message without a display.
#pragma once
#include "engine/manylights.h"

struct GLFWwindow;

namespace ml {

class Window {
  public:
    static Result<std::unique_ptr<Window>> open(Module& module, uint32_t width, uint32_t height);
    ~Window();
    bool shouldClose() const;
    // Records module.record() plus the blit into a fresh swapchain image, submits and presents.
    Result<void> frame(Module& module);

  private:
    Window() = default;
    Module* module_ = nullptr;
    GLFWwindow* window_ = nullptr;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    std::vector<VkImage> images_;
    VkExtent2D extent_{};
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkSemaphore acquired_ = VK_NULL_HANDLE, rendered_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    uint32_t width_ = 0, height_ = 0;
};

} // namespace ml
