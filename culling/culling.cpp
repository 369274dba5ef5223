#include "culling/culling.h"

#include "culling/culling_bindings.h"
#include "culling/culling_push.h"
#include "gpu/bindings.h"
#include "shaders/shared/light_math.h"

#include "cluster_bounds.comp.spv.h"
#include "cluster_bounds_wave.comp.spv.h"
#include "light_alloc.comp.spv.h"
#include "light_assign.comp.spv.h"
#include "light_fill.comp.spv.h"
#include "light_footprint.comp.spv.h"
#include "view_lights.comp.spv.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ml {

namespace {
constexpr auto kC = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr auto kR = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr auto kW = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
} // namespace

static_assert(uint32_t(CullingMode::Clustered) == ML_CULL_CLUSTERED &&
              uint32_t(CullingMode::Tiled) == ML_CULL_TILED && uint32_t(CullingMode::None) == ML_CULL_NONE &&
              uint32_t(CullingMode::ClusteredBrute) == ML_CULL_CLUSTERED_BRUTE);
static_assert(ML_FOOTPRINT_GROUP % ML_FOOTPRINT_LANES == 0, "a light's lanes share one group");
static_assert(ML_CLUSTER_SLICES <= ML_MAX_SLICES && ML_MAX_SLICES <= 64, "tile masks hold 64 slices");

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
    g.slices = mode == CullingMode::Clustered || mode == CullingMode::ClusteredBrute ? ML_CLUSTER_SLICES : 1;
    return g;
}

uint32_t sliceOf(float z, const std::vector<float>& sliceFar, uint32_t slices) {
    uint32_t s = 0;
    while (s + 1 < slices && z >= sliceFar[s]) ++s;
    return s;
}

std::optional<gpu::LightFootprint> wideFootprint(const gpu::GpuLight& light,
                                                 const gpu::FrameConstants& frame) {
    // Only directional lights are wide: the kind first, so the others cost no footprint.
    if (light.info.x != ML_LIGHT_DIRECTIONAL) return std::nullopt;
    const gpu::LightFootprint f =
        gpu::lightFootprint(light, frame.viewProj, frame.size, frame.cluster.y, frame.depth.x);
    if (f.tiles.x > f.tiles.z || f.tiles.y > f.tiles.w) return std::nullopt; // off screen
    return f;
}

