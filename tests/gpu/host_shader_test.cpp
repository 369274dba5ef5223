// The module's lights and shadows from a host's own shaders: a host pass written only against
// the installed GLSL include and Module::hostShaderBindings (tests/host_shader/, compiled against the
// staged install tree), as a compute shader and as a fragment shader, reproduces the evaluation pass's
// HDR image on the night city at 320x180 with static bakes and virtual shadow maps, recorded in the same
// command buffer after record(), under synchronization validation with 0 messages.
#include "gpu_test_util.h"

#include "host_forward.comp.spv.h"
#include "host_forward.frag.spv.h"
#include "host_fullscreen.vert.spv.h"

#include <cmath>

namespace ml::test {
namespace {

constexpr uint32_t kW = 320, kH = 180;

// What a host engine does with the contract: its own set layouts, pool, sets and pipeline; the module's
// buffers in set 1 from hostShaderLayout / hostShaderBindings, its G-buffer and outputs in set 0
// (binding 3, the storage output, for the compute pass only: the fragment pass writes an attachment).
struct HostPass {
    VkDevice dev = VK_NULL_HANDLE;
    bool fragment = false;
    VkDescriptorSetLayout layouts[2] = {};
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkShaderModule shaders[2] = {};
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet sets[2] = {};

    VkShaderModule shader(const uint32_t* code, size_t bytes) {
        VkShaderModuleCreateInfo si{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO, nullptr, 0, bytes, code};
        VkShaderModule m = VK_NULL_HANDLE;
        EXPECT_EQ(vkCreateShaderModule(dev, &si, nullptr, &m), VK_SUCCESS);
        return m;
    }

