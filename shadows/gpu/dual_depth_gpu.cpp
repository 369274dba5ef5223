#include "shadows/gpu/dual_depth_gpu.h"

#include "gpu/bindings.h"
#include "shadows/gpu/dual_depth_push.h"

#include "dual_depth.frag.spv.h"
#include "dual_depth.vert.spv.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ml {

Result<std::unique_ptr<DualDepthRenderer>> DualDepthRenderer::create(const Device& device) {
    std::unique_ptr<DualDepthRenderer> r(new DualDepthRenderer(device));
    ML_TRY(ML_LOAD_SHADER(device, r->vs_, spv_dual_depth_vert));
    ML_TRY(ML_LOAD_SHADER(device, r->fs_, spv_dual_depth_frag));
    GraphicsState state;
    state.cull = VK_CULL_MODE_NONE; // both faces: front faces enter, back faces exit
    // The light projection has no y flip (map row 0 = NDC y -1 = framebuffer row 0), so a triangle that
    // is counter-clockwise seen from the light (y up) is clockwise in Vulkan's framebuffer orientation.
    state.frontFace = VK_FRONT_FACE_CLOCKWISE;
    state.depthTest = false;
    state.depthWrite = false;
    for (uint32_t pass = 0; pass < 3; ++pass)
        ML_TRY(createGraphicsProgram(device, r->passes_[pass], {&r->vs_, &r->fs_}, state, {{0, pass}}));
    return r;
}

DualDepthRenderer::~DualDepthRenderer() {
    for (Program& p : passes_) destroyProgram(device_, p);
    destroyShader(device_, vs_);
    destroyShader(device_, fs_);
    destroyBuffer(device_, vertices_);
    destroyBuffer(device_, readback_);
    for (Image* i : {&enter_, &closed_, &exit_}) destroyImage(device_, *i);
}