Result<void> LightCulling::create(const Device& device) {
    // The wave build runs a tile in one subgroup of ML_TILE_SIZE lanes (subgroupMin / Max, subgroupElect):
    // basic + arithmetic operations in compute shaders (a SPIR-V module declaring them may not be created
    // on a device without them), and no subgroup smaller than a workgroup (a SPIR-V 1.6 module may run at
    // any size from minSubgroupSize up). ML_BOUNDS_WAVE=0 keeps the per-lane build (tests compare both
    // with the reference).
    VkPhysicalDeviceSubgroupSizeControlProperties size{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_SIZE_CONTROL_PROPERTIES};
    VkPhysicalDeviceSubgroupProperties sub{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES, &size};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &sub};
    vkGetPhysicalDeviceProperties2(device.physicalDevice, &props);
    const VkSubgroupFeatureFlags need = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
    const bool supported = (sub.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                           (sub.supportedOperations & need) == need && sub.subgroupSize >= ML_TILE_SIZE &&
                           size.minSubgroupSize >= ML_TILE_SIZE;
    const char* env = std::getenv("ML_BOUNDS_WAVE");
    waveBounds_ = supported && !(env && std::strcmp(env, "0") == 0);
    if (!supported)
        std::fprintf(stderr,
                     "cluster_bounds: %s has no subgroup arithmetic in compute or subgroups under %u lanes: "
                     "per-lane build\n",
                     device.name.c_str(), unsigned(ML_TILE_SIZE));
    ML_TRY(waveBounds_ ? ML_LOAD_SHADER(device, boundsShader_, spv_cluster_bounds_wave_comp)
                       : ML_LOAD_SHADER(device, boundsShader_, spv_cluster_bounds_comp));
    ML_TRY(ML_LOAD_SHADER(device, assignShader_, spv_light_assign_comp));
    ML_TRY(ML_LOAD_SHADER(device, footprintShader_, spv_light_footprint_comp));
    ML_TRY(ML_LOAD_SHADER(device, allocShader_, spv_light_alloc_comp));
    ML_TRY(createComputeProgram(device, boundsProgram_, boundsShader_));
    ML_TRY(createComputeProgram(device, receiversProgram_, boundsShader_, {{0, 1u}})); // kReceivers
    ML_TRY(createComputeProgram(device, assignProgram_, assignShader_));
    ML_TRY(ML_LOAD_SHADER(device, fillShader_, spv_light_fill_comp));
    ML_TRY(createComputeProgram(device, countProgram_, footprintShader_, {{0, 0u}}));
    ML_TRY(createComputeProgram(device, wideProgram_, footprintShader_, {{0, 1u}}));
    ML_TRY(createComputeProgram(device, allocProgram_, allocShader_));
    for (uint32_t step = 0; step < 2; ++step) // mark, append (light_fill.comp's kSpecStep)
        ML_TRY(createComputeProgram(device, fillPrograms_[step], fillShader_, {{0, step}}));
    ML_TRY(ML_LOAD_SHADER(device, viewShader_, spv_view_lights_comp));
    for (uint32_t r = 0; r < 2; ++r)
        ML_TRY(createComputeProgram(device, viewPrograms_[r], viewShader_, {{0, r}}));
    // The host reads the box-test count (lastBoxTests).
    return createBuffer(device, work, 12, kStorageBufferUsage, "cull_work", MemoryRole::Readback);
}

void LightCulling::destroy(const Device& device) {
    destroyProgram(device, boundsProgram_);
    destroyProgram(device, receiversProgram_);
    destroyProgram(device, assignProgram_);
    destroyProgram(device, countProgram_);
    destroyProgram(device, wideProgram_);

    for (Program& p : fillPrograms_) destroyProgram(device, p);
    destroyProgram(device, allocProgram_);
    for (Program& p : viewPrograms_) destroyProgram(device, p);
    destroyShader(device, viewShader_);
    destroyShader(device, boundsShader_);
    destroyShader(device, assignShader_);
    destroyShader(device, footprintShader_);
    destroyShader(device, allocShader_);
    destroyShader(device, fillShader_);
    for (Buffer* b : {&bounds, &receivers, &ranges, &pool, &tileMasks, &counts, &work, &hits, &viewCounts,
                      &tileBits, &tilePrefix, &tileRanges, &tileSlices})
        destroyBuffer(device, *b);
}

