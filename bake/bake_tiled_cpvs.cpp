// Tiled CPVS bakes and verifies of one record (see bake_tiled_cpvs.h).
#include "bake/bake_tiled_cpvs.h"

#include "shadows/static/cpvs_tiled.h"
#include "shadows/static/mh.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

namespace ml {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}
} // namespace

Result<std::vector<uint32_t>> bakeCpvsRecordTiled(const CasterTriangles& casters, const LightFrustum& frustum,
                                                  uint32_t res, const TiledBakeOptions& options,
                                                  LightBakeStats& stats) {
    const DualRasterizer raster(casters, frustum, res);
    CpvsParams p;
    p.resolution = res, p.nearPlane = frustum.nearPlane, p.farPlane = frustum.farPlane;
    // Directional (orthographic) maps: equal slices over the box's slab; others eq. 1 (as encodeStatic).
    p.slicing = frustum.orthographic() ? CpvsSlicing::Linear : CpvsSlicing::Log;
    CpvsTiledOptions o;
    o.tile = options.tile, o.progress = options.progress;
    o.maxLiveBytes = options.maxNodes * 2 * sizeof(MhTree::Node);
    o.emptyBlock = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
        return raster.blockEmpty(x0, y0, w, h);
    };
    DualTileSource source = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* enter,
                                      uint32_t* exit, uint32_t* plane) -> Result<void> {
        raster.renderRect(x0, y0, w, h, enter, exit, plane);
        return {};
    };
    CpvsTiledStats ts;
    const auto t0 = Clock::now();
    auto bake = bakeCpvsTiled(source, p, o, &ts);
    if (!bake) return fail(bake.error());
    // Rendering, insertion and merging interleave per region: all of it is "render", the layout "encode".
    stats.encodeSeconds = bake->stats.layoutMs / 1000.0;
    stats.renderSeconds = secondsSince(t0) - stats.encodeSeconds;
    stats.coveredTexels = ts.coveredTexels, stats.closedTexels = ts.closedTexels;
    stats.tiles = ts.regions, stats.emptyTiles = ts.emptyRegions;
    stats.treeNodes = bake->stats.nodesFinal + bake->stats.leavesFinal;
    stats.cpvsSteps = bake->stats.tileSteps, stats.dagLiveBytes = bake->stats.liveBytesPeak;
    stats.regionNodesPeak = bake->stats.regionNodesPeak,
    stats.regionLeavesPeak = bake->stats.regionLeavesPeak;
    return std::move(bake->data);
}

Result<void> verifyCpvsRecordTiled(const BakeRecord& rec, const CasterTriangles& casters, uint32_t tile,
                                   const std::function<void(double)>& progress, VerifyLight& out,
                                   std::vector<std::string>& examples, size_t maxExamples) {
    if (rec.method != StaticMethod::CPVS) return fail("tiled CPVS verify of a record of another method");
    if (tile == 0 || (tile & (tile - 1)) != 0)
        return fail("tile side " + std::to_string(tile) + " is not a power of two");
    const uint32_t* d = rec.data.data();
    if (auto v = validateCpvs(d, rec.data.size()); !v) return fail(v.error());
    auto space = cpvsSpaceOf(d);
    if (!space) return fail(space.error());
    const uint32_t res = rec.resolution, T = std::min(tile, res), m = (res + T - 1) / T, count = m * m;
    if (space->resolution != res)
        return fail("CPVS resolution " + std::to_string(space->resolution) + " differs from the record's " +
                    std::to_string(res));
    const DualRasterizer raster(casters, rec.frustum, res);
    CpvsVerifyReport total;
    total.mismatches = cpvsThresholdMismatches(d, *space);
    if (total.mismatches && examples.size() < maxExamples)
        examples.push_back("light " + std::to_string(rec.light) + ": " + std::to_string(total.mismatches) +
                           " slice thresholds differ from the header's voxel space");
    std::atomic<uint32_t> next{0}, done{0};
    std::mutex mutex; // guards the sums, the examples and progress
    const auto t0 = Clock::now();
    auto worker = [&]() {
        std::vector<uint32_t> enter(size_t(T) * T), exit(size_t(T) * T);
        CpvsVerifyReport mine;
        for (uint32_t k; (k = next++) < count;) {
            const uint32_t x0 = (k % m) * T, y0 = (k / m) * T, w = std::min(T, res - x0),
                           h = std::min(T, res - y0);
            if (raster.blockEmpty(x0, y0, w, h))
                std::fill(enter.begin(), enter.end(), kDepthEmpty),
                    std::fill(exit.begin(), exit.end(), kDepthEmpty);
            else
                raster.renderRect(x0, y0, w, h, enter.data(), exit.data());
            const uint64_t before = mine.mismatches;
            verifyCpvsBlock(d, *space, x0, y0, w, h, enter.data(), exit.data(), mine);
            const uint32_t finished = ++done;
            std::lock_guard<std::mutex> lock(mutex);
            if (mine.mismatches > before && examples.size() < maxExamples)
                examples.push_back("light " + std::to_string(rec.light) + ": " +
                                   std::to_string(mine.mismatches - before) +
                                   " voxels disagree in the tile at (" + std::to_string(x0) + ", " +
                                   std::to_string(y0) + ")");
            if (progress) progress(double(finished) / count);
        }
        std::lock_guard<std::mutex> lock(mutex);
        total.checked += mine.checked, total.undefined += mine.undefined, total.mismatches += mine.mismatches;
    };
    const uint32_t threads = std::min(std::max(1u, std::thread::hardware_concurrency()), count);
    std::vector<std::thread> pool;
    for (uint32_t i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& th : pool) th.join();
    out.checked = total.checked, out.undefined = total.undefined, out.mismatches = total.mismatches;
    out.renderSeconds = 0, out.checkSeconds = secondsSince(t0); // rendering and checking overlap per tile
    return {};
}

} // namespace ml
