// A host engine's use of manylights, written from README.md and <manylights/manylights.h> only: the module
// makes its device (validation on), the host makes its own G-buffer images and graphics pipeline,
// draws a ground quad and a box, hands the images over with setTargets, and records 3 frames: its
// G-buffer commands, then module.record(cmd), in one command buffer. It reads back its output image
// and checks that the ground under the spot light is lit, the ground outside the cone is dark, and
// that the validation layer said nothing. Exit 0 when all holds, 1 with a one-line reason otherwise.
#include <manylights/manylights.h>

#include "host_gbuffer_frag.h"
#include "host_gbuffer_vert.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

// An engine's own VK_CHECK: the module's header must leave the name free (it uses ML_VK_CHECK).
#ifdef VK_CHECK
#error "engine/manylights.h defines VK_CHECK, which clashes with host engines' own"
#endif
#define VK_CHECK(call)                                                                                       \
    do {                                                                                                     \
        if (VkResult r_ = (call); r_ != VK_SUCCESS) {                                                        \
            std::fprintf(stderr, "host_example: %s failed (%d)\n", #call, int(r_));                          \
            std::exit(1);                                                                                    \
        }                                                                                                    \
    } while (0)

namespace {
constexpr uint32_t kWidth = 320, kHeight = 180;
constexpr VkFormat kNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT, kAlbedoFormat = VK_FORMAT_R8G8B8A8_UNORM;

struct OwnedImage {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageUsageFlags usage = 0;
    // What setTargets checks: the image, its view and what it was created with.
    ml::HostImage target() const { return {image, view, format, {kWidth, kHeight}, usage}; }
};

uint32_t memoryType(VkPhysicalDevice pd, uint32_t bits, VkMemoryPropertyFlags flags) {
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(pd, &mp);
    for (uint32_t i = 0; i < mp.memoryTypeCount; ++i)
        if ((bits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & flags) == flags) return i;
    std::fprintf(stderr, "host_example: no memory type\n");
    std::exit(1);
}

OwnedImage makeImage(VkDevice dev, VkPhysicalDevice pd, VkFormat format, VkImageUsageFlags usage,
                     VkImageAspectFlags aspect) {
    OwnedImage h;
    h.format = format;
    h.usage = usage;
    VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ici.imageType = VK_IMAGE_TYPE_2D;
    ici.format = format;
    ici.extent = {kWidth, kHeight, 1};
    ici.mipLevels = ici.arrayLayers = 1;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.usage = usage;
    VK_CHECK(vkCreateImage(dev, &ici, nullptr, &h.image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(dev, h.image, &req);
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, nullptr, req.size,
                            memoryType(pd, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)};
    VK_CHECK(vkAllocateMemory(dev, &ai, nullptr, &h.memory));
    VK_CHECK(vkBindImageMemory(dev, h.image, h.memory, 0));
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = h.image;
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vci.format = format;
    vci.subresourceRange = {aspect, 0, 1, 0, 1};
    VK_CHECK(vkCreateImageView(dev, &vci, nullptr, &h.view));
    return h;
}

void barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
             VkImageLayout to, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
             VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = srcStage;
    b.srcAccessMask = srcAccess;
    b.dstStageMask = dstStage;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, 0, 1};
    VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    di.imageMemoryBarrierCount = 1;
    di.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &di);
}

// An axis-aligned box as 6 quads (CCW from outside), or just its top face for the ground.
void addBox(std::vector<ml::MeshVertex>& v, std::vector<uint32_t>& idx, glm::vec3 lo, glm::vec3 hi,
            bool topOnly) {
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            if (topOnly && !(axis == 1 && side == 1)) continue;
            glm::vec3 n(0.0f);
            n[axis] = side ? 1.0f : -1.0f;
            int u = (axis + 1) % 3, w = (axis + 2) % 3;
            uint32_t base = uint32_t(v.size());
            for (int k = 0; k < 4; ++k) {
                glm::vec3 p = side ? hi : lo;
                p[u] = (k == 1 || k == 2) ? hi[u] : lo[u];
                p[w] = (k >= 2) ? hi[w] : lo[w];
                v.push_back({{p.x, p.y, p.z}, {n.x, n.y, n.z}});
            }
            bool flip = side == 0; // keep the winding counter-clockwise seen from outside
            uint32_t q[6] = {0, 1, 2, 0, 2, 3};
            for (uint32_t i : q) idx.push_back(base + (flip ? (i == 1 ? 3 : i == 3 ? 1 : i) : i));
        }
}