Result<void> LightCulling::resize(const Device& device, const ClusterGrid& g, uint32_t poolEntries) {
    constexpr MemoryRole kGpu = MemoryRole::GpuOnly;
    grid = g;
    // Sized for the clustered grid in every mode: a tiled list holds what the tile's 64 clusters would
    // (at 4096 lights on the default view a tile's list is ~100 lights, past 16 per grid cluster).
    // The pool is bound whole: at most maxStorageBufferRange (lavapipe: 128 MiB, 2 M pixels of 64 B;
    // frames use a tenth of it, and lists past it overflow, counted, never lost).
    const uint64_t fit = device.properties.limits.maxStorageBufferRange / 4;
    poolCapacity = poolEntries
                       ? poolEntries
                       : uint32_t(std::min<uint64_t>(
                             uint64_t(g.tilesX) * g.tilesY * ML_CLUSTER_SLICES * ML_POOL_PER_CLUSTER, fit));
    ML_TRY(ensureBuffer(device, bounds, VkDeviceSize(g.count()) * sizeof(gpu::ClusterBounds),
                        kStorageBufferUsage, "cluster_bounds", kGpu));
    ML_TRY(ensureBuffer(device, ranges, VkDeviceSize(g.count()) * 8, kStorageBufferUsage, "cluster_ranges",
                        kGpu));
    ML_TRY(ensureBuffer(device, pool, VkDeviceSize(poolCapacity) * 4, kStorageBufferUsage, "cluster_pool",
                        kGpu));
    ML_TRY(ensureBuffer(device, tileMasks, VkDeviceSize(g.tilesX) * g.tilesY * 8, kStorageBufferUsage,
                        "tile_masks", kGpu));
    ML_TRY(ensureBuffer(device, counts, VkDeviceSize(g.count()) * 4, kStorageBufferUsage, "cluster_counts",
                        kGpu));
    hitCapacity = std::max(1u, poolCapacity / ML_HITS_PER_POOL_ENTRY_DIV);
    ML_TRY(
        ensureBuffer(device, hits, VkDeviceSize(hitCapacity) * 8, kStorageBufferUsage, "cluster_hits", kGpu));
    // The sorted fill's buffers (config.h, ML_TILE_WORDS): a tile's (tile, light) pairs are at most its
    // hits, so hitCapacity slice masks hold every frame whose hits fit.
    const VkDeviceSize tiles = VkDeviceSize(g.tilesX) * g.tilesY;
    ML_TRY(ensureBuffer(device, tileBits, tiles * ML_TILE_WORDS * 4, kStorageBufferUsage, "tile_light_bits",
                        kGpu));
    ML_TRY(ensureBuffer(device, tilePrefix, tiles * ML_TILE_WORDS * 4, kStorageBufferUsage,
                        "tile_light_prefix", kGpu));
    ML_TRY(ensureBuffer(device, tileRanges, tiles * 8, kStorageBufferUsage, "tile_light_ranges", kGpu));
    ML_TRY(ensureBuffer(device, tileSlices, VkDeviceSize(hitCapacity) * 8, kStorageBufferUsage,
                        "tile_light_slices", kGpu));
    return {};
}

Result<void> LightCulling::prepareView(const Device& device, uint32_t width, uint32_t height) {
    VkDeviceSize bytes = VkDeviceSize(width) * height * 4;
    if (viewCounts.buffer && viewCounts.size >= bytes) return {};
    releaseAfterFrame(device, viewCounts); // an earlier frame in flight may still write the old one
    ML_TRY(ensureBuffer(device, viewCounts, bytes, kStorageBufferUsage, "view_counts", MemoryRole::Readback));
    return {};
}

Result<void> LightCulling::ensureReceivers(const Device& device) {
    ML_TRY(ensureBuffer(device, receivers, VkDeviceSize(grid.count()) * sizeof(gpu::ClusterReceivers),
                        kStorageBufferUsage, "cluster_receivers", MemoryRole::GpuOnly));
    return {};
}

void LightCulling::recordBounds(const Device& device, VkCommandBuffer c, const BoundsInputs& in) {
    const bool withReceivers =
        wantReceivers && receivers.buffer && receivers.size >= grid.count() * sizeof(gpu::ClusterReceivers);
    constexpr VkImageLayout kRead = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    // One group per tile: ML_TILE_SIZE^2 threads (a thread per pixel), or in the wave build one subgroup
    // of ML_TILE_SIZE (a thread per column). The plain variant binds the bounds in the receivers' slot
    // (never written there).
    dispatch(device, c, withReceivers ? receiversProgram_ : boundsProgram_, grid.tilesX * ML_TILE_SIZE,
             waveBounds_ ? grid.tilesY : grid.tilesY * ML_TILE_SIZE, NoPush{},
             {ML_BIND(ML_BOUNDS_FRAME, *in.frame), ML_BIND(ML_BOUNDS_SLICES, *in.slices),
              ML_BIND(ML_BOUNDS_DEPTH, Descriptor(in.depth, kRead)), ML_BIND(ML_BOUNDS_OUT, bounds),
              ML_BIND(ML_BOUNDS_COUNTERS, *in.counters), ML_BIND(ML_BOUNDS_TILE_MASKS, tileMasks),
              ML_BIND(ML_BOUNDS_NORMAL, Descriptor(in.normal, kRead)),
              ML_BIND(ML_BOUNDS_RECEIVERS, withReceivers ? receivers : bounds)});
    // Cluster bounds and tile masks -> light assignment (read); counters (atomics) -> assignment's
    // atomics.
    memoryBarrier(c, kC, kW, kC, kR | kW);
}

