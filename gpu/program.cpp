#include "gpu/program.h"
#include "gpu/bindings.h"

#include <algorithm>
#include <cassert>
#include <cstdio>
#include <vector>

namespace ml {

namespace {

// Minimal SPIR-V reflection: entry stage, LocalSize, the descriptor type of every set-0 binding and
// the size of the push-constant block. Opcodes and enums from the SPIR-V specification, section 3.
enum : uint32_t {
    OpEntryPoint = 15,
    OpExecutionMode = 16,
    OpTypeInt = 21,
    OpTypeFloat = 22,
    OpTypeVector = 23,
    OpTypeMatrix = 24,
    OpTypeImage = 25,
    OpTypeSampler = 26,
    OpTypeSampledImage = 27,
    OpTypeArray = 28,
    OpTypeRuntimeArray = 29,
    OpTypeStruct = 30,
    OpTypePointer = 32,
    OpVariable = 59,
    OpDecorate = 71,
    OpTypeAccelerationStructureKHR = 5341
};
enum : uint32_t {
    DecArrayStride = 6,
    DecMatrixStride = 7,
    DecBlock = 2,
    DecBufferBlock = 3,
    DecBinding = 33,
    DecDescriptorSet = 34,
    DecOffset = 35
};
enum : uint32_t { OpMemberDecorate = 72 };
enum : uint32_t { ScUniformConstant = 0, ScUniform = 2, ScPushConstant = 9, ScStorageBuffer = 12 };

struct Id {
    uint32_t opcode = 0;
    uint32_t typeId = 0;
    uint32_t storageClass = 0;
    uint32_t binding = ~0u, set = ~0u;
    uint32_t sampled = 0; // OpTypeImage Sampled operand
    uint32_t width = 0;   // OpTypeInt / OpTypeFloat: bits; OpTypeVector / OpTypeMatrix / OpTypeArray: count
    uint32_t stride = 0;  // ArrayStride of an array type
    bool block = false, bufferBlock = false;
    std::vector<uint32_t> members;                // OpTypeStruct member type ids
    std::vector<uint32_t> offsets, matrixStrides; // per member (Offset, MatrixStride decorations)
};

// Bytes a value of type `t` spans in an explicitly laid-out block (push constants): scalars and vectors
// by their width, matrices and arrays by their strides, structs up to the end of their last member.
uint32_t typeBytes(const std::vector<Id>& ids, const std::vector<uint32_t>& constants, uint32_t t,
                   uint32_t matrixStride = 0) {
    const Id& ty = ids[t];
    switch (ty.opcode) {
    case OpTypeInt:
    case OpTypeFloat:
        return ty.width / 8;
    case OpTypeVector:
        return ty.width * typeBytes(ids, constants, ty.typeId);
    case OpTypeMatrix:
        return ty.width * (matrixStride ? matrixStride : typeBytes(ids, constants, ty.typeId));
    case OpTypeArray:
        return constants[ty.width] * ty.stride;
    case OpTypeStruct: {
        uint32_t end = 0;
        for (size_t m = 0; m < ty.members.size(); ++m) {
            uint32_t off = m < ty.offsets.size() ? ty.offsets[m] : 0;
            uint32_t ms = m < ty.matrixStrides.size() ? ty.matrixStrides[m] : 0;
            end = std::max(end, off + typeBytes(ids, constants, ty.members[m], ms));
        }
        return end;
    }
    default:
        return 0;
    }
}

void memberDecoration(std::vector<uint32_t>& v, uint32_t member, uint32_t value) {
    if (v.size() <= member) v.resize(member + 1, 0);
    v[member] = value;
}

void reflect(ShaderModule& sm, const uint32_t* code, size_t words) {
    assert(words >= 5 && code[0] == 0x07230203);
    uint32_t bound = code[3];
    std::vector<Id> ids(bound);
    std::vector<uint32_t> constants(bound, 0);
    uint32_t localSizeIds[3] = {0, 0, 0}; // LocalSizeId operands, resolved once the constants are read
    for (size_t i = 5; i < words;) {
        uint32_t op = code[i] & 0xffff, n = code[i] >> 16;
        const uint32_t* ins = code + i;
        switch (op) {
        case OpEntryPoint:
            switch (ins[1]) {
            case 0:
                sm.stage = VK_SHADER_STAGE_VERTEX_BIT;
                break;
            case 4:
                sm.stage = VK_SHADER_STAGE_FRAGMENT_BIT;
                break;
            case 5:
                sm.stage = VK_SHADER_STAGE_COMPUTE_BIT;
                break;
            case 5364:
                sm.stage = VK_SHADER_STAGE_TASK_BIT_EXT;
                break;
            case 5365:
                sm.stage = VK_SHADER_STAGE_MESH_BIT_EXT;
                break;
            default:
                break;
            }
            break;
        case OpExecutionMode:
            if (ins[2] == 17) { // LocalSize
                sm.localSize[0] = ins[3];
                sm.localSize[1] = ins[4];
                sm.localSize[2] = ins[5];
            }
            break;
        case 331: // OpExecutionModeId: glslang emits LocalSizeId (38) for SPIR-V 1.6 targets
            if (ins[2] == 38)
                for (int k = 0; k < 3; ++k) localSizeIds[k] = ins[3 + k];
            break;
        case 43: // OpConstant (32-bit scalars are all the local sizes need)
            if (n == 4) constants[ins[2]] = ins[3];
            break;
        case OpMemberDecorate:
            if (ins[3] == DecOffset) memberDecoration(ids[ins[1]].offsets, ins[2], ins[4]);
            if (ins[3] == DecMatrixStride) memberDecoration(ids[ins[1]].matrixStrides, ins[2], ins[4]);
            break;
        case OpDecorate:
            if (ins[2] == DecArrayStride) ids[ins[1]].stride = ins[3];
            if (ins[2] == DecBinding) ids[ins[1]].binding = ins[3];
            if (ins[2] == DecDescriptorSet) ids[ins[1]].set = ins[3];
            if (ins[2] == DecBlock) ids[ins[1]].block = true;
            if (ins[2] == DecBufferBlock) ids[ins[1]].bufferBlock = true;
            break;
        case OpTypeImage:
            ids[ins[1]].opcode = op;
            ids[ins[1]].sampled = ins[7];
            break;
        case OpTypeSampler:
        case OpTypeSampledImage:
        case OpTypeAccelerationStructureKHR:
            ids[ins[1]].opcode = op;
            break;
        case OpTypeStruct:
            ids[ins[1]].opcode = op;
            ids[ins[1]].members.assign(ins + 2, ins + n);
            break;
        case OpTypeInt:
        case OpTypeFloat:
            ids[ins[1]].opcode = op;
            ids[ins[1]].width = ins[2];
            break;
        case OpTypeVector:
        case OpTypeMatrix:
            ids[ins[1]].opcode = op;
            ids[ins[1]].typeId = ins[2];
            ids[ins[1]].width = ins[3];
            break;
        case OpTypeArray:
            ids[ins[1]].opcode = op;
            ids[ins[1]].typeId = ins[2];
            ids[ins[1]].width = ins[3]; // the length's constant id
            break;
        case OpTypeRuntimeArray:
            ids[ins[1]].opcode = op;
            ids[ins[1]].typeId = ins[2];
            break;
        case OpTypePointer:
            ids[ins[1]].opcode = op;
            ids[ins[1]].storageClass = ins[2];
            ids[ins[1]].typeId = ins[3];
            break;
        case OpVariable:
            ids[ins[2]].opcode = op;
            ids[ins[2]].typeId = ins[1];
            ids[ins[2]].storageClass = ins[3];
            break;
        default:
            break;
        }
        i += n ? n : 1;
    }
    if (localSizeIds[0])
        for (int k = 0; k < 3; ++k) sm.localSize[k] = constants[localSizeIds[k]];
    for (const Id& v : ids) {
        if (v.opcode != OpVariable) continue;
        if (v.storageClass == ScPushConstant) // pointer -> the block struct
            sm.pushSize = typeBytes(ids, constants, ids[v.typeId].typeId);
        if (v.binding == ~0u) continue;
        if (v.set != 0) {
            std::fprintf(stderr, "%s: only descriptor set 0 is supported\n", sm.name.c_str());
            std::abort();
        }
        const Id* t = &ids[ids[v.typeId].typeId]; // pointer -> pointee
        if (t->opcode == OpTypeArray || t->opcode == OpTypeRuntimeArray) t = &ids[t->typeId];
        VkDescriptorType type;
        if (t->opcode == OpTypeStruct)
            type = (v.storageClass == ScStorageBuffer || t->bufferBlock) ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
                                                                         : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        else if (t->opcode == OpTypeImage)
            type = t->sampled == 2 ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
        else if (t->opcode == OpTypeSampledImage)
            type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        else if (t->opcode == OpTypeSampler)
            type = VK_DESCRIPTOR_TYPE_SAMPLER;
        else {
            std::fprintf(stderr, "%s: binding %u has an unsupported descriptor type\n", sm.name.c_str(),
                         v.binding);
            std::abort();
        }
        if (v.binding >= 32) {
            std::fprintf(stderr, "%s: binding %u >= 32\n", sm.name.c_str(), v.binding);
            std::abort();
        }
        sm.bindingMask |= 1u << v.binding;
        sm.bindingTypes[v.binding] = type;
    }
}

Error vkFail(const char* call, const std::string& name, VkResult r) {
    return fail(std::string(call) + " for '" + name + "' failed: " + vkResultName(r));
}

struct SpecData {
    std::vector<VkSpecializationMapEntry> entries;
    std::vector<uint32_t> values;
    VkSpecializationInfo info{};
    SpecData(std::initializer_list<SpecConstant> spec) {
        for (auto& s : spec) {
            entries.push_back({s.id, uint32_t(values.size() * 4), 4});
            values.push_back(s.value);
        }
        info.mapEntryCount = uint32_t(entries.size());
        info.pMapEntries = entries.data();
        info.dataSize = values.size() * 4;
        info.pData = values.data();
    }
};

Result<void> createLayout(const Device& device, Program& p,
                          std::initializer_list<const ShaderModule*> shaders) {
    uint32_t mask = 0, pushSize = 0;
    for (const ShaderModule* s : shaders) {
        p.stages |= s->stage;
        pushSize = std::max(pushSize, s->pushSize); // stages may declare a prefix of the block
        for (uint32_t b = 0; b < 32; ++b) {
            if (!(s->bindingMask & (1u << b))) continue;
            if ((mask & (1u << b)) && p.bindingTypes[b] != s->bindingTypes[b]) {
                std::fprintf(stderr, "%s: binding %u has different types across stages\n", s->name.c_str(),
                             b);
                std::abort();
            }
            mask |= 1u << b;
            p.bindingTypes[b] = s->bindingTypes[b];
        }
    }
    // Bindings must be dense (0..n-1) so descriptors are given in binding order without gaps.
    while (mask & (1u << p.bindingCount)) p.bindingCount++;
    if (mask != (p.bindingCount == 32 ? ~0u : (1u << p.bindingCount) - 1)) {
        std::fprintf(stderr, "%s: descriptor bindings must be dense from 0 (mask %x)\n", p.name.c_str(),
                     mask);
        std::abort();
    }
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (uint32_t b = 0; b < p.bindingCount; ++b)
        bindings.push_back({b, p.bindingTypes[b], 1, p.stages, nullptr});
    VkDescriptorSetLayoutCreateInfo sci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    sci.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    sci.bindingCount = uint32_t(bindings.size());
    sci.pBindings = bindings.data();
    if (VkResult r = ML_VK_ALLOC(vkCreateDescriptorSetLayout(device.device, &sci, nullptr, &p.setLayout));
        r != VK_SUCCESS) {
        p.setLayout = VK_NULL_HANDLE;
        return vkFail("vkCreateDescriptorSetLayout", p.name, r);
    }
    if (pushSize > device.properties.limits.maxPushConstantsSize) {
        std::fprintf(stderr, "%s: %u push bytes exceed the device's %u\n", p.name.c_str(), pushSize,
                     device.properties.limits.maxPushConstantsSize);
        std::abort();
    }
    VkPushConstantRange range{p.stages, 0, pushSize};
    VkPipelineLayoutCreateInfo lci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    lci.setLayoutCount = 1;
    lci.pSetLayouts = &p.setLayout;
    lci.pushConstantRangeCount = pushSize ? 1 : 0;
    lci.pPushConstantRanges = &range;
    if (VkResult r = ML_VK_ALLOC(vkCreatePipelineLayout(device.device, &lci, nullptr, &p.layout));
        r != VK_SUCCESS) {
        p.layout = VK_NULL_HANDLE;
        return vkFail("vkCreatePipelineLayout", p.name, r);
    }
    p.pushSize = pushSize;
    return {};
}

void orAbort(const Result<void>& r) {
    if (!r) {
        std::fprintf(stderr, "%s\n", r.error().c_str());
        std::abort();
    }
}

} // namespace

Result<void> loadShader(const Device& device, ShaderModule& sm, const uint32_t* code, size_t bytes,
                        const char* name) {
    sm = ShaderModule{};
    sm.name = name;
    reflect(sm, code, bytes / 4);
    VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    ci.codeSize = bytes;
    ci.pCode = code;
    if (VkResult r = ML_VK_ALLOC(vkCreateShaderModule(device.device, &ci, nullptr, &sm.module));
        r != VK_SUCCESS) {
        sm.module = VK_NULL_HANDLE;
        return vkFail("vkCreateShaderModule", sm.name, r);
    }
    return {};
}

ShaderModule loadShader(const Device& device, const uint32_t* code, size_t bytes, const char* name) {
    ShaderModule sm;
    orAbort(loadShader(device, sm, code, bytes, name));
    return sm;
}

void destroyShader(const Device& device, ShaderModule& shader) {
    if (shader.module) vkDestroyShaderModule(device.device, shader.module, nullptr);
    shader.module = VK_NULL_HANDLE;
}

Result<void> createComputeProgram(const Device& device, Program& p, const ShaderModule& shader,
                                  std::initializer_list<SpecConstant> spec) {
    p = Program{};
    p.name = shader.name;
    p.bindPoint = VK_PIPELINE_BIND_POINT_COMPUTE;
    if (auto r = createLayout(device, p, {&shader}); !r) {
        destroyProgram(device, p);
        return r;
    }
    for (int i = 0; i < 3; ++i) p.localSize[i] = shader.localSize[i];
    SpecData sd(spec);
    VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    ci.stage.module = shader.module;
    ci.stage.pName = "main";
    ci.stage.pSpecializationInfo = spec.size() ? &sd.info : nullptr;
    ci.layout = p.layout;
    device.countPipelineBuild(); // none may happen inside record() (built ahead by createTargets)
    if (VkResult r = ML_VK_ALLOC(
            vkCreateComputePipelines(device.device, device.pipelineCache, 1, &ci, nullptr, &p.pipeline));
        r != VK_SUCCESS) {
        p.pipeline = VK_NULL_HANDLE;
        const std::string name = p.name;
        destroyProgram(device, p);
        return vkFail("vkCreateComputePipelines", name, r);
    }
    device.setName(VK_OBJECT_TYPE_PIPELINE, uint64_t(p.pipeline), p.name.c_str());
    return {};
}

Program createComputeProgram(const Device& device, const ShaderModule& shader,
                             std::initializer_list<SpecConstant> spec) {
    Program p;
    orAbort(createComputeProgram(device, p, shader, spec));
    return p;
}

Result<void> createGraphicsProgram(const Device& device, Program& p,
                                   std::initializer_list<const ShaderModule*> shaders,
                                   const GraphicsState& state, std::initializer_list<SpecConstant> spec) {
    p = Program{};
    p.name = (*shaders.begin())->name;
    p.bindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    if (auto r = createLayout(device, p, shaders); !r) {
        destroyProgram(device, p);
        return r;
    }
    SpecData sd(spec);
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    for (const ShaderModule* s : shaders) {
        VkPipelineShaderStageCreateInfo st{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        st.stage = s->stage;
        st.module = s->module;
        st.pName = "main";
        st.pSpecializationInfo = spec.size() ? &sd.info : nullptr;
        stages.push_back(st);
    }
    VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.lineWidth = 1.0f;
    rs.cullMode = state.cull;
    rs.frontFace = state.frontFace;
    rs.depthClampEnable = state.depthClamp;
    VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = state.depthTest;
    ds.depthWriteEnable = state.depthWrite;
    ds.depthCompareOp = state.depthCompare;
    std::vector<VkPipelineColorBlendAttachmentState> blends(state.colorFormats.size());
    for (auto& b : blends) b.colorWriteMask = 0xF;
    VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cb.attachmentCount = uint32_t(blends.size());
    cb.pAttachments = blends.data();
    VkDynamicState dyn[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dy.dynamicStateCount = 2;
    dy.pDynamicStates = dyn;
    VkPipelineRenderingCreateInfo ri{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    ri.colorAttachmentCount = uint32_t(state.colorFormats.size());
    ri.pColorAttachmentFormats = state.colorFormats.data();
    ri.depthAttachmentFormat = state.depthFormat;
    VkGraphicsPipelineCreateInfo ci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &ri};
    ci.stageCount = uint32_t(stages.size());
    ci.pStages = stages.data();
    ci.pVertexInputState = &vi;
    ci.pInputAssemblyState = &ia;
    ci.pViewportState = &vp;
    ci.pRasterizationState = &rs;
    ci.pMultisampleState = &ms;
    ci.pDepthStencilState = &ds;
    ci.pColorBlendState = &cb;
    ci.pDynamicState = &dy;
    ci.layout = p.layout;
    device.countPipelineBuild(); // none may happen inside record() (built ahead by createTargets)
    if (VkResult r = ML_VK_ALLOC(
            vkCreateGraphicsPipelines(device.device, device.pipelineCache, 1, &ci, nullptr, &p.pipeline));
        r != VK_SUCCESS) {
        p.pipeline = VK_NULL_HANDLE;
        const std::string name = p.name;
        destroyProgram(device, p);
        return vkFail("vkCreateGraphicsPipelines", name, r);
    }
    device.setName(VK_OBJECT_TYPE_PIPELINE, uint64_t(p.pipeline), p.name.c_str());
    return {};
}

Program createGraphicsProgram(const Device& device, std::initializer_list<const ShaderModule*> shaders,
                              const GraphicsState& state, std::initializer_list<SpecConstant> spec) {
    Program p;
    orAbort(createGraphicsProgram(device, p, shaders, state, spec));
    return p;
}

void destroyProgram(const Device& device, Program& p) {
    if (p.pipeline) vkDestroyPipeline(device.device, p.pipeline, nullptr);
    if (p.layout) vkDestroyPipelineLayout(device.device, p.layout, nullptr);
    if (p.setLayout) vkDestroyDescriptorSetLayout(device.device, p.setLayout, nullptr);
    p = Program{};
}

namespace {

// bindProgram over descriptors[0..count) in binding order (by position or placed by name).
// names[b], where given, is binding b's constant (named bindings), for the message on a wrong kind.
void bindDescriptors(const Device& device, VkCommandBuffer cmd, const Program& p, const Descriptor* const* ds,
                     size_t count, const void* push, uint32_t pushSize, const char* const* names = nullptr) {
    if (count != p.bindingCount || pushSize != p.pushSize) {
        std::fprintf(stderr, "%s: %zu descriptors / %u push bytes given, shader wants %u / %u\n",
                     p.name.c_str(), count, pushSize, p.bindingCount, p.pushSize);
        std::abort();
    }
    vkCmdBindPipeline(cmd, p.bindPoint, p.pipeline);
    VkWriteDescriptorSet writes[32];
    VkDescriptorBufferInfo bufferInfos[32];
    VkDescriptorImageInfo imageInfos[32];
    uint32_t b = 0;
    for (; b < count; ++b) {
        const Descriptor& d = *ds[b];
        VkWriteDescriptorSet& w = writes[b];
        w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstBinding = b;
        w.descriptorCount = 1;
        w.descriptorType = p.bindingTypes[b];
        bool isBuffer = w.descriptorType == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER ||
                        w.descriptorType == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        if (isBuffer != (d.buffer != VK_NULL_HANDLE)) {
            const char* kind = isBuffer ? " buffer" : "n image";
            if (names && names[b])
                std::fprintf(stderr, "%s: %s (binding %u) expects a%s\n", p.name.c_str(), names[b], b, kind);
            else
                std::fprintf(stderr, "%s: binding %u expects a%s\n", p.name.c_str(), b, kind);
            std::abort();
        }
        if (isBuffer) {
            bufferInfos[b] = {d.buffer, d.offset, d.range};
            w.pBufferInfo = &bufferInfos[b];
        } else {
            imageInfos[b] = {d.sampler, d.view, d.layout};
            w.pImageInfo = &imageInfos[b];
        }
    }
    if (b) device.cmdPushDescriptorSet(cmd, p.bindPoint, p.layout, 0, b, writes);
    if (pushSize) vkCmdPushConstants(cmd, p.layout, p.stages, 0, pushSize, push);
}

void dispatchGroups(const Device& device, VkCommandBuffer cmd, const Program& p, const uint32_t threads[3]) {
    uint32_t groups[3];
    for (int k = 0; k < 3; ++k) {
        groups[k] = (threads[k] + p.localSize[k] - 1) / p.localSize[k];
        if (groups[k] > device.properties.limits.maxComputeWorkGroupCount[k]) {
            std::fprintf(stderr,
                         "%s: dispatch of %u x %u x %u groups exceeds the device's %u in dimension %d\n",
                         p.name.c_str(), groups[0], groups[1], groups[2],
                         device.properties.limits.maxComputeWorkGroupCount[k], k);
            std::abort();
        }
    }
    if (groups[0] && groups[1] && groups[2]) vkCmdDispatch(cmd, groups[0], groups[1], groups[2]);
}

} // namespace

void bindProgram(const Device& device, VkCommandBuffer cmd, const Program& p,
                 std::initializer_list<Descriptor> descriptors, const void* push, uint32_t pushSize) {
    const Descriptor* ds[32] = {};
    size_t n = 0;
    for (const Descriptor& d : descriptors)
        if (n < 32) ds[n++] = &d; // more than 32: refused by the count below
    bindDescriptors(device, cmd, p, ds, descriptors.size(), push, pushSize);
}

void dispatchThreads(const Device& device, VkCommandBuffer cmd, const Program& p, const uint32_t threads[3],
                     const void* push, uint32_t pushSize, std::initializer_list<Descriptor> descriptors) {
    bindProgram(device, cmd, p, descriptors, push, pushSize);
    dispatchGroups(device, cmd, p, threads);
}

namespace {
std::vector<BoundName>* gBindingLog = nullptr;
} // namespace

void setBindingLog(std::vector<BoundName>* log) {
    gBindingLog = log;
}

namespace {
// A binding left out of a named list has no name at the dispatch (the shaders are compiled without
// debug names), so the refusal names the constants given on either side of it, which find its line in
// the pass's bindings header: " (between ML_X_A at 2 and ML_X_C at 4)", or "" when none is given.
std::string neighbours(std::initializer_list<NamedDescriptor> named, uint32_t missing) {
    const NamedDescriptor* below = nullptr;
    const NamedDescriptor* above = nullptr;
    for (const NamedDescriptor& n : named) {
        if (n.binding < missing && (!below || n.binding > below->binding)) below = &n;
        if (n.binding > missing && (!above || n.binding < above->binding)) above = &n;
    }
    auto at = [](const NamedDescriptor* n) {
        return std::string(n->name) + " at " + std::to_string(n->binding);
    };
    if (below && above) return " (between " + at(below) + " and " + at(above) + ")";
    if (below) return " (after " + at(below) + ")";
    if (above) return " (before " + at(above) + ")";
    return {};
}
} // namespace

std::string orderNamedDescriptors(const Program& p, std::initializer_list<NamedDescriptor> named,
                                  const Descriptor* ordered[32], const char* names[32]) {
    const NamedDescriptor* given[32] = {};
    for (uint32_t b = 0; b < 32; ++b) {
        ordered[b] = nullptr;
        if (names) names[b] = nullptr;
    }
    for (const NamedDescriptor& n : named) {
        if (n.binding >= p.bindingCount)
            return p.name + ": " + n.name + " (binding " + std::to_string(n.binding) +
                   ") is past the shader's " + std::to_string(p.bindingCount) + " bindings";
        if (ordered[n.binding])
            return p.name + ": " + n.name + " (binding " + std::to_string(n.binding) + ") is given twice";
        ordered[n.binding] = &n.descriptor;
        given[n.binding] = &n;
        if (names) names[n.binding] = n.name;
    }
    for (uint32_t b = 0; b < p.bindingCount; ++b)
        if (!ordered[b])
            return p.name + ": binding " + std::to_string(b) + " is not given" + neighbours(named, b);
    // The kind of each resource, here where its binding's name is at hand (the bind checks it again for
    // lists by position, by number only).
    for (uint32_t b = 0; b < p.bindingCount; ++b) {
        const bool isBuffer = p.bindingTypes[b] == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER ||
                              p.bindingTypes[b] == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        if (isBuffer != (ordered[b]->buffer != VK_NULL_HANDLE))
            return p.name + ": " + given[b]->name + " (binding " + std::to_string(b) + ") expects a" +
                   (isBuffer ? " buffer" : "n image");
    }
    return {};
}

void bindProgramNamed(const Device& device, VkCommandBuffer cmd, const Program& p,
                      std::initializer_list<NamedDescriptor> named, const void* push, uint32_t pushSize) {
    const Descriptor* ordered[32];
    const char* names[32];
    const std::string error = orderNamedDescriptors(p, named, ordered, names);
    if (!error.empty()) {
        std::fprintf(stderr, "%s\n", error.c_str());
        std::abort();
    }
    if (gBindingLog)
        for (uint32_t b = 0; b < p.bindingCount; ++b)
            gBindingLog->push_back({p.name, names[b], b, *ordered[b]});
    bindDescriptors(device, cmd, p, ordered, p.bindingCount, push, pushSize, names);
}

void dispatchThreadsNamed(const Device& device, VkCommandBuffer cmd, const Program& p,
                          const uint32_t threads[3], const void* push, uint32_t pushSize,
                          std::initializer_list<NamedDescriptor> named) {
    bindProgramNamed(device, cmd, p, named, push, pushSize);
    dispatchGroups(device, cmd, p, threads);
}

void dispatchIndirectNamed(const Device& device, VkCommandBuffer cmd, const Program& p, const Buffer& args,
                           VkDeviceSize offset, const void* push, uint32_t pushSize,
                           std::initializer_list<NamedDescriptor> named) {
    bindProgramNamed(device, cmd, p, named, push, pushSize);
    vkCmdDispatchIndirect(cmd, args.buffer, offset);
}

void dispatchIndirect(const Device& device, VkCommandBuffer cmd, const Program& p, const Buffer& args,
                      VkDeviceSize offset, const void* push, uint32_t pushSize,
                      std::initializer_list<Descriptor> descriptors) {
    bindProgram(device, cmd, p, descriptors, push, pushSize);
    vkCmdDispatchIndirect(cmd, args.buffer, offset);
}

} // namespace ml
