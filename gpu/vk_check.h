// ML_VK_CHECK: every Vulkan call whose failure is a bug (not an expected condition) goes through it; it
// names the file, the line and the VkResult, then aborts. Fallible setup returns Result instead.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdio>
#include <cstdlib>

namespace ml {
const char* vkResultName(VkResult result);
}

#define ML_VK_CHECK(call)                                                                                    \
    do {                                                                                                     \
        VkResult vk_check_result_ = (call);                                                                  \
        if (vk_check_result_ != VK_SUCCESS) {                                                                \
            std::fprintf(stderr, "%s:%d: %s failed: %s\n", __FILE__, __LINE__, #call,                        \
                         ::ml::vkResultName(vk_check_result_));                                              \
            std::abort();                                                                                    \
        }                                                                                                    \
    } while (0)
