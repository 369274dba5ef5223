// Tiled CPVS construction (see cpvs_tiled.h for why it equals the whole-map bake).
#include "shadows/static/cpvs_tiled.h"

#include "shadows/static/cpvs_internal.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>

namespace ml {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}
} // namespace

Result<CpvsBake> bakeCpvsTiled(const DualTileSource& source, const CpvsParams& params,
                               const CpvsTiledOptions& options, CpvsTiledStats* stats) {
    using namespace cpvs_detail;
    if (!source) return fail("cpvs: tiled bake without a tile source");
    auto space = makeCpvsSpace(params.resolution, params.nearPlane, params.farPlane, params.slicing);
    if (!space) return fail(space.error());
    if (options.tile < 8 || !std::has_single_bit(options.tile))
        return fail("cpvs: tile side " + std::to_string(options.tile) +
                    " is not a power of two >= 8, so it does not divide the map into whole 8x8 tiles");
    const uint32_t n = space->resolution, lg = space->log2Resolution;
    const uint32_t gridLog2 = std::min(params.gridLog2, lg - 3), cellLog2 = lg - gridLog2;
    const uint32_t tile = std::min(options.tile, n), cell = 1u << cellLog2;
    // A region is a whole number of grid cells (insertion needs a cell's footprints) and of tiles.
    const uint32_t side = std::max(tile, cell), regionLog2 = lg - uint32_t(std::countr_zero(side));
    uint32_t threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    // Strip height: at most max(tile^2, 8 R) texels a strip, and at least one strip per worker.
    uint32_t stripRows = uint32_t(std::clamp<uint64_t>(uint64_t(tile) * tile / side, 8, side));
    stripRows = std::min(stripRows, std::max(8u, std::bit_floor(side / threads)));
    const uint32_t strips = side / stripRows;
    threads = std::max(1u, std::min(threads, strips));

    CpvsTiledStats st;
    st.regionSide = side;
    uint64_t steps = 0; // visibility masks over all 8x8 tiles (CpvsStats::tileSteps)
    std::mutex mutex;   // guards st's sums and `error` from the workers
    auto region = [&](const CellBlock& block) -> Result<Dag> {
        const uint32_t x0 = block.x0 << cellLog2, y0 = block.y0 << cellLog2;
        if (options.emptyBlock && options.emptyBlock(x0, y0, side, side)) {
            // Every voxel lit: every grid entry kCpvsLit, no node (what inserting the empty texels gives).
            ++st.emptyRegions;
            Dag d;
            d.levels.resize(cellLog2 - 2);
            d.grid.assign(size_t(block.w) * block.w << gridLog2, kCpvsLit);
            return d;
        }
        std::vector<CpvsPrecompute> parts(strips);
        std::atomic<uint32_t> next{0};
        std::atomic<bool> failed{false};
        std::string error;
        auto worker = [&] {
            std::vector<uint32_t> enter, exit;
            uint64_t covered = 0, closed = 0, empty = 0;
            double seconds = 0;
            for (uint32_t j; !failed && (j = next++) < strips;) {
                const auto tw = Clock::now();
                const uint32_t y = y0 + j * stripRows;
                CpvsPrecompute& part = parts[j];
                part.minT.emplace_back();
                part.maxT.emplace_back();
                if (options.emptyBlock && options.emptyBlock(x0, y, side, stripRows)) {
                    precomputeEmpty(*space, size_t(side / 8) * (stripRows / 8), part);
                    ++empty;
                } else {
                    enter.resize(size_t(side) * stripRows), exit.resize(size_t(side) * stripRows);
                    if (auto r = source(x0, y, side, stripRows, enter.data(), exit.data(), nullptr); !r) {
                        std::lock_guard<std::mutex> lock(mutex);
                        if (!failed)
                            error = "cpvs: strip (" + std::to_string(x0) + ", " + std::to_string(y) +
                                    "): " + r.error();
                        failed = true;
                        break;
                    }
                    for (size_t i = 0; i < enter.size(); ++i)
                        covered += enter[i] != kDepthEmpty, closed += exit[i] > enter[i];
                    precomputeBlock(*space, enter.data(), exit.data(), side, stripRows, side, part);
                }
                seconds += secondsSince(tw);
            }
            std::lock_guard<std::mutex> lock(mutex);
            st.coveredTexels += covered, st.closedTexels += closed, st.emptyStrips += empty;
            st.renderSeconds += seconds;
        };
        std::vector<std::thread> pool;
        for (uint32_t i = 1; i < threads; ++i) pool.emplace_back(worker);
        worker();
        for (std::thread& th : pool) th.join();
        if (failed) return fail(error);
        st.strips += strips;
        CpvsPrecompute pre;
        pre.resolution = side;
        pre.tiles = side / 8;
        pre.minT.emplace_back();
        pre.maxT.emplace_back();
        for (CpvsPrecompute& p : parts) {
            precomputeAppend(pre, p);
            p = CpvsPrecompute{}; // freed as appended
        }
        precomputeFinish(pre, cell);
        steps += pre.stepStart.size();
        CellBlock local = block; // the region's own precompute: cells from (0, 0)
        local.x0 = local.y0 = 0;
        return insertBlock(pre, lg, gridLog2, local);
    };

    CpvsBake bake;
    CpvsStats& cs = bake.stats;
    RegionStats rs;
    auto dag = mergeRegions(
        lg, gridLog2, regionLog2, rs,
        [&](float f) {
            if (options.progress) options.progress(double(f));
        },
        region, options.maxLiveBytes);
    if (!dag) return fail(dag.error());
    auto tl = Clock::now();
    auto words = writeLayout(*space, dag.value());
    if (!words) return fail(words.error());
    bake.data = std::move(words.value());
    cs.layoutMs = 1000.0 * secondsSince(tl);
    st.regions = rs.regions;
    cs.tileSteps = steps;
    cs.nodesInserted = rs.nodesInserted, cs.leavesInserted = rs.leavesInserted;
    cs.regions = rs.regions, cs.regionNodesPeak = rs.regionNodesPeak,
    cs.regionLeavesPeak = rs.regionLeavesPeak;
    cs.liveBytesPeak = rs.liveBytesPeak;
    // Rendering and the precompute run inside the region source: the insert time less the render share.
    cs.precomputeMs = 1000.0 * st.renderSeconds / threads;
    cs.insertMs = std::max(0.0, rs.insertMs - cs.precomputeMs);
    cs.compressMs = rs.compressMs + rs.mergeMs, cs.mergeMs = rs.mergeMs;
    cs.leavesFinal = dag->leaves.size();
    for (const auto& l : dag->levels) cs.nodesFinal += l.size(), cs.nodesPerLevel.push_back(l.size());
    cs.bytes = cpvsBytes(bake.data.data());
    if (stats) *stats = st;
    return bake;
}

} // namespace ml
