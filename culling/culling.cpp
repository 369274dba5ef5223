#include "culling/culling.h"

#include "engine/profiler.h"
#include "shaders/shared/light_math.h"

#include "cluster_bounds.comp.spv.h"
#include "light_assign.comp.spv.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ml {

std::vector<float> sliceBoundaries(float nearPlane, float farPlane, uint32_t slices) {
    std::vector<float> far(slices);
    for (uint32_t s = 0; s < slices; ++s)
        far[s] = float(double(nearPlane) * std::pow(double(farPlane) / nearPlane, double(s + 1) / slices));
    far[slices - 1] = farPlane;
    return far;
}

ClusterGrid clusterGrid(uint32_t width, uint32_t height, CullingMode mode) {
    ClusterGrid g;
    g.tilesX = (width + ML_TILE_SIZE - 1) / ML_TILE_SIZE;
    g.tilesY = (height + ML_TILE_SIZE - 1) / ML_TILE_SIZE;
    g.slices = mode == CullingMode::Clustered ? ML_MAX_SLICES : 1;
    return g;
}

uint32_t sliceOf(float z, const std::vector<float>& sliceFar, uint32_t slices) {
    uint32_t s = 0;
    while (s + 1 < slices && z >= sliceFar[s]) ++s;
    return s;
}

void LightCulling::create(const Device& device) {
    boundsShader_ = ML_SHADER(device, spv_cluster_bounds_comp);
    assignShader_ = ML_SHADER(device, spv_light_assign_comp);
    boundsProgram_ = createComputeProgram(device, boundsShader_, 0);
    assignProgram_ = createComputeProgram(device, assignShader_, 0);
}

void LightCulling::destroy(const Device& device) {
    destroyProgram(device, boundsProgram_);
    destroyProgram(device, assignProgram_);
    destroyShader(device, boundsShader_);
    destroyShader(device, assignShader_);
    destroyBuffer(device, bounds);
    destroyBuffer(device, ranges);
    destroyBuffer(device, pool);
}

void LightCulling::resize(const Device& device, const ClusterGrid& g, uint32_t poolEntries) {
    grid = g;
    poolCapacity = poolEntries ? poolEntries : g.count() * ML_POOL_PER_CLUSTER;
    ensureBuffer(device, bounds, VkDeviceSize(g.count()) * sizeof(gpu::ClusterBounds), kStorageBufferUsage,
                 "cluster_bounds");
    ensureBuffer(device, ranges, VkDeviceSize(g.count()) * 8, kStorageBufferUsage, "cluster_ranges");
    ensureBuffer(device, pool, VkDeviceSize(poolCapacity) * 4, kStorageBufferUsage, "cluster_pool");
}

void LightCulling::record(const Device& device, VkCommandBuffer cmd, const Buffer& frame, const Buffer& slices,
                          const Buffer& lights, VkImageView depth, const Buffer& counters, Profiler& profiler) {
    profiler.run(cmd, Pass::ClusterBounds, [&](VkCommandBuffer c) {
        bindProgram(device, c, boundsProgram_,
                    {frame, slices, Descriptor(Image{.view = depth}, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL), bounds,
                     counters},
                    nullptr, 0);
        vkCmdDispatch(c, grid.tilesX, grid.tilesY, 1); // one group per tile by construction
        fullBarrier(c, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    });
    profiler.run(cmd, Pass::LightAssign, [&](VkCommandBuffer c) {
        bindProgram(device, c, assignProgram_, {frame, lights, bounds, ranges, pool, counters}, nullptr, 0);
        vkCmdDispatch(c, grid.tilesX, grid.tilesY, 1);
        fullBarrier(c, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    });
}

namespace {
// The shader's order-preserving float key (cluster_bounds.comp): min/max on keys also orders -0 < +0.
uint32_t toKey(float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}
float fromKey(uint32_t k) {
    uint32_t u = (k & 0x80000000u) ? (k & 0x7fffffffu) : ~k;
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}
} // namespace

ClusterReference cullReference(const std::vector<float>& depth, const gpu::FrameConstants& frame,
                               const std::vector<float>& sliceFar, const std::vector<gpu::GpuLight>& lights) {
    const uint32_t width = frame.size.x, height = frame.size.y, tilesX = frame.size.z, tilesY = frame.size.w;
    const uint32_t slices = frame.cluster.x;
    ClusterReference ref;
    std::vector<glm::uvec3> lo(size_t(tilesX) * tilesY * slices, glm::uvec3(0xFFFFFFFFu));
    std::vector<glm::uvec3> hi(lo.size(), glm::uvec3(0u));
    std::vector<uint8_t> occupied(lo.size(), 0);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            float d = depth[size_t(y) * width + x];
            if (!(d < 1.0f)) continue;
            glm::vec3 p = gpu::worldFromPixel(x, y, d, frame.invViewProj, frame.size);
            float z = gpu::linearDepth(d, frame.depth);
            uint32_t s = sliceOf(z, sliceFar, slices);
            size_t c = (size_t(y / ML_TILE_SIZE) * tilesX + x / ML_TILE_SIZE) * slices + s;
            for (int i = 0; i < 3; ++i) {
                lo[c][i] = std::min(lo[c][i], toKey(p[i]));
                hi[c][i] = std::max(hi[c][i], toKey(p[i]));
            }
            occupied[c] = 1;
        }
    ref.bounds.resize(lo.size());
    ref.lists.resize(lo.size());
    for (size_t c = 0; c < lo.size(); ++c) {
        auto& b = ref.bounds[c];
        if (!occupied[c]) {
            b.lo = glm::vec4(0.0f);
            b.hi = glm::vec4(0.0f);
            continue;
        }
        glm::vec3 l3(fromKey(lo[c].x), fromKey(lo[c].y), fromKey(lo[c].z));
        glm::vec3 h3(fromKey(hi[c].x), fromKey(hi[c].y), fromKey(hi[c].z));
        b.lo = glm::vec4(l3, 1.0f);
        b.hi = glm::vec4(h3, 0.0f);
        for (uint32_t l = 0; l < frame.cluster.z; ++l)
            if (gpu::lightTouchesBox(lights[l], l3, h3)) ref.lists[c].push_back(l);
    }
    return ref;
}

} // namespace ml
