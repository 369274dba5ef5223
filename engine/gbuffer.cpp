#include "engine/gbuffer.h"

#include "engine/gbuffer_bindings.h"
#include "gpu/bindings.h"

#include "gbuffer.frag.spv.h"
#include "gbuffer.vert.spv.h"

namespace ml {

Result<void> GBufferPass::create(const Device& device) {
    ML_TRY(ML_LOAD_SHADER(device, vs_, spv_gbuffer_vert));
    ML_TRY(ML_LOAD_SHADER(device, fs_, spv_gbuffer_frag));
    GraphicsState state;
    state.colorFormats = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R8G8_UNORM};
    state.depthFormat = VK_FORMAT_D32_SFLOAT;
    state.cull = VK_CULL_MODE_NONE; // open geometry (cards, awnings, fences) is two-sided
    return createGraphicsProgram(device, program_, {&vs_, &fs_}, state);
}

void GBufferPass::destroy(const Device& device) {
    destroyProgram(device, program_);
    destroyShader(device, vs_);
    destroyShader(device, fs_);
}

Result<void> GBufferPass::createTargets(const Device& device, uint32_t w, uint32_t h,
                                        GBufferTargets& t) const {
    VkImageUsageFlags common = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    ML_TRY(createImage(device, t.depth, w, h, VK_FORMAT_D32_SFLOAT,
                       common | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, "gbuffer_depth"));
    ML_TRY(createImage(device, t.normal, w, h, VK_FORMAT_R16G16B16A16_SFLOAT,
                       common | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, "gbuffer_normal"));
    ML_TRY(createImage(device, t.albedo, w, h, VK_FORMAT_R8G8B8A8_UNORM,
                       common | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, "gbuffer_albedo"));
    // 2 bytes a pixel, written whether or not the evaluation reads it (one pipeline for both shadings).
    ML_TRY(createImage(device, t.material, w, h, VK_FORMAT_R8G8_UNORM,
                       common | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, "gbuffer_material"));
    return {};
}

void GBufferPass::record(const Device& device, VkCommandBuffer cmd, const GBufferInputs& in) const {
    const GBufferTargets& t = *in.targets;
    const auto color = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    const auto depthStages =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    const auto compute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    for (const Image* img : {&t.normal, &t.albedo, &t.material})
        imageBarrier(cmd, img->image, img->aspect, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, compute, 0, color,
                     VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    imageBarrier(cmd, t.depth.image, t.depth.aspect, VK_IMAGE_LAYOUT_UNDEFINED,
                 VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, compute, 0, depthStages,
                 VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                     VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT);

    VkRenderingAttachmentInfo colors[3] = {{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO},
                                           {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO},
                                           {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO}};
    const Image* colorImages[3] = {&t.normal, &t.albedo, &t.material};
    for (int i = 0; i < 3; ++i) {
        colors[i].imageView = colorImages[i]->view;
        colors[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        colors[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        colors[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    }
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = t.depth.view;
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depth.clearValue.depthStencil = {0.0f, 0}; // reversed Z: 0 is the far plane (the sky)
    VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
    ri.renderArea = {{0, 0}, {t.depth.width, t.depth.height}};
    ri.layerCount = 1;
    ri.colorAttachmentCount = 3;
    ri.pColorAttachments = colors;
    ri.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &ri);
    VkViewport vp{0, 0, float(t.depth.width), float(t.depth.height), 0, 1};
    VkRect2D sc{{0, 0}, {t.depth.width, t.depth.height}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    if (in.drawCount) {
        bindProgram(device, cmd, program_, NoPush{},
                    {ML_BIND(ML_GBUFFER_FRAME, *in.frame), ML_BIND(ML_GBUFFER_VERTICES, *in.vertices),
                     ML_BIND(ML_GBUFFER_INSTANCES, *in.instances)});
        vkCmdBindIndexBuffer(cmd, in.indices->buffer, 0, VK_INDEX_TYPE_UINT32);
        vkCmdDrawIndexedIndirect(cmd, in.draws->buffer, 0, in.drawCount,
                                 sizeof(VkDrawIndexedIndirectCommand));
    }
    vkCmdEndRendering(cmd);

    for (const Image* img : {&t.normal, &t.albedo, &t.material})
        imageBarrier(cmd, img->image, img->aspect, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, color, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                     compute, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    imageBarrier(cmd, t.depth.image, t.depth.aspect, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, depthStages,
                 VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, compute,
                 VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
}

} // namespace ml
