// A host engine's use of manylights, written from README.md, docs/integration.md and
// <manylights/manylights.h> only. The host makes its own instance (validation layer, its own message
// counter; synchronization validation with --sync or ML_VALIDATION_SYNC=1) and device, and lends the
// device to the module (ModuleOptions::borrow). It makes its own G-buffer images and graphics pipeline,
// draws a ground quad, a static box and a moving box (a dynamic caster: virtual shadow maps), hands the
// images over with setTargets, bakes the static shadows in the module (bakeStaticShadows), and records
// 10 frames with two frames in flight (two command buffers, two fences, two readbacks: frame f is
// checked when its slot comes round again): its G-buffer commands, then module.record(cmd), then a copy
// of the output. Frames 0-4 are LDR (RGBA8), 5-9 HDR (an RGBA16F output, switched with setTargets while
// frame 4 is in flight). A second spot light is added at frame 2, removed at frame 4 and added again at
// frame 6 (its slot reused: the old id is refused). Every frame's image is checked: the ground under the
// spot light lit, the box top lit, the ground outside the cones dark, the second light's ground lit
// exactly when it exists, the moving box's shadow on the ground where the box is and not where it was.
// After record(), in the same command buffer, the host runs its own lighting pass (lights.comp: the
// module's GLSL include, its buffers bound from hostShaderBindings() into a descriptor set per frame in
// flight): its radiance must equal the module's output in every pixel (HDR frames: the radiance
// itself; LDR frames: its tone map).
// Exit 0 when all holds and the host's messenger counted 0 validation messages, 1 with a reason.
#include <manylights/manylights.h>

#include "host_device.h"
#include "host_gbuffer_frag.h"
#include "host_gbuffer_vert.h"
#include "host_lights_comp.h"

#include <glm/glm.hpp> // the host's own glm (the module's headers include none)
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

// An engine's own VK_CHECK: the module's header must leave the name free (it uses ML_VK_CHECK).
#ifdef VK_CHECK
#error "manylights/module.h defines VK_CHECK, which clashes with host engines' own"
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

namespace {
constexpr int kFrames = 10, kHdrFrom = 5;
constexpr uint32_t kInFlight = 2;
// The moving box: 0.6 m, 2 m above the ground, alternating between two places (even and odd frames).
// Seen from the spot light 5 m up, its shadow on the ground is the box scaled by 5 / (5 - 2..2.6):
// around (2.5, 0, 2.5) from place A, around (-2.5, 0, 2.5) from place B.
const glm::vec3 kPlaceA{1.5f, 2.0f, 1.5f}, kPlaceB{-1.5f, 2.0f, 1.5f};
const glm::vec3 kShadowA{2.5f, 0.0f, 2.5f};

int fail(const std::string& why) {
    std::fprintf(stderr, "host_example: FAILED: %s\n", why.c_str());
    return 1;
}
} // namespace