void LightCulling::recordAssign(const Device& device, VkCommandBuffer c, const AssignInputs& in) {
    const Buffer& frame = *in.frame;
    const gpu::FrameConstants& fc = *frame.as<gpu::FrameConstants>();
    const uint32_t mode = fc.cluster.w, visible = fc.cluster.z;
    const uint32_t tiles = grid.tilesX * grid.tilesY;
    vkCmdFillBuffer(c, work.buffer, 0, VK_WHOLE_SIZE, 0);
    if (mode == ML_CULL_CLUSTERED) {
        vkCmdFillBuffer(c, counts.buffer, 0, VK_WHOLE_SIZE, 0);
        vkCmdFillBuffer(c, tileBits.buffer, 0, VK_WHOLE_SIZE, 0);
    }
    // Cleared work counters and per-cluster counts -> the atomics of count, alloc, fill and assign.
    memoryBarrier(c, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, kC, kR | kW);
    if (mode == ML_CULL_CLUSTERED) {
        // Count and record hits (ML_FOOTPRINT_LANES threads per light), allocate (one thread per tile),
        // mark (ML_FILL_GROUPS groups stride over the hits) and append (one thread per tile, walking
        // its lights in index order: the lists come out sorted, in time linear in the hits).
        const gpu::CullPush push{hitCapacity, in.wideCount, in.wideThreads};
        // Both footprint variants read and write the same buffers.
        auto footprint = [&](const Program& program, uint32_t threadsX, uint32_t threadsY) {
            dispatch(device, c, program, threadsX, threadsY, push,
                     {ML_BIND(ML_FOOTPRINT_FRAME, frame), ML_BIND(ML_FOOTPRINT_SLICES, *in.slices),
                      ML_BIND(ML_FOOTPRINT_LIGHTS, *in.lights), ML_BIND(ML_FOOTPRINT_BOUNDS, bounds),
                      ML_BIND(ML_FOOTPRINT_TILE_MASKS, tileMasks), ML_BIND(ML_FOOTPRINT_COUNTS, counts),
                      ML_BIND(ML_FOOTPRINT_HITS, hits), ML_BIND(ML_FOOTPRINT_WORK, work),
                      ML_BIND(ML_FOOTPRINT_WIDE, *in.wideLights), ML_BIND(ML_FOOTPRINT_TILE_BITS, tileBits)});
        };
        if (visible) {
            footprint(countProgram_, visible * ML_FOOTPRINT_LANES, 1);
            // The wide lights: a thread per tile of each one's footprint, in rows of ML_WIDE_ROW. Its
            // atomics (counts, hit cursor) commute with the lane pass's: no barrier between the two.
            if (in.wideThreads)
                footprint(wideProgram_, std::min(in.wideThreads, uint32_t(ML_WIDE_ROW)),
                          (in.wideThreads + ML_WIDE_ROW - 1) / ML_WIDE_ROW);
            memoryBarrier(c, kC, kW, kC, kR | kW); // counts, hits, work -> alloc (reads; pool cursor atomics)
        }
        dispatch(device, c, allocProgram_, tiles, 1, push,
                 {ML_BIND(ML_ALLOC_FRAME, frame), ML_BIND(ML_ALLOC_TILE_MASKS, tileMasks),
                  ML_BIND(ML_ALLOC_COUNTS, counts), ML_BIND(ML_ALLOC_RANGES, ranges),
                  ML_BIND(ML_ALLOC_COUNTERS, *in.counters), ML_BIND(ML_ALLOC_WORK, work),
                  ML_BIND(ML_ALLOC_TILE_BITS, tileBits), ML_BIND(ML_ALLOC_TILE_PREFIX, tilePrefix),
                  ML_BIND(ML_ALLOC_TILE_RANGES, tileRanges), ML_BIND(ML_ALLOC_TILE_SLICES, tileSlices)});
        // Ranges, prefix counts, tile ranges, cleared slice masks -> mark (reads, atomics).
        memoryBarrier(c, kC, kW, kC, kR | kW);
        if (visible) {
            // Mark, then append: one shader, the same buffers.
            auto fill = [&](const Program& program, uint32_t threads) {
                dispatch(device, c, program, threads, 1, push,
                         {ML_BIND(ML_FILL_FRAME, frame), ML_BIND(ML_FILL_HITS, hits),
                          ML_BIND(ML_FILL_RANGES, ranges), ML_BIND(ML_FILL_POOL, pool),
                          ML_BIND(ML_FILL_WORK, work), ML_BIND(ML_FILL_TILE_BITS, tileBits),
                          ML_BIND(ML_FILL_TILE_PREFIX, tilePrefix), ML_BIND(ML_FILL_TILE_RANGES, tileRanges),
                          ML_BIND(ML_FILL_TILE_SLICES, tileSlices)});
            };
            fill(fillPrograms_[0], ML_FILL_GROUPS * ML_FILL_GROUP);
            memoryBarrier(c, kC, kW, kC, kR); // slice masks -> append
            fill(fillPrograms_[1], tiles);
        }
    } else {
        // One ML_ASSIGN_GROUP group per tile (its threads stride over the lights).
        dispatch(device, c, assignProgram_, grid.tilesX * ML_ASSIGN_GROUP, grid.tilesY, NoPush{},
                 {ML_BIND(ML_ASSIGN_FRAME, frame), ML_BIND(ML_ASSIGN_LIGHTS, *in.lights),
                  ML_BIND(ML_ASSIGN_BOUNDS, bounds), ML_BIND(ML_ASSIGN_RANGES, ranges),
                  ML_BIND(ML_ASSIGN_POOL, pool), ML_BIND(ML_ASSIGN_COUNTERS, *in.counters),
                  ML_BIND(ML_ASSIGN_WORK, work)});
    }
    // Ranges and pool -> every later reader (VSM marks, evaluation, statistics, views: compute).
    // The counters reach the host through the frame-end barrier (engine/frame_passes.cpp).
    memoryBarrier(c, kC, kW, kC, kR);
}

