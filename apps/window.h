// --window: shows the module's output in a GLFW window (X11/Wayland through lavapipe's WSI) by
// blitting it into the swapchain image each frame. Fails with a clear message without a display.
// Input for the interactive camera and key commands comes from poll(): held keys and mouse drags as
// FlyInput, key presses in order (a press and release between two polls is not lost).
#pragma once
#include "manylights/manylights.h"
#include "host/fly_camera.h"

#include <string>
#include <vector>

struct GLFWwindow;

namespace ml {

class Window {
  public:
    // Before Module::create: initialises GLFW and hands its surface extensions to the module's device
    // (the module links no window library).
    static Result<void> prepareDevice(DeviceOptions& options);
    static Result<std::unique_ptr<Window>> open(Module& module, uint32_t width, uint32_t height);
    ~Window();
    bool shouldClose() const;
    void close();
    void setTitle(const std::string& title);

    struct Input {
        FlyInput fly;
        std::vector<int> pressed; // GLFW key codes pressed since the last poll
    };
    // Processes window events; returns what the user did since the last call.
    Input poll();
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
    std::vector<int> pressed_;
    double cursorX_ = 0.0, cursorY_ = 0.0;
    bool dragging_ = false;
    static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void onButton(GLFWwindow* window, int button, int action, int mods);
};

} // namespace ml