    HostPass(VkDevice d, bool frag) : dev(d), fragment(frag) {
        const VkShaderStageFlags stage = frag ? VK_SHADER_STAGE_FRAGMENT_BIT : VK_SHADER_STAGE_COMPUTE_BIT;
        std::vector<VkDescriptorSetLayoutBinding> own = {
            {0, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1, stage, nullptr},
            {1, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1, stage, nullptr},
            {2, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1, stage, nullptr},
            {4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stage, nullptr}};
        if (!frag) own.push_back({3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, stage, nullptr});
        const auto module = hostShaderLayout(0, stage);
        VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        li.bindingCount = uint32_t(own.size());
        li.pBindings = own.data();
        EXPECT_EQ(vkCreateDescriptorSetLayout(dev, &li, nullptr, &layouts[0]), VK_SUCCESS);
        li.bindingCount = uint32_t(module.size());
        li.pBindings = module.data();
        EXPECT_EQ(vkCreateDescriptorSetLayout(dev, &li, nullptr, &layouts[1]), VK_SUCCESS);
        VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pli.setLayoutCount = 2;
        pli.pSetLayouts = layouts;
        EXPECT_EQ(vkCreatePipelineLayout(dev, &pli, nullptr, &layout), VK_SUCCESS);
        if (frag)
            makeGraphics();
        else
            makeCompute();
        VkDescriptorPoolSize sizes[4] = {{VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 3},
                                         {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1},
                                         {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 11},
                                         {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 2}};
        VkDescriptorPoolCreateInfo poi{
            VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, nullptr, 0, 2, 4, sizes};
        EXPECT_EQ(vkCreateDescriptorPool(dev, &poi, nullptr, &pool), VK_SUCCESS);
        VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, nullptr, pool, 2,
                                       layouts};
        EXPECT_EQ(vkAllocateDescriptorSets(dev, &ai, sets), VK_SUCCESS);
    }
    void makeCompute() {
        shaders[0] = shader(spv_host_forward_comp, sizeof(spv_host_forward_comp));
        VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                    nullptr,
                    0,
                    VK_SHADER_STAGE_COMPUTE_BIT,
                    shaders[0],
                    "main",
                    nullptr};
        ci.layout = layout;
        EXPECT_EQ(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline), VK_SUCCESS);
    }
    // A full-screen triangle into one RGBA16F attachment (dynamic rendering), no depth, no blending.
    void makeGraphics() {
        shaders[0] = shader(spv_host_fullscreen_vert, sizeof(spv_host_fullscreen_vert));
        shaders[1] = shader(spv_host_forward_frag, sizeof(spv_host_forward_frag));
        VkPipelineShaderStageCreateInfo stages[2] = {
            {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT,
             shaders[0], "main", nullptr},
            {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT,
             shaders[1], "main", nullptr}};
        VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
        VkPipelineInputAssemblyStateCreateInfo ia{
            VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
        ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        VkViewport viewport{0, 0, float(kW), float(kH), 0, 1};
        VkRect2D scissor{{0, 0}, {kW, kH}};
        VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
        vp.viewportCount = vp.scissorCount = 1;
        vp.pViewports = &viewport;
        vp.pScissors = &scissor;
        VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
        rs.cullMode = VK_CULL_MODE_NONE;
        rs.lineWidth = 1.0f;
        VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
        ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
        VkPipelineColorBlendAttachmentState blend{};
        blend.colorWriteMask = 0xF;
        VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
        cb.attachmentCount = 1;
        cb.pAttachments = &blend;
        const VkFormat format = VK_FORMAT_R16G16B16A16_SFLOAT;
        VkPipelineRenderingCreateInfo rci{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
        rci.colorAttachmentCount = 1;
        rci.pColorAttachmentFormats = &format;
        VkGraphicsPipelineCreateInfo gci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rci};
        gci.stageCount = 2;
        gci.pStages = stages;
        gci.pVertexInputState = &vi;
        gci.pInputAssemblyState = &ia;
        gci.pViewportState = &vp;
        gci.pRasterizationState = &rs;
        gci.pMultisampleState = &ms;
        gci.pColorBlendState = &cb;
        gci.layout = layout;
        EXPECT_EQ(vkCreateGraphicsPipelines(dev, VK_NULL_HANDLE, 1, &gci, nullptr, &pipeline), VK_SUCCESS);
    }
    ~HostPass() {
        vkDestroyDescriptorPool(dev, pool, nullptr);
        vkDestroyPipeline(dev, pipeline, nullptr);
        for (VkShaderModule m : shaders) vkDestroyShaderModule(dev, m, nullptr);
        vkDestroyPipelineLayout(dev, layout, nullptr);
        for (VkDescriptorSetLayout l : layouts) vkDestroyDescriptorSetLayout(dev, l, nullptr);
    }

    // Set 1: the module's buffers of this frame (rewritten every frame: the handles may change).
    void writeModuleSet(const HostShaderBindings& b) {
        VkDescriptorBufferInfo infos[ML_HOST_BINDING_COUNT];
        VkWriteDescriptorSet writes[ML_HOST_BINDING_COUNT];
        for (uint32_t i = 0; i < ML_HOST_BINDING_COUNT; ++i) {
            infos[i] = {b.buffers[i].buffer, b.buffers[i].offset, b.buffers[i].range};
            writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                         nullptr,
                         sets[1],
                         i,
                         0,
                         1,
                         b.buffers[i].type,
                         nullptr,
                         &infos[i],
                         nullptr};
        }
        vkUpdateDescriptorSets(dev, ML_HOST_BINDING_COUNT, writes, 0, nullptr);
    }
    void writeOwnSet(VkImageView depth, VkImageView normal, VkImageView albedo, VkImageView out,
                     VkBuffer counts) {
        const VkImageLayout ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
        VkDescriptorImageInfo images[4] = {{VK_NULL_HANDLE, depth, ro},
                                           {VK_NULL_HANDLE, normal, ro},
                                           {VK_NULL_HANDLE, albedo, ro},
                                           {VK_NULL_HANDLE, out, VK_IMAGE_LAYOUT_GENERAL}};
        VkDescriptorBufferInfo buffer{counts, 0, VK_WHOLE_SIZE};
        std::vector<VkWriteDescriptorSet> w;
        for (uint32_t i = 0; i < (fragment ? 3u : 4u); ++i)
            w.push_back({VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, sets[0], i, 0, 1,
                         i < 3 ? VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                         &images[i], nullptr, nullptr});
        w.push_back({VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, sets[0], 4, 0, 1,
                     VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, nullptr, &buffer, nullptr});
        vkUpdateDescriptorSets(dev, uint32_t(w.size()), w.data(), 0, nullptr);
    }
    // The host's pass into `out` (RGBA16F), left in GENERAL.
    void record(VkCommandBuffer cmd, const Image& out) const {
        constexpr auto C = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
        constexpr auto A = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
        if (!fragment) {
            imageBarrier(cmd, out.image, out.aspect, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                         VK_PIPELINE_STAGE_2_NONE, 0, C, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 2, sets, 0, nullptr);
            vkCmdDispatch(cmd, (kW + 7) / 8, (kH + 7) / 8, 1);
            return;
        }
        imageBarrier(cmd, out.image, out.aspect, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, 0, A,
                     VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
        VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        color.imageView = out.view;
        color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
        color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
        ri.renderArea = {{0, 0}, {kW, kH}};
        ri.layerCount = 1;
        ri.colorAttachmentCount = 1;
        ri.pColorAttachments = &color;
        vkCmdBeginRendering(cmd, &ri);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 2, sets, 0, nullptr);
        vkCmdDraw(cmd, 3, 1, 0, 0);
        vkCmdEndRendering(cmd);
        imageBarrier(cmd, out.image, out.aspect, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_IMAGE_LAYOUT_GENERAL, A, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
    }
};

