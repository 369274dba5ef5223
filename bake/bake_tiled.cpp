// Tiled bakes and verifies of one record (see bake_tiled.h).
#include "bake/bake_tiled.h"

#include "bake/bake_tiled_cpvs.h"

#include "shadows/static/mh_tiled.h"
#include "shadows/static/sm.h"

#include <sys/resource.h>

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

uint64_t tiledWorkingBytes(uint32_t tile) {
    const uint64_t threads = std::max(1u, std::thread::hardware_concurrency());
    return threads * uint64_t(tile) * tile * (30 + 68); // the tile, and the rasteriser's hit slots
}

uint64_t peakResidentBytes() {
    struct rusage u {};
    if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
    return uint64_t(u.ru_maxrss) * 1024u; // Linux reports KiB
}

namespace {

// SM in tiles: each tile's midpoints go straight to their place in the output words, so a bake holds the
// output (4 B a texel: 256 MiB at 8192^2) and a tile per thread, never the dual map (8 B a texel more).
// The words are encodeSM's of the whole map: the same header (smBlankWords), the same rows (a fitted
// directional map stores mapRows(res) rows; no tile past them is rendered) and the same values.
Result<std::vector<uint32_t>> bakeSmRecordTiled(const CasterTriangles& casters, const LightFrustum& frustum,
                                                uint32_t res, const TiledBakeOptions& options,
                                                LightBakeStats& stats) {
    if (res > kBakeWholeMapMax) return fail(smPastLimitReason(res));
    const uint32_t tile = options.tile;
    if (tile == 0 || (tile & (tile - 1)) != 0)
        return fail("tile side " + std::to_string(tile) + " is not a power of two");
    const DualRasterizer raster(casters, frustum, res);
    std::vector<uint32_t> out = smBlankWords(res, frustum.mapRows(res));
    const uint32_t rows = smStoredRows(res, frustum.mapRows(res)), T = std::min(tile, res);
    const uint32_t mx = (res + T - 1) / T, my = (rows + T - 1) / T, count = mx * my;
    uint32_t* values = out.data() + smfmt::kHeaderWords;
    std::atomic<uint32_t> next{0}, done{0};
    std::mutex mutex; // guards the sums and progress
    const auto t0 = Clock::now();
    auto worker = [&]() {
        std::vector<uint32_t> enter(size_t(T) * T), exit(size_t(T) * T);
        uint64_t covered = 0, closed = 0;
        uint32_t empty = 0;
        for (uint32_t k; (k = next++) < count;) {
            const uint32_t x0 = (k % mx) * T, y0 = (k / mx) * T, w = std::min(T, res - x0),
                           h = std::min(T, rows - y0);
            if (raster.blockEmpty(x0, y0, w, h)) {
                ++empty;
                for (uint32_t y = 0; y < h; ++y)
                    std::fill_n(values + size_t(y0 + y) * res + x0, w, smValue(kDepthEmpty, kDepthEmpty));
            } else {
                raster.renderRect(x0, y0, w, h, enter.data(), exit.data());
                for (uint32_t y = 0; y < h; ++y) {
                    uint32_t* row = values + size_t(y0 + y) * res + x0;
                    for (uint32_t x = 0; x < w; ++x) {
                        const size_t i = size_t(y) * w + x;
                        row[x] = smValue(enter[i], exit[i]);
                        covered += enter[i] != kDepthEmpty, closed += exit[i] > enter[i];
                    }
                }
            }
            const uint32_t finished = ++done;
            if (options.progress) {
                std::lock_guard<std::mutex> lock(mutex);
                options.progress(double(finished) / count);
            }
        }
        std::lock_guard<std::mutex> lock(mutex);
        stats.coveredTexels += covered, stats.closedTexels += closed, stats.emptyTiles += empty;
    };
    const uint32_t threads = std::min(std::max(1u, std::thread::hardware_concurrency()), count);
    std::vector<std::thread> pool;
    for (uint32_t i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& th : pool) th.join();
    smSeal(out);
    stats.tiles = count, stats.renderSeconds = secondsSince(t0); // rendering and encoding interleave
    stats.encodeSeconds = 0;
    return out;
}

} // namespace

