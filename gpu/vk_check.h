// ML_VK_CHECK: every Vulkan call whose failure is a bug (not an expected condition) goes through it; it
// names the file, the line and the VkResult, then aborts. Fallible setup returns Result instead:
// allocations and object creations (memory, buffers, images, views, shaders, pipelines, layouts, query
// pools, command buffers, submissions) can run out of memory on any device, so on the module's paths
// they go through ML_VK_ALLOC and return a Result naming what failed; ML_TRY passes a failed Result up.
//
// Fault injection (tests): every ML_VK_ALLOC is an allocation point. faultInjection::failAt(n) makes the
// n-th point reached from then on return VK_ERROR_OUT_OF_DEVICE_MEMORY instead of calling Vulkan (n = 0:
// off); allocationPoints() counts the points passed since the last failAt. Process-wide counters.
#pragma once
#include "manylights/result.h"

#include <vulkan/vulkan.h>

#include <cstdio>
#include <cstdlib>

namespace ml {
const char* vkResultName(VkResult result);

namespace faultInjection {
void failAt(uint64_t n);
uint64_t allocationPoints();
bool injected(); // true when the point being passed is the one to fail (counts it); used by ML_VK_ALLOC
} // namespace faultInjection
} // namespace ml

// A VkResult: the call's, or VK_ERROR_OUT_OF_DEVICE_MEMORY without calling it when injected.
#define ML_VK_ALLOC(call) (::ml::faultInjection::injected() ? VK_ERROR_OUT_OF_DEVICE_MEMORY : (call))

// Returns a failed Result (any Result<T>) from the enclosing function, keeping its message.
#define ML_TRY(expr)                                                                                         \
    do {                                                                                                     \
        if (auto ml_try_ = (expr); !ml_try_) return ::ml::fail(ml_try_.error());                             \
    } while (0)

#define ML_VK_CHECK(call)                                                                                    \
    do {                                                                                                     \
        VkResult vk_check_result_ = (call);                                                                  \
        if (vk_check_result_ != VK_SUCCESS) {                                                                \
            std::fprintf(stderr, "%s:%d: %s failed: %s\n", __FILE__, __LINE__, #call,                        \
                         ::ml::vkResultName(vk_check_result_));                                              \
            std::abort();                                                                                    \
        }                                                                                                    \
    } while (0)
