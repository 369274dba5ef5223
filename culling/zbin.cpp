#include "culling/zbin.h"

#include "culling/culling.h"
#include "culling/zbin_bindings.h"
#include "gpu/bindings.h"
#include "shaders/shared/light_math.h"

#include "zbin_bins.comp.spv.h"
#include "zbin_mask.comp.spv.h"
#include "zbin_shade.comp.spv.h"
#include "zbin_stats.comp.spv.h"

#include <algorithm>
#include <bit>
#include <cstring>

namespace ml {

namespace {
constexpr auto kC = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr auto kR = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr auto kW = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;

// Bits [a, b] of the 64-bit slice mask (as the footprint pass's sliceMask).
glm::uvec2 sliceBits(uint32_t a, uint32_t b) {
    uint64_t m = 0;
    for (uint32_t s = a; s <= b && s < 64; ++s) m |= uint64_t(1) << s;
    return glm::uvec2(uint32_t(m), uint32_t(m >> 32));
}
} // namespace

static_assert(ML_ZBIN_BINS <= 0x10000 && ML_MAX_LIGHTS <= 0x10000, "bins pack 16-bit indices");
static_assert(ML_ZBIN_WORDS * 32 == ML_MAX_LIGHTS);
static_assert(ML_ZBIN_GROUP % ML_ZBIN_LANES == 0 && ML_ZBIN_GROUP % 8 == 0);

ZBinFrame zbinPrepare(const gpu::FrameConstants& frame, const std::vector<float>& sliceFar,
                      const std::vector<gpu::GpuLight>& lights, bool depthTest) {
    ZBinFrame zf;
    struct Entry {
        float mid, nearZ, farZ;
        gpu::uvec4 tiles;
        uint32_t light;
    };
    std::vector<Entry> entries;
    const uint32_t visible = std::min<uint32_t>(frame.cluster.z, uint32_t(lights.size()));
    for (uint32_t l = 0; l < visible; ++l) {
        const gpu::LightFootprint f =
            gpu::lightFootprint(lights[l], frame.viewProj, frame.size, frame.cluster.y, frame.depth.x);
        if (f.tiles.x > f.tiles.z || f.tiles.y > f.tiles.w) continue; // reaches no pixel
        if (lights[l].info.x == ML_LIGHT_DIRECTIONAL) {
            zf.wide.push_back(l);
            continue;
        }
        const float farZ = std::min(f.depth.y, frame.depth.y); // no pixel lies past the far plane
        entries.push_back({0.5f * (f.depth.x + farZ), f.depth.x, farZ, f.tiles, l});
    }
    // Drobot's order: by view depth (the middle of the range), ties by index so the order is unique.
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        return a.mid < b.mid || (a.mid == b.mid && a.light < b.light);
    });
    float zMax = frame.depth.x;
    for (const Entry& e : entries) zMax = std::max(zMax, e.farZ);
    if (!(zMax > frame.depth.x * 1.001f)) zMax = frame.depth.x + 1.0f; // no light: any span
    gpu::ZBinPush& p = zf.push;
    p.sorted = uint32_t(entries.size());
    p.words = (p.sorted + 31) / 32;
    p.wide = uint32_t(zf.wide.size());
    p.depthTest = depthTest ? 1u : 0u;
    p.binNear = frame.depth.x;
    p.binScale = float(ML_ZBIN_BINS) / (zMax - frame.depth.x);
    p.bins = ML_ZBIN_BINS;
    const uint32_t slices = std::max(1u, frame.cluster.x);
    for (const Entry& e : entries) {
        gpu::ZBinLight z{};
        z.tiles = e.tiles;
        z.sliceMask = sliceBits(sliceOf(e.nearZ, sliceFar, slices), sliceOf(e.farZ, sliceFar, slices));
        z.bins = gpu::zbinOf(e.nearZ, p.binNear, p.binScale, p.bins) |
                 (gpu::zbinOf(e.farZ, p.binNear, p.binScale, p.bins) << 16);
        z.light = e.light;
        zf.sorted.push_back(z);
    }
    return zf;
}

