// The bake's peak memory estimate (see bake_estimate.h for each term's reason and size).
#include "bake/bake_estimate.h"

#include "bake/bake_tiled.h"
#include "shadows/static/mh_tiled.h"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <thread>

namespace ml {

namespace {

constexpr uint64_t kMiB = uint64_t(1) << 20;
constexpr uint64_t kCpvsNodeBytes = 36; // CpvsOctree::Node: two masks and 8 child indices

uint32_t hardwareThreads() {
    return std::max(1u, std::thread::hardware_concurrency());
}

// One tiled CPVS map of side n: what is held beside the base while it is built (bake_estimate.h).
uint64_t cpvsTiledMapBytes(uint32_t n, uint32_t tile, uint32_t threads) {
    const uint32_t lg = uint32_t(std::countr_zero(std::bit_floor(std::max(n, 64u))));
    const uint32_t cell = n >> std::min(4u, lg - 3); // bakeCpvsTiled: the grid has 2^min(4, lg-3) cells
    const uint32_t t = std::min(tile, n), side = std::max(t, cell);
    // Strip rows as bakeCpvsTiled chooses them: R h <= max(T^2, 8 R), and a strip for every thread.
    uint64_t rows = std::clamp<uint64_t>(uint64_t(t) * t / side, 8, side);
    rows = std::min<uint64_t>(rows, std::max(8u, std::bit_floor(side / threads)));
    const uint64_t strips = uint64_t(threads) * side * rows * (8 + 68);
    const uint64_t regionTexels = uint64_t(side) * side;
    // Per 8x8 tile 12 B x 4/3 (16 B), and a step of 12 B per 16 texels (0.75 B a texel): held twice.
    const uint64_t precompute = 2 * (regionTexels / 64 * 16 + regionTexels / 16 * 12);
    const uint64_t inserted = regionTexels / 8 * kCpvsNodeBytes;
    const uint64_t dag = kCpvsNodesPerSide * n * kCpvsNodeBytes;
    // The merge holds both halves and the result; the layout's words (below the DAG's bytes) come after
    // the region work is freed, and the record's words are serialised once the DAG is gone.
    return strips + precompute + inserted + 3 * dag;
}

} // namespace

uint64_t currentResidentBytes() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long long size = 0, resident = 0;
    const int got = std::fscanf(f, "%llu %llu", &size, &resident);
    std::fclose(f);
    const long page = sysconf(_SC_PAGESIZE);
    return got == 2 && page > 0 ? resident * uint64_t(page) : 0;
}

BakeBase bakeBaseOf(const Scene& scene, bool gpuDevice) {
    BakeBase b;
    // The peak (getrusage, KiB) and the resident bytes (/proc, pages) come from two readings; the peak so
    // far is never below what is resident now, whatever their granularity and order.
    b.residentBytes = currentResidentBytes(), b.gpuDevice = gpuDevice;
    b.peakBytes = std::max(peakResidentBytes(), b.residentBytes);
    for (const Instance& inst : scene.instances) // castersFromScene's triangles, counted, not built
        if (!inst.dynamic && inst.mesh < scene.meshes.size())
            b.casterTriangles += scene.meshes[inst.mesh].indices.size() / 3;
    return b;
}

uint64_t cpvsTiledPeakBytes(const std::vector<uint32_t>& faceResolutions, uint32_t tile, const BakeBase& base,
                            uint32_t threads) {
    const uint32_t p = threads ? threads : hardwareThreads();
    // Maps are built one after another: each beside the words of those before it; at the end every
    // record's words are serialised beside themselves (x2), after the last DAG is freed.
    uint64_t held = 0, peak = 0;
    for (uint32_t r : faceResolutions) {
        peak = std::max(peak, held + cpvsTiledMapBytes(r, tile ? tile : kBakeDefaultTile, p));
        held += kCpvsNodesPerSide * r * kCpvsNodeBytes; // the layout's words, below the DAG's bytes
    }
    peak = std::max(peak, 2 * held);
    const uint64_t device = base.gpuDevice ? 128 * kMiB : 0;
    return std::max(base.peakBytes, base.residentBytes + device + base.casterTriangles * 256 + peak);
}

uint64_t bakePeakBytes(const std::vector<uint32_t>& faceResolutions, StaticMethod method, uint32_t tile,
                       uint32_t shards, const BakeBase& base) {
    const auto tiled = [&](uint32_t r) { return bakeTiled(method, r, tile); };
    if (method == StaticMethod::CPVS && !faceResolutions.empty() &&
        std::all_of(faceResolutions.begin(), faceResolutions.end(), tiled))
        return cpvsTiledPeakBytes(faceResolutions, tile, base);
    uint64_t words = 0, largest = 0, tiledLargest = 0;
    bool anyTiled = false;
    for (uint32_t r : faceResolutions) {
        const uint64_t texels = uint64_t(r) * r;
        anyTiled = anyTiled || tiled(r);
        if (tiled(r) && method == StaticMethod::SM) {
            words += texels * 4; // the output, filled tile by tile: no map, no tree
            continue;
        }
        if (tiled(r)) {
            const uint64_t nodes = texels / 64;
            tiledLargest = std::max(tiledLargest, shards > 1 ? nodes / shards * 2 * sizeof(MhPackedNode)
                                                             : nodes * (2 * sizeof(MhTree::Node) + 8));
            words += shards > 1 ? 0 : nodes * 8;
            continue;
        }
        words += texels * 4;
        largest = std::max(largest, texels);
    }
    uint64_t working = largest * (8 + 16); // the map, and the encoder's scratch
    if (anyTiled)
        working = std::max(working, tiledLargest + tiledWorkingBytes(tile ? tile : kBakeDefaultTile));
    return 400 * kMiB + 2 * words + working;
}

} // namespace ml
