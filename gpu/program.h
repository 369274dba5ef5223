// Programs: shader modules, pipelines and the dispatch that records a compute pass in a few lines.
//
// Descriptor bindings, the push-constant block size and the compute local size are read from the SPIR-V
// itself (a small reflection pass), so the C++ side never restates them: `dispatch` divides thread
// counts by the shader's local size, checks sizeof(Push) against the shader's block (each push block is
// one ML_STRUCT shared by C++ and GLSL, beside its feature) and matches `Descriptors` to the shader's
// bindings in binding order, type-checked, pushed with VK_KHR_push_descriptor (no pools, no sets).
// Every compute dispatch goes through dispatch / dispatchIndirect; draws bind with bindProgram.
// Variants are specialization constants given by id at program creation, {id, value}: the shaders are
// built with -g0 (no names in the SPIR-V), so the id is the shader's `constant_id` (each shader has
// at most one, id 0, named kSpec* in its source).
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
    uint32_t pushSize = 0;                  // bytes of the push-constant block (0: none)
    std::string name;
};

// SPIR-V from the build (shaders/*.spv.h arrays): spv_<file>_<ext>. As with buffers (gpu/resources.h),
// the Result forms (out-parameter) are the module's: out of memory is an error naming the shader or
// program, and the out-parameter is left empty; the value forms abort on failure (tests, tools).
Result<void> loadShader(const Device& device, ShaderModule& out, const uint32_t* code, size_t bytes,
                        const char* name);
ShaderModule loadShader(const Device& device, const uint32_t* code, size_t bytes, const char* name);
void destroyShader(const Device& device, ShaderModule& shader);
#define ML_SHADER(device, array) ::ml::loadShader(device, array, sizeof(array), #array)
#define ML_LOAD_SHADER(device, out, array) ::ml::loadShader(device, out, array, sizeof(array), #array)

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
    uint32_t pushSize = 0; // largest push block of its stages (reflected)
    uint32_t localSize[3] = {1, 1, 1};
    uint32_t bindingCount = 0; // bindings 0..bindingCount-1, all used
    VkDescriptorType bindingTypes[32] = {};
    std::string name;
};

Result<void> createComputeProgram(const Device& device, Program& out, const ShaderModule& shader,
                                  std::initializer_list<SpecConstant> spec = {});
Program createComputeProgram(const Device& device, const ShaderModule& shader,
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
Result<void> createGraphicsProgram(const Device& device, Program& out,
                                   std::initializer_list<const ShaderModule*> shaders,
                                   const GraphicsState& state, std::initializer_list<SpecConstant> spec = {});
Program createGraphicsProgram(const Device& device, std::initializer_list<const ShaderModule*> shaders,
                              const GraphicsState& state, std::initializer_list<SpecConstant> spec = {});
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

// Binds the program and pushes descriptors (in binding order) and the push constants; aborts naming the
// program when their count, types or the push size differ from the shader's.
void bindProgram(const Device& device, VkCommandBuffer cmd, const Program& program,
                 std::initializer_list<Descriptor> descriptors, const void* push, uint32_t pushSize);

// A program without push constants takes NoPush{}.
struct NoPush {};

// Bytes a push block passes (the device's maxPushConstantsSize is checked at program creation: 128 on
// every device, 144 used by the dual depth bake).
template <class Push> constexpr uint32_t pushBytes() {
    return std::is_empty_v<Push> ? 0u : uint32_t(sizeof(Push));
}

template <class Push>
void bindProgram(const Device& device, VkCommandBuffer cmd, const Program& program, const Push& push,
                 std::initializer_list<Descriptor> descriptors) {
    bindProgram(device, cmd, program, descriptors, &push, pushBytes<Push>());
}

// Binds, then dispatches ceil(threads / local size) groups per dimension; aborts naming the program when
// a count exceeds the device's maxComputeWorkGroupCount. Nothing is recorded for zero threads.
void dispatchThreads(const Device& device, VkCommandBuffer cmd, const Program& program,
                     const uint32_t threads[3], const void* push, uint32_t pushSize,
                     std::initializer_list<Descriptor> descriptors);
// Binds, then dispatches the VkDispatchIndirectCommand at `offset` in `args` (written on the GPU, so its
// counts are the writer's to bound: vsm_scan.comp clamps them).
void dispatchIndirect(const Device& device, VkCommandBuffer cmd, const Program& program, const Buffer& args,
                      VkDeviceSize offset, const void* push, uint32_t pushSize,
                      std::initializer_list<Descriptor> descriptors);

template <class Push>
void dispatch(const Device& device, VkCommandBuffer cmd, const Program& program, uint32_t threadsX,
              uint32_t threadsY, uint32_t threadsZ, const Push& push,
              std::initializer_list<Descriptor> descriptors) {
    const uint32_t threads[3] = {threadsX, threadsY, threadsZ};
    dispatchThreads(device, cmd, program, threads, &push, pushBytes<Push>(), descriptors);
}
template <class Push>
void dispatch(const Device& device, VkCommandBuffer cmd, const Program& program, uint32_t threadsX,
              uint32_t threadsY, const Push& push, std::initializer_list<Descriptor> descriptors) {
    dispatch(device, cmd, program, threadsX, threadsY, 1, push, descriptors);
}
template <class Push>
void dispatchIndirect(const Device& device, VkCommandBuffer cmd, const Program& program, const Buffer& args,
                      VkDeviceSize offset, const Push& push, std::initializer_list<Descriptor> descriptors) {
    dispatchIndirect(device, cmd, program, args, offset, &push, pushBytes<Push>(), descriptors);
}

} // namespace ml