ZBinReference zbinReference(const ZBinFrame& zf, const gpu::FrameConstants& frame,
                            const std::vector<glm::uvec2>& tileSlices) {
    ZBinReference ref;
    const gpu::ZBinPush& p = zf.push;
    const uint32_t tilesX = frame.size.z, tilesY = frame.size.w;
    ref.masks.assign(size_t(tilesX) * tilesY * p.words, 0u);
    for (uint32_t i = 0; i < p.sorted; ++i) {
        const gpu::ZBinLight& L = zf.sorted[i];
        for (uint32_t ty = L.tiles.y; ty <= L.tiles.w; ++ty)
            for (uint32_t tx = L.tiles.x; tx <= L.tiles.z; ++tx) {
                const uint32_t t = ty * tilesX + tx;
                if (p.depthTest &&
                    ((tileSlices[t].x & L.sliceMask.x) | (tileSlices[t].y & L.sliceMask.y)) == 0)
                    continue;
                ref.masks[size_t(t) * p.words + i / 32] |= 1u << (i % 32);
            }
    }
    ref.bins.assign(p.bins, ML_ZBIN_EMPTY);
    for (uint32_t b = 0; b < p.bins; ++b) {
        uint32_t lo = 0xFFFF, hi = 0;
        for (uint32_t i = 0; i < p.sorted; ++i) {
            const uint32_t r = zf.sorted[i].bins;
            if ((r & 0xFFFF) <= b && b <= (r >> 16)) {
                lo = std::min(lo, i);
                hi = i;
            }
        }
        ref.bins[b] = lo | (hi << 16);
    }
    return ref;
}

ZBinStats zbinStatsReference(const ZBinFrame& zf, const ZBinReference& ref, const std::vector<float>& depth,
                             const gpu::FrameConstants& frame, const std::vector<gpu::GpuLight>& lights) {
    ZBinStats s;
    const gpu::ZBinPush& p = zf.push;
    for (uint32_t y = 0; y < frame.size.y; ++y)
        for (uint32_t x = 0; x < frame.size.x; ++x) {
            const float d = depth[size_t(y) * frame.size.x + x];
            if (!gpu::hasSurface(d)) continue;
            const glm::vec3 P = gpu::worldFromPixel(x, y, d, frame.invViewProj, frame.size);
            const uint32_t bin = gpu::zbinOf(gpu::linearDepth(d, frame.depth), p.binNear, p.binScale, p.bins);
            const uint32_t range = ref.bins[bin];
            const uint32_t lo = range & 0xFFFF, hi = range >> 16;
            const size_t tile = size_t(y / frame.cluster.y) * frame.size.z + x / frame.cluster.y;
            ++s.surface;
            s.evaluated += p.wide;
            s.tile += p.wide;
            s.exact += p.wide;
            for (uint32_t w = 0; w < p.words; ++w)
                s.tile += uint64_t(std::popcount(ref.masks[tile * p.words + w]));
            for (uint32_t l : zf.wide) s.reaching += gpu::lightReachesPoint(lights[l], P);
            for (uint32_t i = lo; i <= hi && lo <= hi; ++i)
                if (ref.masks[tile * p.words + i / 32] >> (i % 32) & 1u) {
                    ++s.evaluated;
                    const uint32_t r = zf.sorted[i].bins;
                    s.exact += (r & 0xFFFF) <= bin && bin <= (r >> 16);
                    s.reaching += gpu::lightReachesPoint(lights[zf.sorted[i].light], P);
                }
        }
    return s;
}