Result<DualDepthMap> DualDepthRenderer::render(const CasterTriangles& casters, const LightFrustum& f,
                                               uint32_t res, uint32_t maxTile,
                                               const std::function<void(float)>& progress) {
    if (res == 0 || res > 65536)
        return fail("dual depth: resolution " + std::to_string(res) + " outside 1..65536");
    if (maxTile == 0 || maxTile > 4096) return fail("dual depth: tile size must be 1..4096");
    const Device& d = device_;
    d.waitDevice();
    // Upload the triangles (w marks closed meshes).
    std::vector<glm::vec4> verts;
    verts.reserve(casters.positions.size());
    for (size_t t = 0; t < casters.triangleCount(); ++t)
        for (int k = 0; k < 3; ++k)
            verts.emplace_back(casters.positions[t * 3 + k], casters.closed[t] ? 1.0f : 0.0f);
    // GPU-only, written once per map through a staging copy.
    ML_TRY(ensureBuffer(d, vertices_, verts.size() * sizeof(glm::vec4), kStorageBufferUsage, "dual_vertices",
                        MemoryRole::GpuOnly));
    ML_TRY(uploadBuffer(d, vertices_, verts.data(), verts.size() * sizeof(glm::vec4), 0, "dual_vertices"));

    const uint32_t tile = std::min(res, maxTile);
    if (tile != tile_) {
        for (Image* i : {&enter_, &closed_, &exit_}) destroyImage(d, *i);
        VkImageUsageFlags usage =
            VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        tile_ = 0; // until all three exist
        ML_TRY(createImage(d, enter_, tile, tile, VK_FORMAT_R32_UINT, usage, "dual_enter"));
        ML_TRY(createImage(d, closed_, tile, tile, VK_FORMAT_R32_UINT, usage, "dual_closed"));
        ML_TRY(createImage(d, exit_, tile, tile, VK_FORMAT_R32_UINT, usage, "dual_exit"));
        tile_ = tile;
    }
    ML_TRY(ensureBuffer(d, readback_, size_t(tile) * tile * 4 * 3, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                        "dual_readback", MemoryRole::Readback));

    DualDepthMap map;
    map.resolution = res;
    map.enter.assign(size_t(res) * res, kDepthEmpty);
    map.exit.assign(size_t(res) * res, kDepthEmpty);
    const glm::mat4 proj = glm::perspectiveRH_ZO(f.fov, 1.0f, f.nearPlane, f.farPlane);
    const uint32_t tilesPerAxis = (res + tile - 1) / tile;
    uint32_t done = 0;
    for (uint32_t ty = 0; ty < tilesPerAxis; ++ty)
        for (uint32_t tx = 0; tx < tilesPerAxis; ++tx) {
            const uint32_t x0 = tx * tile, y0 = ty * tile;
            const uint32_t w = std::min(tile, res - x0), h = std::min(tile, res - y0);
            // Tile projection: x' = x * R/T + ((R - 2 x0)/T - 1) w, likewise y (see the header).
            glm::mat4 crop(1.0f);
            crop[0][0] = float(res) / float(tile);
            crop[1][1] = float(res) / float(tile);
            crop[3][0] = (float(res) - 2.0f * float(x0)) / float(tile) - 1.0f;
            crop[3][1] = (float(res) - 2.0f * float(y0)) / float(tile) - 1.0f;
            gpu::DualDepthPush push{crop * proj * f.view, f.view,
                                    glm::vec4(f.farPlane, float(x0), float(y0), float(tile))};

            auto began = d.tryBeginOneTime("dual depth tile");
            ML_TRY(began);
            VkCommandBuffer cmd = began.value();
            for (const Image* img : {&enter_, &closed_, &exit_}) {
                imageBarrier(cmd, img->image, img->aspect, VK_IMAGE_LAYOUT_UNDEFINED,
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0,
                             VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
                VkClearColorValue clear{};
                clear.uint32[0] = img == &closed_ ? 0u : kDepthEmpty;
                VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
                vkCmdClearColorImage(cmd, img->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &clear, 1,
                                     &range);
                imageBarrier(cmd, img->image, img->aspect, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_CLEAR_BIT,
                             VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                             VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
            }
            for (uint32_t pass = 0; pass < 3; ++pass) {
                beginAttachmentless(cmd, tile, {w, h});
                bindProgram(d, cmd, passes_[pass], push,
                            {ML_BIND(ML_DUAL_DEPTH_VERTICES, vertices_), ML_BIND(ML_DUAL_DEPTH_ENTER, enter_),
                             ML_BIND(ML_DUAL_DEPTH_CLOSED, closed_), ML_BIND(ML_DUAL_DEPTH_EXIT, exit_)});
                if (!verts.empty()) vkCmdDraw(cmd, uint32_t(verts.size()), 1, 0, 0);
                vkCmdEndRendering(cmd);
                fullBarrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                            VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
            }
            VkDeviceSize offset = 0;
            for (const Image* img : {&enter_, &closed_, &exit_}) {
                imageBarrier(cmd, img->image, img->aspect, VK_IMAGE_LAYOUT_GENERAL,
                             VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                             VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                             VK_ACCESS_2_TRANSFER_READ_BIT);
                VkBufferImageCopy region{};
                region.bufferOffset = offset;
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.imageExtent = {tile, tile, 1};
                vkCmdCopyImageToBuffer(cmd, img->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                       readback_.buffer, 1, &region);
                offset += VkDeviceSize(tile) * tile * 4;
            }
            fullBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_PIPELINE_STAGE_2_HOST_BIT);
            ML_TRY(d.tryEndOneTime(cmd, "dual depth tile"));

            const uint32_t* enter = readback_.as<uint32_t>();
            const uint32_t* closed = enter + size_t(tile) * tile;
            const uint32_t* exit = closed + size_t(tile) * tile;
            for (uint32_t y = 0; y < h; ++y)
                for (uint32_t x = 0; x < w; ++x) {
                    size_t s = size_t(y) * tile + x, t = size_t(y0 + y) * res + x0 + x;
                    uint32_t e = enter[s];
                    map.enter[t] = e;
                    if (e == kDepthEmpty)
                        map.exit[t] = kDepthEmpty;
                    else if (closed[s])
                        map.exit[t] = exit[s] == kDepthEmpty ? 0xFFFFFFFEu : exit[s];
                    else
                        map.exit[t] = e;
                }
            ++done;
            if (progress) progress(float(done) / float(tilesPerAxis * tilesPerAxis));
        }
    return map;
}

} // namespace ml