TEST(HostShaderBindings, RefusedBeforeTheFirstFrame) {
    auto m = makeModule();
    auto b = m->hostShaderBindings();
    ASSERT_FALSE(b.ok());
    EXPECT_NE(b.error().find("no frame recorded"), std::string::npos) << b.error();
    const auto layout = hostShaderLayout(4, VK_SHADER_STAGE_FRAGMENT_BIT);
    for (uint32_t i = 0; i < ML_HOST_BINDING_COUNT; ++i) {
        EXPECT_EQ(layout[i].binding, 4 + i);
        const bool uniform = i == ML_HOST_FRAME || i == ML_HOST_VSM_CONST;
        EXPECT_EQ(layout[i].descriptorType,
                  uniform ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
        EXPECT_EQ(layout[i].stageFlags, VkShaderStageFlags(VK_SHADER_STAGE_FRAGMENT_BIT));
    }
    EXPECT_EQ(validationErrors(), 0u);
}

// The night city at 320x180, 48 lights with DAG-MH bakes, virtual shadow maps, one frame drawn; then the
// host pass (compute or fragment) recorded after the second frame's record() in the same command buffer,
// its image compared with the evaluation's HDR image of that frame. `plain`: no culling, no virtual
// maps, no bakes (the contract's buffers then stand in for absent ones and must still bind).
void hostPassMatchesEvaluation(bool fragment, bool plain = false) {
    resetValidationCounters();
    ModuleOptions o;
    o.device.validationSync = true; // the host pass after record() is checked for hazards too
    o.vsm.enabled = !plain;
    o.culling = plain ? CullingMode::None : CullingMode::Clustered;
    auto created = Module::create(o);
    ASSERT_TRUE(created.ok()) << created.error();
    Module& m = *created.value();
    auto scene = loadScene("night-city", 48, 3);
    ASSERT_TRUE(scene.ok()) << scene.error();
    auto binding = bindScene(m, scene.value());
    ASSERT_TRUE(binding.ok()) << binding.error();
    if (!plain) {
        auto baked = m.bakeStaticShadows(StaticMethod::DAGMH, 64);
        ASSERT_TRUE(baked.ok()) << baked.error();
        ASSERT_GT(baked.value(), 8u);
    }
    ASSERT_TRUE(m.createTargets(kW, kH).ok());
    renderFrame(m); // a first frame: the second one reads cached virtual pages too

    Device& d = deviceOf(m);
    auto& impl = internals(m);
    const VkImageUsageFlags usage =
        VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
        (fragment ? VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT : VK_IMAGE_USAGE_STORAGE_BIT);
    Image radiance = createImage(d, kW, kH, VK_FORMAT_R16G16B16A16_SFLOAT, usage, "host_radiance");
    Buffer counts = createBuffer(d, VkDeviceSize(kW) * kH * 16, kStorageBufferUsage, "host_counts");
    {
        HostPass pass(d.device, fragment);
        // The host's inputs: here the module-owned G-buffer of the same frame (what the evaluation read).
        pass.writeOwnSet(impl.targets.depth.view, impl.targets.normal.view, impl.targets.albedo.view,
                         radiance.view, counts.buffer);
        VkCommandBuffer cmd = d.beginOneTime();
        ASSERT_TRUE(m.record(cmd).ok());
        auto bindings = m.hostShaderBindings();
        ASSERT_TRUE(bindings.ok()) << bindings.error();
        EXPECT_EQ(bindings->frame, 1u);
        EXPECT_EQ(bindings->slot, 1u);
        EXPECT_TRUE(bindings->stages & (fragment ? VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT
                                                 : VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT));
        for (const HostShaderBuffer& b : bindings->buffers) {
            EXPECT_NE(b.buffer, VK_NULL_HANDLE);
            EXPECT_GT(b.range, 0u);
        }
        pass.writeModuleSet(bindings.value());
        pass.record(cmd, radiance);
        d.endOneTime(cmd);
        vkQueueWaitIdle(d.queue);
        m.collect();
    }

    auto hostImage = readImage(m, radiance, 8, VK_IMAGE_LAYOUT_GENERAL);
    auto moduleImage = readImage(m, impl.hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
    const auto* n = counts.as<glm::uvec4>();
    size_t same = 0, lit = 0, shadowed = 0, virtualMapped = 0;
    float worst = 0.0f;
    for (size_t i = 0; i < size_t(kW) * kH; ++i) {
        const glm::vec4 h = half4(hostImage, i), e = half4(moduleImage, i);
        for (int k = 0; k < 3; ++k) {
            // Half-float storage: one ulp is 2^-10 of the value; the two passes run the same code, so
            // anything beyond one ulp is a real difference (another list, record or page).
            const float err = std::abs(h[k] - e[k]) / (std::abs(e[k]) + 1e-4f);
            worst = std::max(worst, err);
            ASSERT_LE(err, 1.0f / 1024.0f) << "pixel " << i % kW << "," << i / kW << " channel " << k
                                           << ": host " << h[k] << ", evaluation " << e[k];
        }
        same += std::memcmp(hostImage.data() + i * 8, moduleImage.data() + i * 8, 6) == 0;
        lit += n[i].y > 0;
        shadowed += n[i].z > 0;
        virtualMapped += n[i].w > 0;
    }
    std::printf("host %s pass%s vs evaluation: %zu of %u pixels identical, worst relative difference %.3g; "
                "%zu lit, %zu with a shadowed light, %zu with a virtual-mapped light\n",
                fragment ? "fragment" : "compute", plain ? " (no culling, maps or bakes)" : "", same, kW * kH,
                double(worst), lit, shadowed, virtualMapped);
    // The comparison means something only if lights, static shadows and virtual maps were looked up.
    EXPECT_GT(lit, size_t(kW) * kH / 10);
    if (plain) { // nothing casts: no bake, no virtual map
        EXPECT_EQ(shadowed, 0u);
        EXPECT_EQ(virtualMapped, 0u);
    } else {
        EXPECT_GT(shadowed, 500u);
        EXPECT_GT(virtualMapped, 500u);
    }
    destroyImage(d, radiance);
    destroyBuffer(d, counts);
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(HostShader, ForwardPassMatchesEvaluation) {
    hostPassMatchesEvaluation(false);
}

TEST(HostShader, FragmentPassMatchesEvaluation) {
    hostPassMatchesEvaluation(true);
}

TEST(HostShader, ForwardPassMatchesWithoutCullingMapsOrBakes) {
    hostPassMatchesEvaluation(false, true);
}

} // namespace
} // namespace ml::test