Result<void> ZBinning::create(const Device& device) {
    ML_TRY(ML_LOAD_SHADER(device, maskShader_, spv_zbin_mask_comp));
    ML_TRY(ML_LOAD_SHADER(device, binShader_, spv_zbin_bins_comp));
    ML_TRY(ML_LOAD_SHADER(device, statsShader_, spv_zbin_stats_comp));
    ML_TRY(createComputeProgram(device, maskProgram_, maskShader_));
    ML_TRY(createComputeProgram(device, binProgram_, binShader_));
    ML_TRY(createComputeProgram(device, statsProgram_, statsShader_));
    ML_TRY(ML_LOAD_SHADER(device, shadeShader_, spv_zbin_shade_comp));
    for (uint32_t z = 0; z < 2; ++z)
        ML_TRY(createComputeProgram(device, shadePrograms_[z], shadeShader_, {{0, z}}));
    static_assert(sizeof(ZBinStats) == 5 * sizeof(uint64_t));
    ML_TRY(createBuffer(device, statsBuffer, sizeof(ZBinStats), kStorageBufferUsage, "zbin_stats",
                        MemoryRole::Readback));
    return createBuffer(device, frame, sizeof(gpu::FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                        "zbin_frame");
}

void ZBinning::destroy(const Device& device) {
    for (Program* p : {&maskProgram_, &binProgram_, &statsProgram_, &shadePrograms_[0], &shadePrograms_[1]})
        destroyProgram(device, *p);
    for (ShaderModule* s : {&maskShader_, &binShader_, &statsShader_, &shadeShader_})
        destroyShader(device, *s);
    for (Buffer* b : {&sorted, &wide, &frame, &lights, &slices, &masks, &bins, &statsBuffer, &shaded})
        destroyBuffer(device, *b);
}

Result<void> ZBinning::prepare(const Device& device, const ZBinFrame& zf, const gpu::FrameConstants& fc,
                               const std::vector<gpu::GpuLight>& visible) {
    push = zf.push;
    tiles = fc.size.z * fc.size.w;
    // Sized for the worst case (ML_MAX_LIGHTS lights: ML_ZBIN_WORDS words per tile) so the buffers are
    // made once per size; at least one element each (empty frames still bind valid buffers).
    ML_TRY(ensureBuffer(device, sorted, sizeof(gpu::ZBinLight) * ML_MAX_LIGHTS, kStorageBufferUsage,
                        "zbin_sorted"));
    ML_TRY(ensureBuffer(device, wide, 4 * ML_MAX_LIGHTS, kStorageBufferUsage, "zbin_wide"));
    ML_TRY(ensureBuffer(device, lights, sizeof(gpu::GpuLight) * ML_MAX_LIGHTS, kStorageBufferUsage,
                        "zbin_lights"));
    ML_TRY(ensureBuffer(device, masks, VkDeviceSize(tiles) * ML_ZBIN_WORDS * 4, kStorageBufferUsage,
                        "zbin_masks", MemoryRole::GpuOnly));
    ML_TRY(ensureBuffer(device, shaded, VkDeviceSize(fc.size.x) * fc.size.y * 16, kStorageBufferUsage,
                        "zbin_shaded", MemoryRole::GpuOnly));
    ML_TRY(
        ensureBuffer(device, bins, ML_ZBIN_BINS * 4, kStorageBufferUsage, "zbin_bins", MemoryRole::GpuOnly));
    upload(sorted, zf.sorted.data(), zf.sorted.size() * sizeof(gpu::ZBinLight));
    upload(wide, zf.wide.data(), zf.wide.size() * 4);
    upload(lights, visible.data(), std::min<size_t>(visible.size(), ML_MAX_LIGHTS) * sizeof(gpu::GpuLight));
    upload(frame, &fc, sizeof(fc));
    return {};
}

void ZBinning::recordMasks(const Device& device, VkCommandBuffer c, const Buffer& tileSlices) {
    // The frame's cluster_bounds (tile slices) and earlier Z-bin readers -> this pass's clear and writes.
    memoryBarrier(c, kC, kW | kR, kFillStages | kC, VK_ACCESS_2_TRANSFER_WRITE_BIT | kR);
    if (push.words) vkCmdFillBuffer(c, masks.buffer, 0, VkDeviceSize(tiles) * push.words * 4, 0);
    memoryBarrier(c, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, kC, kR | kW); // cleared -> atomicOr
    dispatch(device, c, maskProgram_, push.sorted * ML_ZBIN_LANES, 1, push,
             {ML_BIND(ML_ZBIN_MASK_SORTED, sorted), ML_BIND(ML_ZBIN_MASK_TILE_SLICES, tileSlices),
              ML_BIND(ML_ZBIN_MASK_MASKS, masks), ML_BIND(ML_ZBIN_MASK_FRAME, frame)});
    memoryBarrier(c, kC, kW, kC, kR); // masks -> stats (and any later reader)
}

void ZBinning::recordBins(const Device& device, VkCommandBuffer c) {
    memoryBarrier(c, kC, kR, kC, kW); // an earlier stats pass's reads -> this pass's writes
    dispatch(device, c, binProgram_, push.bins, 1, push,
             {ML_BIND(ML_ZBIN_BINS_SORTED, sorted), ML_BIND(ML_ZBIN_BINS_OUT, bins)});
    memoryBarrier(c, kC, kW, kC, kR); // bins -> stats
}

void ZBinning::recordStats(const Device& device, VkCommandBuffer c, VkImageView depth) {
    vkCmdFillBuffer(c, statsBuffer.buffer, 0, VK_WHOLE_SIZE, 0);
    memoryBarrier(c, kFillStages, VK_ACCESS_2_TRANSFER_WRITE_BIT, kC, kR | kW);
    const gpu::FrameConstants& fc = *frame.as<gpu::FrameConstants>();
    const auto layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    dispatch(device, c, statsProgram_, fc.size.x, fc.size.y, push,
             {ML_BIND(ML_ZBIN_STATS_FRAME, frame), ML_BIND(ML_ZBIN_STATS_LIGHTS, lights),
              ML_BIND(ML_ZBIN_STATS_SORTED, sorted), ML_BIND(ML_ZBIN_STATS_MASKS, masks),
              ML_BIND(ML_ZBIN_STATS_BINS, bins),
              ML_BIND(ML_ZBIN_STATS_DEPTH, Descriptor(Image{.view = depth}, layout)),
              ML_BIND(ML_ZBIN_STATS_OUT, statsBuffer), ML_BIND(ML_ZBIN_STATS_WIDE, wide)});
    // Sums -> the host (mapped readback, after the submission's wait).
    memoryBarrier(c, kC, kW, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

Result<void> ZBinning::prepareSlices(const Device& device, const std::vector<float>& sliceFar) {
    ML_TRY(ensureBuffer(device, slices, 4 * ML_MAX_SLICES, kStorageBufferUsage, "zbin_slices"));
    upload(slices, sliceFar.data(), std::min<size_t>(sliceFar.size(), ML_MAX_SLICES) * 4);
    return {};
}

void ZBinning::recordShade(const Device& device, VkCommandBuffer c, bool zbin, VkImageView depth,
                           VkImageView normal, const Buffer& ranges, const Buffer& pool) {
    const gpu::FrameConstants& fc = *frame.as<gpu::FrameConstants>();
    const auto layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    memoryBarrier(c, kC, kW | kR, kC, kW); // an earlier probe's output -> this one's
    dispatch(device, c, shadePrograms_[zbin ? 1 : 0], fc.size.x, fc.size.y, push,
             {ML_BIND(ML_ZBIN_SHADE_FRAME, frame), ML_BIND(ML_ZBIN_SHADE_SLICES, slices),
              ML_BIND(ML_ZBIN_SHADE_LIGHTS, lights), ML_BIND(ML_ZBIN_SHADE_RANGES, ranges),
              ML_BIND(ML_ZBIN_SHADE_POOL, pool), ML_BIND(ML_ZBIN_SHADE_SORTED, sorted),
              ML_BIND(ML_ZBIN_SHADE_MASKS, masks), ML_BIND(ML_ZBIN_SHADE_BINS, bins),
              ML_BIND(ML_ZBIN_SHADE_WIDE, wide),
              ML_BIND(ML_ZBIN_SHADE_DEPTH, Descriptor(Image{.view = depth}, layout)),
              ML_BIND(ML_ZBIN_SHADE_NORMAL, Descriptor(Image{.view = normal}, layout)),
              ML_BIND(ML_ZBIN_SHADE_OUT, shaded)});
    memoryBarrier(c, kC, kW, kC, kR); // output -> readers (tests copy it: readBuffer orders its own copy)
}

ZBinStats ZBinning::stats() const {
    ZBinStats s;
    std::memcpy(&s, statsBuffer.data, sizeof s);
    return s;
}

} // namespace ml
