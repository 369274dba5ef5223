#include "lights/evaluate_pass.h"

#include "gpu/bindings.h"
#include "lights/evaluate_bindings.h"

#include "evaluate.comp.spv.h"
#include "evaluate_wave.comp.spv.h"
#include "statistics.comp.spv.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ml {

namespace {
constexpr auto kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr auto kWrite = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
Descriptor sampled(VkImageView view) {
    return Descriptor(view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}
} // namespace

Result<void> EvaluatePass::create(const Device& device) {
    // The wave loop's subgroupMin: basic + arithmetic operations in compute shaders (a SPIR-V module
    // declaring GroupNonUniformArithmetic may not be created on a device without them).
    VkPhysicalDeviceSubgroupProperties sub{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &sub};
    vkGetPhysicalDeviceProperties2(device.physicalDevice, &props);
    const VkSubgroupFeatureFlags need = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
    waveBuild_ =
        (sub.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) && (sub.supportedOperations & need) == need;
    if (!waveBuild_)
        std::fprintf(stderr,
                     "evaluate: %s has no subgroup arithmetic in compute shaders: per-lane light loop\n",
                     device.name.c_str());
    const char* env = std::getenv("ML_UNIFORM_LOOP");
    // Off by default: at 4096 lights on lavapipe it was no faster (docs/culling.md).
    uniform_ = waveBuild_ && env && std::strcmp(env, "1") == 0;
    return waveBuild_ ? ML_LOAD_SHADER(device, shader_, spv_evaluate_wave_comp)
                      : ML_LOAD_SHADER(device, shader_, spv_evaluate_comp);
}

bool EvaluatePass::setUniformLoop(bool on) {
    uniform_ = on && waveBuild_;
    return uniform_ == on;
}

Result<void> EvaluatePass::prepare(const Device& device, EvaluateOutputs outputs, bool pbr) {
    Program& p = programs_[programIndex(outputs, pbr)];
    // kUniformLoop (id 2) is absent from the plain build: an unused map entry is ignored (Vulkan spec).
    if (!p.pipeline)
        ML_TRY(createComputeProgram(device, p, shader_,
                                    {{/*kSpecOutput*/ 0, uint32_t(outputs)},
                                     {/*kSpecPbr*/ 1, uint32_t(pbr)},
                                     {/*kUniformLoop*/ 2, uint32_t(uniform_)}}));
    return {};
}

void EvaluatePass::destroy(const Device& device) {
    for (Program& p : programs_)
        if (p.pipeline) destroyProgram(device, p);
    destroyShader(device, shader_);
}

void EvaluatePass::record(const Device& d, VkCommandBuffer c, const EvaluateInputs& e) const {
    const ShadingInputs& in = e.shading;
    const ShadowInputs& s = e.shadows;
    const EvaluateTargets& t = e.targets;
    // Without a material target the albedo fills its binding (a valid sampled image, never read).
    const bool pbr = in.material != VK_NULL_HANDLE;
    dispatch(d, c, programs_[programIndex(t.outputs, pbr)], in.width, in.height, NoPush{},
             {// lights/manylights_lights.glsl's 12 (manylights/host_bindings.h), then the images
              ML_BIND(ML_HOST_FRAME, *in.frame), ML_BIND(ML_HOST_SLICES, *in.slices),
              ML_BIND(ML_HOST_LIGHTS, *in.lights), ML_BIND(ML_HOST_RANGES, *in.ranges),
              ML_BIND(ML_HOST_POOL, *in.pool), ML_BIND(ML_HOST_STATIC_WORDS, *s.staticWords),
              ML_BIND(ML_HOST_SHADOW_RECORDS, *s.shadowRecords), ML_BIND(ML_HOST_VSM_CONST, *s.vsmConstants),
              ML_BIND(ML_HOST_VSM_MAPS, *s.vsmMaps), ML_BIND(ML_HOST_VSM_COVERAGE, *s.vsmCoverage),
              ML_BIND(ML_HOST_VSM_TABLE, *s.vsmTable), ML_BIND(ML_HOST_VSM_POOL, *s.vsmPool),
              ML_BIND(ML_EVAL_DEPTH, sampled(in.depth)), ML_BIND(ML_EVAL_NORMAL, sampled(in.normal)),
              ML_BIND(ML_EVAL_ALBEDO, sampled(in.albedo)), ML_BIND(ML_EVAL_HDR, Descriptor(t.hdr)),
              ML_BIND(ML_EVAL_OUTPUT, Descriptor(t.output)),
              ML_BIND(ML_EVAL_MATERIAL, sampled(pbr ? in.material : in.albedo))});
    // HDR and output -> the host's reads after record() (copy, blit, sampling); the debug views that
    // overwrite the output order their writes themselves.
    memoryBarrier(c, kCompute, kWrite, kOutputReaderStages, kOutputReads);
}

Result<void> StatisticsPass::create(const Device& device) {
    ML_TRY(ML_LOAD_SHADER(device, shader_, spv_statistics_comp));
    return createComputeProgram(device, program_, shader_);
}

void StatisticsPass::destroy(const Device& device) {
    destroyProgram(device, program_);
    destroyShader(device, shader_);
}

void StatisticsPass::record(const Device& d, VkCommandBuffer c, const StatisticsInputs& in) const {
    dispatch(d, c, program_, in.width, in.height, NoPush{},
             {ML_BIND(ML_STATS_FRAME, *in.frame), ML_BIND(ML_STATS_SLICES, *in.slices),
              ML_BIND(ML_STATS_LIGHTS, *in.lights), ML_BIND(ML_STATS_RANGES, *in.ranges),
              ML_BIND(ML_STATS_POOL, *in.pool), ML_BIND(ML_STATS_DEPTH, sampled(in.depth)),
              ML_BIND(ML_STATS_COUNTERS, *in.counters)});
    // Counters (every pass's atomics, and these sums) -> host (engine/frame_passes.cpp's frame end does
    // it when statistics are off).
    memoryBarrier(c, kCompute, kWrite, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

} // namespace ml