// The G-buffer pipeline: dynamic rendering into normal + albedo colour attachments and D32 depth
// (reversed Z: GREATER, cleared to 0), vertices as ml::MeshVertex, back faces culled (CCW front faces).
VkPipeline makePipeline(VkDevice dev, VkShaderModule vs, VkShaderModule fs, VkPipelineLayout layout) {
    using S = VkPipelineShaderStageCreateInfo;
    S stages[2] = {{.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                    .stage = VK_SHADER_STAGE_VERTEX_BIT,
                    .module = vs,
                    .pName = "main"},
                   {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                    .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
                    .module = fs,
                    .pName = "main"}};
    VkVertexInputBindingDescription binding{0, sizeof(ml::MeshVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription attrs[2] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                  {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 12}};
    VkPipelineVertexInputStateCreateInfo vi{.sType =
                                                VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
                                            .vertexBindingDescriptionCount = 1,
                                            .pVertexBindingDescriptions = &binding,
                                            .vertexAttributeDescriptionCount = 2,
                                            .pVertexAttributeDescriptions = attrs};
    VkPipelineInputAssemblyStateCreateInfo ia{.sType =
                                                  VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
                                              .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST};
    VkViewport viewport{0, 0, float(kWidth), float(kHeight), 0, 1};
    VkRect2D scissor{{0, 0}, {kWidth, kHeight}};
    VkPipelineViewportStateCreateInfo vp{.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
                                         .viewportCount = 1,
                                         .pViewports = &viewport,
                                         .scissorCount = 1,
                                         .pScissors = &scissor};
    VkPipelineRasterizationStateCreateInfo rs{.sType =
                                                  VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
                                              .cullMode = VK_CULL_MODE_BACK_BIT,
                                              .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE,
                                              .lineWidth = 1.0f};
    VkPipelineMultisampleStateCreateInfo ms{.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
                                            .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT};
    VkPipelineDepthStencilStateCreateInfo ds{.sType =
                                                 VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
                                             .depthTestEnable = VK_TRUE,
                                             .depthWriteEnable = VK_TRUE,
                                             .depthCompareOp = VK_COMPARE_OP_GREATER};
    VkPipelineColorBlendAttachmentState blend[2]{{.colorWriteMask = 0xF}, {.colorWriteMask = 0xF}};
    VkPipelineColorBlendStateCreateInfo cb{.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
                                           .attachmentCount = 2,
                                           .pAttachments = blend};
    VkFormat colorFormats[2] = {kNormalFormat, kAlbedoFormat};
    VkPipelineRenderingCreateInfo rci{.sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO,
                                      .colorAttachmentCount = 2,
                                      .pColorAttachmentFormats = colorFormats,
                                      .depthAttachmentFormat = VK_FORMAT_D32_SFLOAT};
    VkGraphicsPipelineCreateInfo gci{.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
                                     .pNext = &rci,
                                     .stageCount = 2,
                                     .pStages = stages,
                                     .pVertexInputState = &vi,
                                     .pInputAssemblyState = &ia,
                                     .pViewportState = &vp,
                                     .pRasterizationState = &rs,
                                     .pMultisampleState = &ms,
                                     .pDepthStencilState = &ds,
                                     .pColorBlendState = &cb,
                                     .layout = layout};
    VkPipeline pipeline;
    VK_CHECK(vkCreateGraphicsPipelines(dev, VK_NULL_HANDLE, 1, &gci, nullptr, &pipeline));
    return pipeline;
}
} // namespace

