// Programs: shader modules, pipelines and the dispatch that records a compute pass in a few lines.
//
// Descriptor bindings and the compute local size are read from the SPIR-V itself (a small reflection
// pass), so the C++ side never restates them: `dispatch` divides thread counts by the shader's local
// size, and `Descriptors` are matched to the shader's bindings in binding order, type-checked, and
// pushed with VK_KHR_push_descriptor (no pools, no sets to manage).
// Variants are specialization constants given by name at program creation: {kSpecFoo, value}.
#pragma once
#include "gpu/resources.h"

#include <initializer_list>
#include <type_traits>
#include <string>
#include <vector>

namespace ml {

struct ShaderModule {
    VkShaderModule module = VK_NULL_HANDLE;
    VkShaderStageFlagBits stage = VK_SHADER_STAGE_COMPUTE_BIT;
    uint32_t localSize[3] = {1, 1, 1};
    uint32_t bindingMask = 0;               // bit b: set 0 binding b is used
    VkDescriptorType bindingTypes[32] = {}; // valid where bindingMask has the bit
    bool usesPushConstants = false;
    std::string name;
};

// SPIR-V from the build (shaders/*.spv.h arrays): spv_<file>_<ext>.
ShaderModule loadShader(const Device& device, const uint32_t* code, size_t bytes, const char* name);
void destroyShader(const Device& device, ShaderModule& shader);
#define ML_SHADER(device, array) ::ml::loadShader(device, array, sizeof(array), #array)

struct SpecConstant {
    uint32_t id;
    uint32_t value;
};

struct Program {
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineBindPoint bindPoint = VK_PIPELINE_BIND_POINT_COMPUTE;
    VkShaderStageFlags stages = 0;
    uint32_t pushSize = 0;
    uint32_t localSize[3] = {1, 1, 1};
    uint32_t bindingCount = 0; // bindings 0..bindingCount-1, all used
    VkDescriptorType bindingTypes[32] = {};
    std::string name;
};

Program createComputeProgram(const Device& device, const ShaderModule& shader, uint32_t pushSize,
                             std::initializer_list<SpecConstant> spec = {});

struct GraphicsState {
    std::vector<VkFormat> colorFormats;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
    VkCullModeFlags cull = VK_CULL_MODE_BACK_BIT;
    VkFrontFace frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    bool depthTest = true;
    bool depthWrite = true;
    // The camera's G-buffer uses reversed Z (near = 1, cleared to 0): GREATER keeps the nearest surface.
    VkCompareOp depthCompare = VK_COMPARE_OP_GREATER;
    bool depthClamp = false;
};
Program createGraphicsProgram(const Device& device, std::initializer_list<const ShaderModule*> shaders,
                              uint32_t pushSize, const GraphicsState& state,
                              std::initializer_list<SpecConstant> spec = {});
void destroyProgram(const Device& device, Program& program);

// One descriptor: a buffer (whole range) or an image view in a layout.
struct Descriptor {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceSize offset = 0, range = VK_WHOLE_SIZE;
    VkImageView view = VK_NULL_HANDLE;
    VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL;
    VkSampler sampler = VK_NULL_HANDLE;
    Descriptor(const Buffer& b) : buffer(b.buffer) {}
    Descriptor(const Image& i, VkImageLayout l = VK_IMAGE_LAYOUT_GENERAL) : view(i.view), layout(l) {}
    // One view of an image (Image::mipView, layerViews).
    Descriptor(VkImageView v, VkImageLayout l = VK_IMAGE_LAYOUT_GENERAL) : view(v), layout(l) {}
};

// Binds the program and pushes descriptors (in binding order) and the push constants.
void bindProgram(const Device& device, VkCommandBuffer cmd, const Program& program,
                 std::initializer_list<Descriptor> descriptors, const void* push, uint32_t pushSize);

// Aborts naming the program when a dispatch exceeds the 65535 groups per dimension every device has.
void checkGroupCount(const Program& program, uint32_t groupsX, uint32_t groupsY);

// A program without push constants takes NoPush{}.
struct NoPush {};

// Binds, checks the push size and descriptors against the shader's reflection (bindProgram aborts with
// the program's name on a mismatch) and dispatches ceil(threads / local size) groups.
template <class Push>
void dispatch(const Device& device, VkCommandBuffer cmd, const Program& program, uint32_t threadsX,
              uint32_t threadsY, const Push& push, std::initializer_list<Descriptor> descriptors) {
    static_assert(sizeof(Push) <= 128, "push constants are limited to 128 bytes");
    constexpr uint32_t pushSize = std::is_empty_v<Push> ? 0u : uint32_t(sizeof(Push));
    bindProgram(device, cmd, program, descriptors, &push, pushSize);
    uint32_t gx = (threadsX + program.localSize[0] - 1) / program.localSize[0];
    uint32_t gy = (threadsY + program.localSize[1] - 1) / program.localSize[1];
    checkGroupCount(program, gx, gy);
    if (gx && gy) vkCmdDispatch(cmd, gx, gy, 1);
}

} // namespace ml