void LightCulling::recordView(const Device& device, VkCommandBuffer c, const ViewInputs& in) {
    // viewCounts was sized by prepareView (Module::Impl::beginFrame).
    // The evaluation's output -> overwritten here (write-after-write).
    memoryBarrier(c, kC, kW, kC, kW);
    dispatch(device, c, viewPrograms_[in.reaching ? 1 : 0], in.width, in.height, NoPush{},
             {ML_BIND(ML_VIEW_FRAME, *in.frame), ML_BIND(ML_VIEW_SLICES, *in.slices),
              ML_BIND(ML_VIEW_LIGHTS, *in.lights), ML_BIND(ML_VIEW_RANGES, ranges),
              ML_BIND(ML_VIEW_DEPTH, Descriptor(in.depth, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)),
              ML_BIND(ML_VIEW_OUTPUT, Descriptor(in.output)), ML_BIND(ML_VIEW_COUNTS, viewCounts)});
    // Output -> the host's reads after record(); per-pixel counts -> host (tests read them mapped).
    memoryBarrier(c, kC, kW, kOutputReaderStages | VK_PIPELINE_STAGE_2_HOST_BIT,
                  kOutputReads | VK_ACCESS_2_HOST_READ_BIT);
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

std::vector<gpu::ClusterReceivers> cullReceiversReference(const std::vector<float>& depth,
                                                          const std::vector<glm::vec4>& normal,
                                                          const gpu::FrameConstants& frame,
                                                          const std::vector<float>& sliceFar) {
    const uint32_t width = frame.size.x, height = frame.size.y, tilesX = frame.size.z, tilesY = frame.size.w;
    const uint32_t slices = frame.cluster.x;
    const size_t n = size_t(tilesX) * tilesY * slices;
    std::vector<glm::uvec3> lo(n, glm::uvec3(0xFFFFFFFFu)), hi(n, glm::uvec3(0u));
    std::vector<glm::uvec3> nlo(n, glm::uvec3(1023u)), nhi(n, glm::uvec3(0u));
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const float d = depth[size_t(y) * width + x];
            const glm::vec4 stored = normal[size_t(y) * width + x];
            if (!gpu::hasSurface(d) || stored.w < 0.0f) continue; // no surface, or not a receiver
            const glm::vec3 p = gpu::worldFromPixel(x, y, d, frame.invViewProj, frame.size);
            const glm::vec3 u = gpu::clusterUnitNormal(glm::vec3(stored));
            const uint32_t s = sliceOf(gpu::linearDepth(d, frame.depth), sliceFar, slices);
            const size_t c = (size_t(y / ML_TILE_SIZE) * tilesX + x / ML_TILE_SIZE) * slices + s;
            for (int i = 0; i < 3; ++i) {
                lo[c][i] = std::min(lo[c][i], toKey(p[i]));
                hi[c][i] = std::max(hi[c][i], toKey(p[i]));
                nlo[c][i] = std::min(nlo[c][i], gpu::clusterNormalCode(u[i], false));
                nhi[c][i] = std::max(nhi[c][i], gpu::clusterNormalCode(u[i], true));
            }
        }
    std::vector<gpu::ClusterReceivers> out(n, gpu::ClusterReceivers{});
    for (size_t c = 0; c < n; ++c) {
        if (lo[c].x == 0xFFFFFFFFu) continue; // no receiver: all zero
        out[c].lo = glm::vec3(fromKey(lo[c].x), fromKey(lo[c].y), fromKey(lo[c].z));
        out[c].hi = glm::vec3(fromKey(hi[c].x), fromKey(hi[c].y), fromKey(hi[c].z));
        out[c].normalLo = nlo[c].x | (nlo[c].y << 10) | (nlo[c].z << 20);
        out[c].normalHi = nhi[c].x | (nhi[c].y << 10) | (nhi[c].z << 20) | ML_CLUSTER_HAS_RECEIVER;
    }
    return out;
}

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
            if (!gpu::hasSurface(d)) continue;
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
        if (frame.cluster.w == ML_CULL_CLUSTERED) continue; // lists below, per light
        for (uint32_t l = 0; l < frame.cluster.z; ++l)
            if (gpu::lightTouchesBox(lights[l], l3, h3)) ref.lists[c].push_back(l);
    }
    if (frame.cluster.w == ML_CULL_CLUSTERED) {
        // Per light, in index order (so lists come out sorted): the occupied clusters of its footprint.
        for (uint32_t l = 0; l < frame.cluster.z; ++l) {
            gpu::LightFootprint f =
                gpu::lightFootprint(lights[l], frame.viewProj, frame.size, frame.cluster.y, frame.depth.x);
            if (f.tiles.x > f.tiles.z || f.tiles.y > f.tiles.w) continue;
            uint32_t s0 = sliceOf(f.depth.x, sliceFar, slices), s1 = sliceOf(f.depth.y, sliceFar, slices);
            for (uint32_t ty = f.tiles.y; ty <= f.tiles.w; ++ty)
                for (uint32_t tx = f.tiles.x; tx <= f.tiles.z; ++tx)
                    for (uint32_t s = s0; s <= s1; ++s) {
                        size_t c = (size_t(ty) * tilesX + tx) * slices + s;
                        const auto& b = ref.bounds[c];
                        if (occupied[c] && gpu::lightTouchesBox(lights[l], glm::vec3(b.lo), glm::vec3(b.hi)))
                            ref.lists[c].push_back(l);
                    }
        }
    }
    return ref;
}

} // namespace ml