int main() {
    ml::ModuleOptions options;
    options.device.validation = true;
    options.statistics = false;
    // The default timing records every pass into the host's command buffer, after the host's commands.
    auto created = ml::Module::create(options);
    if (!created) {
        std::fprintf(stderr, "host_example: %s\n", created.error().c_str());
        return 1;
    }
    ml::Module& module = *created.value();
    const ml::DeviceInfo device = module.deviceInfo();
    VkDevice dev = device.device;
    VkPhysicalDevice pd = device.physicalDevice;
    VkQueue queue = device.queue;

    // Scene: a 20 m ground quad, a 1 m box, one spot light 5 m above the ground pointing down.
    std::vector<ml::MeshVertex> verts;
    std::vector<uint32_t> indices;
    addBox(verts, indices, {-10, -1, -10}, {10, 0, 10}, true);
    uint32_t groundIndices = uint32_t(indices.size());
    addBox(verts, indices, {-0.5f, 0, -0.5f}, {0.5f, 1, 0.5f}, false);
    ml::MeshDesc mesh{verts, indices, false, "ground+box"};
    if (auto m = module.addMesh(mesh);
        !m || !module.addInstance(m.value(), glm::mat4(1.0f), glm::vec3(0.5f), false)) {
        std::fprintf(stderr, "host_example: addMesh/addInstance failed\n");
        return 1;
    }
    ml::LightDesc spot;
    spot.position = {0, 5, 0};
    spot.range = 12;
    spot.intensity = 30;
    if (auto id = module.addLight(spot); !id)
        return std::fprintf(stderr, "host_example: %s\n", id.error().c_str()), 1;
    // The host's own camera matrices: a right-handed view and a reversed-Z projection into Vulkan clip
    // space (near -> 1, far -> 0: near and far swapped in perspectiveRH_ZO; y flipped). Its G-buffer is
    // drawn with the same matrices, cleared to depth 0 and tested with GREATER.
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 8, 12), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    glm::mat4 proj = glm::perspectiveRH_ZO(1.0f, float(kWidth) / kHeight, 100.0f, 0.1f);
    proj[1][1] *= -1.0f;
    if (auto r = module.setCameraMatrices(view, proj); !r)
        return std::fprintf(stderr, "host_example: %s\n", r.error().c_str()), 1;
    glm::mat4 viewProj = proj * view;

    // Host-owned targets.
    OwnedImage depth = makeImage(dev, pd, VK_FORMAT_D32_SFLOAT,
                                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                 VK_IMAGE_ASPECT_DEPTH_BIT);
    const VkImageUsageFlags colorUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    OwnedImage normal = makeImage(dev, pd, kNormalFormat, colorUsage, VK_IMAGE_ASPECT_COLOR_BIT);
    OwnedImage albedo = makeImage(dev, pd, kAlbedoFormat, colorUsage, VK_IMAGE_ASPECT_COLOR_BIT);
    OwnedImage output =
        makeImage(dev, pd, VK_FORMAT_R8G8B8A8_UNORM,
                  VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    if (auto r = module.setTargets(
            {kWidth, kHeight, depth.target(), normal.target(), albedo.target(), output.target()});
        !r)
        return std::fprintf(stderr, "host_example: %s\n", r.error().c_str()), 1;

    // Host buffers: vertices + indices, and the readback (host-visible, coherent).
    auto makeBuffer = [&](VkDeviceSize size, VkBufferUsageFlags usage, VkBuffer& buf, VkDeviceMemory& mem) {
        VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO, nullptr, 0, size, usage};
        VK_CHECK(vkCreateBuffer(dev, &bci, nullptr, &buf));
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(dev, buf, &req);
        VkMemoryAllocateInfo ai{
            VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, nullptr, req.size,
            memoryType(pd, req.memoryTypeBits,
                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT)};
        VK_CHECK(vkAllocateMemory(dev, &ai, nullptr, &mem));
        VK_CHECK(vkBindBufferMemory(dev, buf, mem, 0));
        void* p = nullptr;
        VK_CHECK(vkMapMemory(dev, mem, 0, VK_WHOLE_SIZE, 0, &p));
        return static_cast<uint8_t*>(p);
    };
    const size_t vbytes = verts.size() * sizeof(ml::MeshVertex), ibytes = indices.size() * 4;
    VkBuffer geo, readback;
    VkDeviceMemory geoMem, readbackMem;
    uint8_t* g = makeBuffer(
        vbytes + ibytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT, geo, geoMem);
    std::memcpy(g, verts.data(), vbytes);
    std::memcpy(g + vbytes, indices.data(), ibytes);
    const uint8_t* pixels =
        makeBuffer(kWidth * kHeight * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, readback, readbackMem);

    // The host's G-buffer pipeline: dynamic rendering, two colour attachments and depth (LESS).
    auto shader = [&](const uint32_t* code, size_t bytes) {
        VkShaderModuleCreateInfo sci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO, nullptr, 0, bytes, code};
        VkShaderModule m;
        VK_CHECK(vkCreateShaderModule(dev, &sci, nullptr, &m));
        return m;
    };
    VkShaderModule vs = shader(host_gbuffer_vert, sizeof(host_gbuffer_vert));
    VkShaderModule fs = shader(host_gbuffer_frag, sizeof(host_gbuffer_frag));
    VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, 80};
    VkPipelineLayoutCreateInfo lci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    lci.pushConstantRangeCount = 1;
    lci.pPushConstantRanges = &push;
    VkPipelineLayout layout;
    VK_CHECK(vkCreatePipelineLayout(dev, &lci, nullptr, &layout));
    VkPipeline pipeline = makePipeline(dev, vs, fs, layout);

    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO, nullptr,
                                VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT, device.queueFamily};
    VkCommandPool pool;
    VK_CHECK(vkCreateCommandPool(dev, &pci, nullptr, &pool));
    VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, nullptr, pool,
                                    VK_COMMAND_BUFFER_LEVEL_PRIMARY, 1};
    VkCommandBuffer cmd;
    VK_CHECK(vkAllocateCommandBuffers(dev, &cai, &cmd));
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    VK_CHECK(vkCreateFence(dev, &fci, nullptr, &fence));

    // The image, after every frame (frame 0 too: the module must read this frame's G-buffer): a world
    // point's pixel through the host's own view-projection. The worst frame counts.
    auto luminance = [&](glm::vec3 world) {
        glm::vec4 clip = viewProj * glm::vec4(world, 1.0f);
        int x = int((clip.x / clip.w * 0.5f + 0.5f) * kWidth),
            y = int((clip.y / clip.w * 0.5f + 0.5f) * kHeight);
        const uint8_t* p = pixels + (size_t(y) * kWidth + size_t(x)) * 4;
        return (p[0] + p[1] + p[2]) / 3.0f;
    };
    float lit = 255.0f, boxTop = 255.0f, dark = 0.0f;
    const auto kColor = VK_IMAGE_ASPECT_COLOR_BIT;
    const auto kAttach = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    const auto kDepthStages =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    for (int frame = 0; frame < 3; ++frame) {
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
        // The G-buffer: previous frame's contents are discarded (UNDEFINED), after the module's reads.
        const auto kRead = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
        barrier(cmd, depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, kRead, 0, kDepthStages,
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
        for (VkImage img : {normal.image, albedo.image})
            barrier(cmd, img, kColor, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    kRead, 0, kAttach, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
        VkRenderingAttachmentInfo colors[2];
        for (int i = 0; i < 2; ++i) {
            colors[i] = {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
            colors[i].imageView = i ? albedo.view : normal.view;
            colors[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
            colors[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
            colors[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        }
        VkRenderingAttachmentInfo depthAttachment{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depthAttachment.imageView = depth.view;
        depthAttachment.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        depthAttachment.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depthAttachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        depthAttachment.clearValue.depthStencil = {0.0f, 0}; // reversed Z: 0 = far
        VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
        ri.renderArea = {{0, 0}, {kWidth, kHeight}};
        ri.layerCount = 1;
        ri.colorAttachmentCount = 2;
        ri.pColorAttachments = colors;
        ri.pDepthAttachment = &depthAttachment;
        vkCmdBeginRendering(cmd, &ri);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        VkDeviceSize zero = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &geo, &zero);
        vkCmdBindIndexBuffer(cmd, geo, vbytes, VK_INDEX_TYPE_UINT32);
        struct {
            glm::mat4 viewProj;
            glm::vec4 albedo;
        } draw{viewProj, {0.5f, 0.5f, 0.5f, 1}};
        vkCmdPushConstants(cmd, layout, push.stageFlags, 0, sizeof(draw), &draw);
        vkCmdDrawIndexed(cmd, groundIndices, 1, 0, 0, 0);
        draw.albedo = {0.8f, 0.2f, 0.1f, 1};
        vkCmdPushConstants(cmd, layout, push.stageFlags, 0, sizeof(draw), &draw);
        vkCmdDrawIndexed(cmd, uint32_t(indices.size()) - groundIndices, 1, groundIndices, 0, 0);
        vkCmdEndRendering(cmd);
        // Hand-over to the module: G-buffer in SHADER_READ_ONLY_OPTIMAL, output in GENERAL.
        barrier(cmd, depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, kDepthStages,
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, kRead, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
        for (VkImage img : {normal.image, albedo.image})
            barrier(cmd, img, kColor, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, kAttach, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                    kRead, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
        barrier(cmd, output.image, kColor, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                VK_PIPELINE_STAGE_2_COPY_BIT, 0, kRead, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
        if (auto r = module.record(cmd); !r)
            return std::fprintf(stderr, "host_example: %s\n", r.error().c_str()), 1;
        // The host reads the output back (a real engine would blit or sample it).
        barrier(cmd, output.image, kColor, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                kRead, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {kColor, 0, 0, 1};
        copy.imageExtent = {kWidth, kHeight, 1};
        vkCmdCopyImageToBuffer(cmd, output.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback, 1, &copy);
        VK_CHECK(vkEndCommandBuffer(cmd));
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        VK_CHECK(vkQueueSubmit(queue, 1, &si, fence));
        VK_CHECK(vkWaitForFences(dev, 1, &fence, VK_TRUE, UINT64_MAX));
        VK_CHECK(vkResetFences(dev, 1, &fence));
        lit = std::min(lit, luminance({1.2f, 0.0f, 1.2f}));       // ground inside the spot's inner cone
        boxTop = std::min(boxTop, luminance({0.0f, 1.0f, 0.2f})); // the box's top, under the light
        dark = std::max(dark, luminance({-7.0f, 0.0f, -5.0f}));   // ground far outside the cone
    }
    module.collect();
    size_t reports = module.takeReports().size();

    std::printf("host_example: worst of 3 frames: lit %.1f, box top %.1f, dark %.1f (of 255), %zu reports, "
                "%u validation messages\n",
                lit, boxTop, dark, reports, ml::validationErrors());

    vkDestroyFence(dev, fence, nullptr);
    vkDestroyCommandPool(dev, pool, nullptr);
    vkDestroyPipeline(dev, pipeline, nullptr);
    vkDestroyPipelineLayout(dev, layout, nullptr);
    vkDestroyShaderModule(dev, vs, nullptr);
    vkDestroyShaderModule(dev, fs, nullptr);
    for (VkBuffer b : {geo, readback}) vkDestroyBuffer(dev, b, nullptr);
    for (VkDeviceMemory m : {geoMem, readbackMem}) vkFreeMemory(dev, m, nullptr);
    for (OwnedImage* h : {&depth, &normal, &albedo, &output}) {
        vkDestroyImageView(dev, h->view, nullptr);
        vkDestroyImage(dev, h->image, nullptr);
        vkFreeMemory(dev, h->memory, nullptr);
    }
    created.value().reset(); // the module's device goes last, after the host's objects on it

    const char* why = lit < 60.0f              ? "the ground under the spot light is not lit"
                      : boxTop < 60.0f         ? "the box top under the spot light is not lit"
                      : dark * 2.5f > lit      ? "the ground outside the cone is not dark"
                      : reports == 0           ? "no frame report arrived"
                      : ml::validationErrors() ? "validation messages"
                                               : nullptr;
    if (why) std::fprintf(stderr, "host_example: FAILED: %s\n", why);
    return why ? 1 : 0;
}