Result<std::vector<uint32_t>> bakeRecordTiled(StaticMethod method, const CasterTriangles& casters,
                                              const LightFrustum& frustum, uint32_t res,
                                              const TiledBakeOptions& options, LightBakeStats& stats) {
    if (method == StaticMethod::CPVS) return bakeCpvsRecordTiled(casters, frustum, res, options, stats);
    if (method == StaticMethod::SM) return bakeSmRecordTiled(casters, frustum, res, options, stats);
    if (method != StaticMethod::MH && method != StaticMethod::MMH && method != StaticMethod::DAGMH)
        return fail(std::string("tiled bakes build the MH family, SM and CPVS, not ") +
                    staticMethodName(method));
    const DualRasterizer raster(casters, frustum, res);
    MhTiledOptions to;
    to.tile = options.tile, to.maxNodes = options.maxNodes, to.progress = options.progress;
    if (method == StaticMethod::DAGMH) to.planes = raster.planes(); // a planar tree (mh.h)
    to.emptyBlock = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) {
        return raster.blockEmpty(x0, y0, w, h);
    };
    DualTileSource source = [&raster](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* enter,
                                      uint32_t* exit, uint32_t* plane) -> Result<void> {
        raster.renderRect(x0, y0, w, h, enter, exit, plane);
        return {};
    };
    MhTiledStats ts;
    const auto t0 = Clock::now();
    auto tree = buildMhTreeTiled(res, source, to, &ts);
    if (!tree) return fail(tree.error());
    stats.renderSeconds = secondsSince(t0); // rendering and reduction overlap in the tile workers
    stats.coveredTexels = ts.coveredTexels, stats.closedTexels = ts.closedTexels;
    stats.tiles = ts.tiles, stats.emptyTiles = ts.emptyTiles, stats.treeNodes = ts.nodes;
    const auto te = Clock::now();
    Result<std::vector<uint32_t>> words = method == StaticMethod::MH    ? encodeMH(*tree)
                                          : method == StaticMethod::MMH ? encodeMMH(*tree)
                                                                        : encodeDAGMH(*tree);
    stats.encodeSeconds = secondsSince(te);
    return words;
}

Result<void> verifyRecordTiled(const BakeRecord& rec, const CasterTriangles& casters, uint32_t tile,
                               const std::function<void(double)>& progress, VerifyLight& out,
                               std::vector<std::string>& examples, size_t maxExamples) {
    if (!isDepthMethod(rec.method)) return fail("tiled verify checks depth methods only");
    if (tile == 0 || (tile & (tile - 1)) != 0)
        return fail("tile side " + std::to_string(tile) + " is not a power of two");
    const uint32_t res = rec.resolution, T = std::min(tile, res), m = (res + T - 1) / T, count = m * m;
    const DualRasterizer raster(casters, rec.frustum, res);
    const uint32_t* d = rec.data.data();
    std::atomic<uint32_t> next{0}, done{0};
    std::mutex mutex; // guards the sums, the examples and progress
    uint64_t mismatches = 0;
    uint32_t lo = kDepthEmpty, hi = 0; // entered depths, for the fitted map's caster slices
    const auto t0 = Clock::now();
    auto worker = [&]() {
        std::vector<uint32_t> enter(size_t(T) * T), exit(size_t(T) * T);
        uint64_t bad = 0;
        uint32_t l = kDepthEmpty, h = 0;
        for (uint32_t k; (k = next++) < count;) {
            const uint32_t x0 = (k % m) * T, y0 = (k / m) * T, w = std::min(T, res - x0),
                           hh = std::min(T, res - y0);
            raster.renderRect(x0, y0, w, hh, enter.data(), exit.data());
            for (uint32_t y = 0; y < hh; ++y)
                for (uint32_t x = 0; x < w; ++x) {
                    const size_t i = size_t(y) * w + x;
                    const uint32_t e = enter[i], f = std::max(e, exit[i]);
                    if (e != kDepthEmpty) l = std::min(l, e), h = std::max(h, e);
                    const uint32_t v = lookupStaticDepth(rec.method, d, 0, x0 + x, y0 + y);
                    const bool ok = e == kDepthEmpty ? v == kDepthEmpty : (e <= v && v <= f);
                    if (ok) continue;
                    ++bad;
                    std::lock_guard<std::mutex> lock(mutex);
                    if (examples.size() < maxExamples)
                        examples.push_back("light " + std::to_string(rec.light) + ": texel (" +
                                           std::to_string(x0 + x) + ", " + std::to_string(y0 + y) +
                                           ") decodes " + std::to_string(v) + " outside [" +
                                           std::to_string(e) + ", " + std::to_string(f) + "]");
                }
            const uint32_t finished = ++done;
            if (progress) {
                std::lock_guard<std::mutex> lock(mutex);
                progress(double(finished) / count);
            }
        }
        std::lock_guard<std::mutex> lock(mutex);
        mismatches += bad, lo = std::min(lo, l), hi = std::max(hi, h);
    };
    const uint32_t threads = std::min(std::max(1u, std::thread::hardware_concurrency()), count);
    std::vector<std::thread> pool;
    for (uint32_t i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& th : pool) th.join();
    out.checked = uint64_t(res) * res, out.mismatches = mismatches;
    out.renderSeconds = 0, out.checkSeconds = secondsSince(t0); // rendering and checking overlap per tile
    if (rec.frustum.fitted()) {
        const double nz = rec.frustum.nearPlane, fz = rec.frustum.farPlane, n = res;
        auto slice = [&](uint32_t q) {
            return std::clamp(std::floor((dequantizeDepth(q, rec.frustum.farPlane) - nz) / (fz - nz) * n),
                              0.0, n - 1);
        };
        out.casterSlices = lo <= hi ? (slice(hi) - slice(lo) + 1) / n : 0.0;
    }
    return {};
}

} // namespace ml