int main(int argc, char** argv) {
    const char* env = std::getenv("ML_VALIDATION_SYNC");
    const bool sync = (argc > 1 && std::string(argv[1]) == "--sync") || (env && std::string(env) == "1");
    HostDevice host;
    createHostDevice(host, sync);
    VkDevice dev = host.device;
    VkPhysicalDevice pd = host.physicalDevice;

    ml::ModuleOptions options;
    options.borrow = host.borrow(); // the module renders on the host's device and queue
    options.framesInFlight = kInFlight;
    options.vsm.enabled = true; // the moving box's shadows
    auto created = ml::Module::create(options);
    if (!created) return fail(created.error());
    ml::Module& module = *created.value();

    // Scene: a 20 m ground quad and a 1 m box (static: baked), the moving box (dynamic), one spot light
    // 5 m above the ground pointing down.
    std::vector<ml::MeshVertex> verts;
    std::vector<uint32_t> indices;
    addBox(verts, indices, {-10, -1, -10}, {10, 0, 10}, true);
    const uint32_t groundIndices = uint32_t(indices.size());
    addBox(verts, indices, {-0.5f, 0, -0.5f}, {0.5f, 1, 0.5f}, false);
    const uint32_t staticIndices = uint32_t(indices.size());
    std::vector<ml::MeshVertex> boxVerts(verts.end() - 24, verts.end()); // the box again, about its corner
    std::vector<uint32_t> boxIndices(indices.begin() + groundIndices, indices.end());
    for (auto& v : boxVerts)
        for (int k = 0; k < 3; ++k) v.position[k] = v.position[k] * 0.6f + (k == 1 ? 0.0f : 0.3f) - 0.3f;
    for (uint32_t& i : boxIndices) i -= uint32_t(verts.size() - 24);
    const uint32_t movingFirstVertex = uint32_t(verts.size()), movingFirstIndex = uint32_t(indices.size());
    verts.insert(verts.end(), boxVerts.begin(), boxVerts.end());
    indices.insert(indices.end(), boxIndices.begin(), boxIndices.end());
    std::vector<ml::MeshVertex> staticVerts(verts.begin(), verts.begin() + movingFirstVertex);
    std::vector<uint32_t> staticIdx(indices.begin(), indices.begin() + staticIndices);
    auto staticMesh = module.addMesh({staticVerts, staticIdx, false, "ground+box"});
    auto movingMesh = module.addMesh({boxVerts, boxIndices, true, "moving box"});
    if (!staticMesh || !movingMesh) return fail("addMesh failed");
    auto movingAt = [](glm::vec3 p) { return glm::translate(glm::mat4(1.0f), p); };
    auto ground = module.addInstance(staticMesh.value(), glm::mat4(1.0f), glm::vec3(0.5f), false);
    auto moving =
        module.addInstance(movingMesh.value(), movingAt(kPlaceA), glm::vec3(0.3f, 0.4f, 0.8f), true);
    if (!ground || !moving) return fail("addInstance failed");
    ml::LightDesc spot;
    spot.position = {0, 5, 0};
    spot.range = 12;
    spot.intensity = 30;
    spot.outerAngle = 0.9f;
    spot.innerAngle = 0.7f;
    if (auto id = module.addLight(spot); !id) return fail(id.error());
    ml::LightDesc second = spot; // added and removed during the run
    second.position = {-5, 5, 3};
    second.outerAngle = 0.6f;
    second.innerAngle = 0.4f;
    // Static shadows baked in the module from its static instances (a load-time call: it may wait).
    auto baked = module.bakeStaticShadows(ml::StaticMethod::DAGMH, 256);
    if (!baked || baked.value() != 1) return fail(baked ? "bakeStaticShadows baked no light" : baked.error());

    // The host's own camera matrices: a right-handed view and a reversed-Z projection into Vulkan clip
    // space (near -> 1, far -> 0: near and far swapped in perspectiveRH_ZO; y flipped). Its G-buffer is
    // drawn with the same matrices, cleared to depth 0 and tested with GREATER.
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 8, 12), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    glm::mat4 proj = glm::perspectiveRH_ZO(1.0f, float(kWidth) / kHeight, 100.0f, 0.1f);
    proj[1][1] *= -1.0f;
    if (auto r = module.setCameraMatrices(view, proj); !r) return fail(r.error());
    const glm::mat4 viewProj = proj * view;

    // Host-owned targets: one G-buffer (frames in flight are ordered on the one queue by the barriers
    // below), an LDR and an HDR output.
    OwnedImage depth = makeImage(dev, pd, VK_FORMAT_D32_SFLOAT,
                                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                                 VK_IMAGE_ASPECT_DEPTH_BIT);
    const VkImageUsageFlags colorUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    OwnedImage normal = makeImage(dev, pd, kNormalFormat, colorUsage, VK_IMAGE_ASPECT_COLOR_BIT);
    OwnedImage albedo = makeImage(dev, pd, kAlbedoFormat, colorUsage, VK_IMAGE_ASPECT_COLOR_BIT);
    const VkImageUsageFlags outUsage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    OwnedImage ldr = makeImage(dev, pd, VK_FORMAT_R8G8B8A8_UNORM, outUsage, VK_IMAGE_ASPECT_COLOR_BIT);
    OwnedImage hdr = makeImage(dev, pd, VK_FORMAT_R16G16B16A16_SFLOAT, outUsage, VK_IMAGE_ASPECT_COLOR_BIT);
    auto targets = [&](bool hdrOut) {
        ml::HostTargets t{kWidth,          kHeight,         depth.target(),
                          normal.target(), albedo.target(), hdrOut ? hdr.target() : ldr.target()};
        t.hdrOutput = hdrOut;
        return t;
    };
    if (auto r = module.setTargets(targets(false)); !r) return fail(r.error());

    // Host buffers: vertices + indices, and one readback per frame in flight (host-visible, coherent).
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
    VkBuffer geo, readback[kInFlight];
    VkDeviceMemory geoMem, readbackMem[kInFlight];
    uint8_t* g = makeBuffer(
        vbytes + ibytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT, geo, geoMem);
    std::memcpy(g, verts.data(), vbytes);
    std::memcpy(g + vbytes, indices.data(), ibytes);
    const uint8_t* pixels[kInFlight];
    for (uint32_t s = 0; s < kInFlight; ++s)
        pixels[s] =
            makeBuffer(kWidth * kHeight * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT, readback[s], readbackMem[s]);
    // The host lighting pass's result per slot (lights.comp's HostPixel: radiance, packed tone map).
    VkBuffer lightsOut[kInFlight];
    VkDeviceMemory lightsOutMem[kInFlight];
    const float* hostRadiance[kInFlight];
    for (uint32_t s = 0; s < kInFlight; ++s)
        hostRadiance[s] = reinterpret_cast<const float*>(makeBuffer(
            kWidth * kHeight * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, lightsOut[s], lightsOutMem[s]));

    // The host's G-buffer pipeline: dynamic rendering, two colour attachments and depth.
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

    // The host's lighting pass: set 0 its own (G-buffer, result), set 1 the module's buffers (the
    // include's layout, ml::hostShaderLayout), one pair of sets per frame in flight.
    VkDescriptorSetLayoutBinding own[4] = {
        {0, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {1, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {2, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
    const auto moduleBindings = ml::hostShaderLayout(0, VK_SHADER_STAGE_COMPUTE_BIT);
    VkDescriptorSetLayout setLayouts[2];
    VkDescriptorSetLayoutCreateInfo dli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO, nullptr, 0, 4,
                                        own};
    VK_CHECK(vkCreateDescriptorSetLayout(dev, &dli, nullptr, &setLayouts[0]));
    dli.bindingCount = uint32_t(moduleBindings.size());
    dli.pBindings = moduleBindings.data();
    VK_CHECK(vkCreateDescriptorSetLayout(dev, &dli, nullptr, &setLayouts[1]));
    VkPipelineLayoutCreateInfo lightsLci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    lightsLci.setLayoutCount = 2;
    lightsLci.pSetLayouts = setLayouts;
    VkPipelineLayout lightsLayout;
    VK_CHECK(vkCreatePipelineLayout(dev, &lightsLci, nullptr, &lightsLayout));
    VkShaderModule cs = shader(host_lights_comp, sizeof(host_lights_comp));
    VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                 nullptr,
                 0,
                 VK_SHADER_STAGE_COMPUTE_BIT,
                 cs,
                 "main",
                 nullptr};
    cpi.layout = lightsLayout;
    VkPipeline lightsPipeline;
    VK_CHECK(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &cpi, nullptr, &lightsPipeline));
    VkDescriptorPoolSize poolSizes[3] = {{VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 3 * kInFlight},
                                         {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 11 * kInFlight},
                                         {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 2 * kInFlight}};
    VkDescriptorPoolCreateInfo dpi{
        VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, nullptr, 0, 2 * kInFlight, 3, poolSizes};
    VkDescriptorPool descriptorPool;
    VK_CHECK(vkCreateDescriptorPool(dev, &dpi, nullptr, &descriptorPool));
    VkDescriptorSet sets[kInFlight][2];
    for (uint32_t s = 0; s < kInFlight; ++s) {
        VkDescriptorSetAllocateInfo dai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, nullptr,
                                        descriptorPool, 2, setLayouts};
        VK_CHECK(vkAllocateDescriptorSets(dev, &dai, sets[s]));
        const VkImageLayout ro = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
        VkDescriptorImageInfo gb[3] = {{VK_NULL_HANDLE, depth.view, ro},
                                       {VK_NULL_HANDLE, normal.view, ro},
                                       {VK_NULL_HANDLE, albedo.view, ro}};
        VkDescriptorBufferInfo result{lightsOut[s], 0, VK_WHOLE_SIZE};
        VkWriteDescriptorSet w[2] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, sets[s][0], 0, 0, 3,
                                      VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, gb, nullptr, nullptr},
                                     {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, sets[s][0], 3, 0, 1,
                                      VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, nullptr, &result, nullptr}};
        vkUpdateDescriptorSets(dev, 2, w, 0, nullptr);
    }

    // Two frames in flight: a command buffer, a fence (created signalled) and a readback per slot.
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO, nullptr,
                                VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT, host.queueFamily};
    VkCommandPool pool;
    VK_CHECK(vkCreateCommandPool(dev, &pci, nullptr, &pool));
    VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, nullptr, pool,
                                    VK_COMMAND_BUFFER_LEVEL_PRIMARY, kInFlight};
    VkCommandBuffer cmds[kInFlight];
    VK_CHECK(vkAllocateCommandBuffers(dev, &cai, cmds));
    VkFence fences[kInFlight];
    for (VkFence& f : fences) {
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, nullptr, VK_FENCE_CREATE_SIGNALED_BIT};
        VK_CHECK(vkCreateFence(dev, &fci, nullptr, &f));
    }

    // What each frame had, for checking its image when its slot comes round: HDR or not, the second
    // light present, the moving box at place A.
    struct FrameState {
        int frame = -1;
        bool hdr = false, second = false, atA = false;
    } inFlight[kInFlight];
    std::string problem;
    auto check = [&](const FrameState& s, const uint8_t* px) {
        if (s.frame < 0 || !problem.empty()) return;
        // Brightness at a world point's pixel: LDR mean of the tone-mapped bytes (0..1), HDR mean of the
        // linear radiance; the checks compare points of the same frame, so both scales work.
        auto at = [&](glm::vec3 world) {
            glm::vec4 clip = viewProj * glm::vec4(world, 1.0f);
            size_t x = size_t((clip.x / clip.w * 0.5f + 0.5f) * kWidth),
                   y = size_t((clip.y / clip.w * 0.5f + 0.5f) * kHeight), i = y * kWidth + x;
            if (!s.hdr) return (px[i * 4] + px[i * 4 + 1] + px[i * 4 + 2]) / (3.0f * 255.0f);
            uint32_t w[2];
            std::memcpy(w, px + i * 8, 8);
            glm::vec2 rg = glm::unpackHalf2x16(w[0]), ba = glm::unpackHalf2x16(w[1]);
            return (rg.x + rg.y + ba.x) / 3.0f;
        };
        const float lit = at({1.2f, 0.0f, 1.2f}), boxTop = at({0.0f, 1.0f, 0.2f}),
                    dark = at({-7.0f, 0.0f, -5.0f});
        const float secondGround = at({-5.0f, 0.0f, 3.0f}), shadowA = at(kShadowA);
        std::printf(
            "host_example: frame %d (%s, second light %s, box at %s): lit %.3f, box top %.3f, dark %.3f, "
            "second light's ground %.3f, ground under place A %.3f\n",
            s.frame, s.hdr ? "HDR" : "LDR", s.second ? "on" : "off", s.atA ? "A" : "B", lit, boxTop, dark,
            secondGround, shadowA);
        const std::string f = "frame " + std::to_string(s.frame) + ": ";
        // The host's own lighting pass against the module's output, every pixel: HDR frames hold the
        // radiance as half floats (rounding <= 2^-11 of the value), LDR frames its exposed tone map as
        // bytes (the host pass packs the same tone map: one step for the two roundings).
        const float* host = hostRadiance[uint32_t(s.frame) % kInFlight];
        size_t differ = 0;
        for (size_t i = 0; i < size_t(kWidth) * kHeight; ++i) {
            const glm::vec3 h(host[i * 4], host[i * 4 + 1], host[i * 4 + 2]);
            if (s.hdr) {
                uint32_t w[2];
                std::memcpy(w, px + i * 8, 8);
                const glm::vec3 e(glm::unpackHalf2x16(w[0]), glm::unpackHalf2x16(w[1]).x);
                for (int k = 0; k < 3; ++k)
                    differ += std::abs(h[k] - e[k]) > std::abs(e[k]) / 1024.0f + 1e-6f;
            } else {
                uint32_t t;
                std::memcpy(&t, host + i * 4 + 3, 4);
                for (int k = 0; k < 3; ++k)
                    differ += std::abs(int((t >> (8 * k)) & 0xFFu) - int(px[i * 4 + k])) > 1;
            }
        }
        std::printf("host_example: frame %d: the host's lighting pass and the module's output differ in %zu "
                    "channels of %u pixels\n",
                    s.frame, differ, kWidth * kHeight);
        if (differ)
            problem = f + "the host's lighting pass (the GLSL include) differs from the module's output";
        if (lit < (s.hdr ? 0.02f : 0.25f))
            problem = f + "the ground under the spot light is not lit";
        else if (boxTop < 0.5f * lit)
            problem = f + "the box top under the spot light is not lit";
        else if (dark > 0.4f * lit)
            problem = f + "the ground outside the cones is not dark";
        // Lit or not, between the ambient-only level (`dark`) and the spot's ground (`lit`).
        else if (s.second != (secondGround > dark + 0.4f * (lit - dark)))
            problem = f + (s.second ? "the second light's ground is dark" : "the removed light still lights");
        else if (s.atA != (shadowA < dark + 0.25f * (lit - dark)))
            problem =
                f + (s.atA ? "no moving-box shadow under place A" : "the moving box's old shadow stays");
    };

    std::optional<ml::LightId> secondId, removedId;
    const auto kColor = VK_IMAGE_ASPECT_COLOR_BIT;
    const auto kAttach = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    const auto kDepthStages =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    const auto kRead = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    size_t reports = 0;
    for (int frame = 0; frame < kFrames; ++frame) {
        const uint32_t slot = uint32_t(frame) % kInFlight;
        // The slot's previous frame: wait for it (the module's slot contract), check its image.
        VK_CHECK(vkWaitForFences(dev, 1, &fences[slot], VK_TRUE, UINT64_MAX));
        VK_CHECK(vkResetFences(dev, 1, &fences[slot]));
        check(inFlight[slot], pixels[slot]);
        module.collect();
        reports += module.takeReports().size();

        // Scene edits of this frame, none of which waits for the device (docs/integration.md).
        const bool hdrFrame = frame >= kHdrFrom;
        if (frame == kHdrFrom)
            if (auto r = module.setTargets(targets(true)); !r) return fail(r.error());
        if (frame == 2 || frame == 6) {
            auto id = module.addLight(second);
            if (!id) return fail(id.error());
            secondId = id.value();
        }
        if (frame == 4) {
            if (auto r = module.removeLight(*secondId); !r) return fail(r.error());
            removedId = secondId;
            secondId.reset();
        }
        if (frame == 6 && module.removeLight(*removedId))
            return fail("removeLight accepted the id of a light removed before (its slot holds a new one)");
        const bool atA = frame % 2 == 0;
        const glm::mat4 movingModel = movingAt(atA ? kPlaceA : kPlaceB);
        if (auto r = module.setInstanceTransform(moving.value(), movingModel); !r) return fail(r.error());
        inFlight[slot] = {frame, hdrFrame, secondId.has_value(), atA};
        OwnedImage& output = hdrFrame ? hdr : ldr;

        VkCommandBuffer cmd = cmds[slot];
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
        // The G-buffer: previous frame's contents are discarded (UNDEFINED), after the module's reads.
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
            glm::mat4 viewProjModel; // the moving box only translates: its normals stay as they are
            glm::vec4 albedo;
        } draw{viewProj, {0.5f, 0.5f, 0.5f, 1}};
        vkCmdPushConstants(cmd, layout, push.stageFlags, 0, sizeof(draw), &draw);
        vkCmdDrawIndexed(cmd, staticIndices, 1, 0, 0, 0);
        draw = {viewProj * movingModel, {0.3f, 0.4f, 0.8f, 1}};
        vkCmdPushConstants(cmd, layout, push.stageFlags, 0, sizeof(draw), &draw);
        vkCmdDrawIndexed(cmd, uint32_t(boxIndices.size()), 1, movingFirstIndex, int32_t(movingFirstVertex),
                         0);
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
        if (auto r = module.record(cmd); !r) return fail(r.error());
        // The host's lighting pass over this frame's lights and shadows: the module's buffers of this
        // frame into the slot's set (its previous frame is done: the fence above), then a dispatch;
        // record() left their writes visible to compute reads.
        auto lightsBuffers = module.hostShaderBindings();
        if (!lightsBuffers) return fail(lightsBuffers.error());
        VkDescriptorBufferInfo infos[ML_HOST_BINDING_COUNT];
        VkWriteDescriptorSet writes[ML_HOST_BINDING_COUNT];
        for (uint32_t i = 0; i < ML_HOST_BINDING_COUNT; ++i) {
            const ml::HostShaderBuffer& b = lightsBuffers->buffers[i];
            infos[i] = {b.buffer, b.offset, b.range};
            writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                         nullptr,
                         sets[slot][1],
                         i,
                         0,
                         1,
                         b.type,
                         nullptr,
                         &infos[i],
                         nullptr};
        }
        vkUpdateDescriptorSets(dev, ML_HOST_BINDING_COUNT, writes, 0, nullptr);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, lightsPipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, lightsLayout, 0, 2, sets[slot], 0,
                                nullptr);
        vkCmdDispatch(cmd, (kWidth + 7) / 8, (kHeight + 7) / 8, 1);
        VkMemoryBarrier2 toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                                nullptr,
                                kRead,
                                VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                                VK_PIPELINE_STAGE_2_HOST_BIT,
                                VK_ACCESS_2_HOST_READ_BIT};
        VkDependencyInfo toHostDep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
        toHostDep.memoryBarrierCount = 1;
        toHostDep.pMemoryBarriers = &toHost;
        vkCmdPipelineBarrier2(cmd, &toHostDep);
        // The host reads the output back into the slot's readback (a real engine would blit or sample it).
        barrier(cmd, output.image, kColor, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                kRead, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                VK_ACCESS_2_TRANSFER_READ_BIT);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {kColor, 0, 0, 1};
        copy.imageExtent = {kWidth, kHeight, 1};
        vkCmdCopyImageToBuffer(cmd, output.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback[slot], 1,
                               &copy);
        VK_CHECK(vkEndCommandBuffer(cmd));
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        VK_CHECK(vkQueueSubmit(host.queue, 1, &si, fences[slot]));
    }
    // The last frames in flight.
    for (uint32_t k = 0; k < kInFlight; ++k) {
        const uint32_t slot = uint32_t(kFrames + k) % kInFlight;
        VK_CHECK(vkWaitForFences(dev, 1, &fences[slot], VK_TRUE, UINT64_MAX));
        check(inFlight[slot], pixels[slot]);
    }
    module.collect();
    reports += module.takeReports().size();
    const uint32_t messages = hostValidationMessages();
    std::printf(
        "host_example: %d frames, 2 in flight, borrowed device, %s validation: %zu reports, %u validation "
        "messages\n",
        kFrames, sync ? "synchronization" : "core", reports, messages);

    for (VkFence f : fences) vkDestroyFence(dev, f, nullptr);
    vkDestroyCommandPool(dev, pool, nullptr);
    vkDestroyPipeline(dev, pipeline, nullptr);
    vkDestroyPipelineLayout(dev, layout, nullptr);
    vkDestroyShaderModule(dev, vs, nullptr);
    vkDestroyShaderModule(dev, fs, nullptr);
    vkDestroyDescriptorPool(dev, descriptorPool, nullptr);
    vkDestroyPipeline(dev, lightsPipeline, nullptr);
    vkDestroyPipelineLayout(dev, lightsLayout, nullptr);
    for (VkDescriptorSetLayout l : setLayouts) vkDestroyDescriptorSetLayout(dev, l, nullptr);
    vkDestroyShaderModule(dev, cs, nullptr);
    vkDestroyBuffer(dev, geo, nullptr);
    vkFreeMemory(dev, geoMem, nullptr);
    for (uint32_t s = 0; s < kInFlight; ++s) {
        vkDestroyBuffer(dev, readback[s], nullptr);
        vkFreeMemory(dev, readbackMem[s], nullptr);
        vkDestroyBuffer(dev, lightsOut[s], nullptr);
        vkFreeMemory(dev, lightsOutMem[s], nullptr);
    }
    for (OwnedImage* h : {&depth, &normal, &albedo, &ldr, &hdr}) {
        vkDestroyImageView(dev, h->view, nullptr);
        vkDestroyImage(dev, h->image, nullptr);
        vkFreeMemory(dev, h->memory, nullptr);
    }
    created.value().reset(); // the module goes before the host's device (DeviceBorrow)
    destroyHostDevice(host);

    if (!problem.empty()) return fail(problem);
    if (reports < size_t(kFrames - 1))
        return fail("only " + std::to_string(reports) + " frame reports arrived");
    if (messages) return fail(std::to_string(messages) + " validation messages");
    return 0;
}
