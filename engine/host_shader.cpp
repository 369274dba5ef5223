// The binding contract of lights/manylights_lights.glsl for a host's own shaders (manylights/module.h,
// HostShaderBindings): the buffers the evaluation pass bound for the last recorded frame, captured at
// record()'s end from the same FrameContext the passes read, so the host and the module cannot bind
// different buffers.
#include "engine/module_impl.h"

namespace ml {

namespace {
constexpr bool isUniform(uint32_t offset) {
    return offset == ML_HOST_FRAME || offset == ML_HOST_VSM_CONST;
}
} // namespace

std::array<VkDescriptorSetLayoutBinding, ML_HOST_BINDING_COUNT> hostShaderLayout(uint32_t first,
                                                                                 VkShaderStageFlags stages) {
    std::array<VkDescriptorSetLayoutBinding, ML_HOST_BINDING_COUNT> b{};
    for (uint32_t i = 0; i < ML_HOST_BINDING_COUNT; ++i)
        b[i] = {first + i,
                isUniform(i) ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
                stages, nullptr};
    return b;
}

void Module::Impl::captureHostBindings(uint32_t slotIndex) {
    const FrameContext f = frameContext(VK_NULL_HANDLE, slotIndex);
    // In the include's order (manylights/host_bindings.h), as EvaluatePass::record binds them.
    const Buffer* order[ML_HOST_BINDING_COUNT] = {};
    order[ML_HOST_FRAME] = f.evaluate.shading.frame;
    order[ML_HOST_SLICES] = f.evaluate.shading.slices;
    order[ML_HOST_LIGHTS] = f.evaluate.shading.lights;
    order[ML_HOST_RANGES] = f.evaluate.shading.ranges;
    order[ML_HOST_POOL] = f.evaluate.shading.pool;
    order[ML_HOST_STATIC_WORDS] = f.evaluate.shadows.staticWords;
    order[ML_HOST_SHADOW_RECORDS] = f.evaluate.shadows.shadowRecords;
    order[ML_HOST_VSM_CONST] = f.evaluate.shadows.vsmConstants;
    order[ML_HOST_VSM_MAPS] = f.evaluate.shadows.vsmMaps;
    order[ML_HOST_VSM_COVERAGE] = f.evaluate.shadows.vsmCoverage;
    order[ML_HOST_VSM_TABLE] = f.evaluate.shadows.vsmTable;
    order[ML_HOST_VSM_POOL] = f.evaluate.shadows.vsmPool;
    HostShaderBindings h;
    h.frame = frameIndex;
    h.slot = slotIndex;
    for (uint32_t i = 0; i < ML_HOST_BINDING_COUNT; ++i) {
        // The whole buffer, as the evaluation binds it (VK_WHOLE_SIZE), given in bytes for the host.
        h.buffers[i] = {isUniform(i) ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                        order[i]->buffer, 0, order[i]->size};
    }
    // What the evaluation pass's closing barrier makes visible (lights/evaluate_pass.cpp): every
    // compute write of the frame (cluster lists, VSM pages, chained from the page draws' fragment
    // writes), to fragment and compute shader reads. The static words arrive by staged copies that the
    // frame-begin barrier makes visible to every shader stage the frame uses, fragment and compute
    // included; host-written buffers (uniforms, lights, records) need no barrier: the submission makes
    // them visible.
    h.stages = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    h.accesses = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_UNIFORM_READ_BIT;
    hostBindings = h;
}

Result<HostShaderBindings> Module::hostShaderBindings() const {
    if (!impl_->hostBindings) return fail("hostShaderBindings: no frame recorded yet (call record() first)");
    return *impl_->hostBindings;
}

} // namespace ml
