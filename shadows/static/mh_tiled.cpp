// Tiled MH tree construction (see mh_tiled.h for why it equals the whole-map build).
#include "shadows/static/mh_tiled.h"

#include <algorithm>
#include <bit>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <atomic>
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

uint32_t log2Ceil(uint32_t v) {
    uint32_t l = 0;
    while ((1u << l) < v) ++l;
    return l;
}

MhTile pack(const mhbuild::Subtree& t) {
    MhTile p;
    p.lo = t.lo, p.hi = t.hi, p.plane = t.plane, p.flags = t.flags;
    p.nodes.resize(t.nodes.size());
    for (size_t i = 0; i < t.nodes.size(); ++i) {
        const MhTree::Node& n = t.nodes[i];
        uint32_t bits = uint32_t(n.valued) << 4 | uint32_t(n.depth) << 8;
        for (uint32_t c = 0; c < 4; ++c) bits |= n.child[c] >= 0 ? 1u << c : 0u;
        p.nodes[i] = {n.lo, n.hi, bits, n.plane};
    }
    return p;
}

// Appends the packed subtree from `cursor` in preorder; returns the index of its root in `out`.
int32_t unpack(const std::vector<MhPackedNode>& nodes, size_t& cursor, std::vector<MhTree::Node>& out) {
    const MhPackedNode q = nodes[cursor++];
    const int32_t index = int32_t(out.size());
    MhTree::Node n;
    n.lo = q.lo, n.hi = q.hi, n.valued = uint8_t((q.bits >> 4) & 1u), n.depth = uint8_t(q.bits >> 8);
    n.plane = q.plane;
    out.push_back(n);
    for (uint32_t c = 0; c < 4; ++c)
        if (q.bits & (1u << c)) {
            const int32_t ci = unpack(nodes, cursor, out);
            out[index].child[c] = ci;
        }
    return index;
}

// The top pyramid: levels 0..top, level `top` holding the tile roots.
struct Top {
    std::vector<std::vector<uint32_t>> lo, hi, plane; // plane: planar trees only
    std::vector<std::vector<uint8_t>> flags;
};

// Preorder emission of the top levels, splicing each present tile's nodes at its root.
int32_t emit(const Top& t, uint32_t top, uint32_t level, uint32_t x, uint32_t y, std::vector<MhTile>& tiles,
             std::vector<MhTree::Node>& out) {
    const uint32_t n = 1u << level;
    const size_t i = size_t(y) * n + x;
    const int32_t index = int32_t(out.size());
    if (level == top) {
        size_t cursor = 0;
        unpack(tiles[i].nodes, cursor, out);
        out[index].valued = (t.flags[level][i] & 1u) ? 1 : 0; // decided above the tile
        std::vector<MhPackedNode>().swap(tiles[i].nodes);     // freed as spliced
        return index;
    }
    MhTree::Node node;
    node.lo = t.lo[level][i], node.hi = t.hi[level][i];
    node.valued = (t.flags[level][i] & 1u) ? 1 : 0;
    node.depth = uint8_t(level);
    node.plane = t.plane.empty() ? 0u : t.plane[level][i];
    out.push_back(node);
    if (t.flags[level][i] & 2u) {
        const uint32_t cn = n * 2;
        for (uint32_t c = 0; c < 4; ++c) {
            const uint32_t cx = 2 * x + (c & 1u), cy = 2 * y + (c >> 1);
            if (t.flags[level + 1][size_t(cy) * cn + cx] & 3u)
                out[index].child[c] = emit(t, top, level + 1, cx, cy, tiles, out);
        }
    }
    return index;
}

} // namespace

Result<MhTileGrid> mhTileGrid(uint32_t res, uint32_t tile) {
    if (res == 0 || res > kMhMaxResolution)
        return fail("MH: resolution " + std::to_string(res) + " outside 1.." +
                    std::to_string(kMhMaxResolution));
    if (tile == 0 || (tile & (tile - 1)) != 0)
        return fail("MH: tile side " + std::to_string(tile) + " is not a power of two");
    MhTileGrid g;
    g.resolution = res, g.levels = log2Ceil(res);
    g.tile = std::min(tile, 1u << g.levels), g.top = g.levels - log2Ceil(g.tile), g.perAxis = 1u << g.top;
    return g;
}

Result<void> buildMhTiles(const MhTileGrid& grid, const DualTileSource& source, const MhTiledOptions& options,
                          const std::function<bool(uint32_t)>& select, std::vector<MhTile>& tiles,
                          MhTiledStats* stats) {
    if (!source) return fail("MH: tiled build without a tile source");
    const uint32_t res = grid.resolution, T = grid.tile, top = grid.top, m = grid.perAxis;
    const uint32_t count = grid.count();
    tiles.assign(count, MhTile{});
    std::vector<uint32_t> mine; // the tiles this call builds
    for (uint32_t k = 0; k < count; ++k)
        if (!select || select(k)) mine.push_back(k);
    const uint32_t owned = uint32_t(mine.size());
    std::atomic<uint32_t> next{0}, done{0};
    std::atomic<uint64_t> nodeCount{0};
    std::atomic<bool> failed{false};
    std::mutex mutex; // guards error, the stats sums and the progress callback
    std::string error;
    MhTiledStats st;
    std::once_flag emptyOnce; // the empty tile's subtree, built by the first worker that meets one
    MhTile emptyTile;
    std::string emptyError;
    std::atomic<uint32_t> emptyCount{0};

    auto worker = [&]() {
        const bool planar = !options.planes.empty();
        std::vector<uint32_t> enter, exit, texelPlane, lo(size_t(T) * T), hi(size_t(T) * T);
        std::vector<uint32_t> plane(planar ? size_t(T) * T : 0); // the tile's plane ids, padded
        uint64_t covered = 0, closed = 0;
        double render = 0, reduce = 0;
        // Reduces the rendered w x h texels of tile k into tiles[k]; false after an error.
        auto reduceTile = [&](uint32_t k, uint32_t w, uint32_t h) -> bool {
            // Texels past the resolution are "don't care" [0, 2^32-1], as in buildMhTree.
            for (uint32_t y = 0; y < T; ++y)
                for (uint32_t x = 0; x < T; ++x) {
                    const size_t o = size_t(y) * T + x;
                    if (x < w && y < h) {
                        const uint32_t e = enter[size_t(y) * w + x], f = exit[size_t(y) * w + x];
                        lo[o] = e, hi[o] = std::max(e, f); // a malformed exit < enter keeps just enter
                        covered += e != kDepthEmpty, closed += f > e;
                        if (planar) plane[o] = texelPlane[size_t(y) * w + x];
                    } else {
                        lo[o] = 0, hi[o] = 0xFFFFFFFFu;
                        if (planar) plane[o] = 0u;
                    }
                }
            if (planar)
                for (uint32_t id : plane)
                    if (id > options.planes.size()) {
                        std::lock_guard<std::mutex> lock(mutex);
                        if (!failed)
                            error = "tile " + std::to_string(k) + ": plane id " + std::to_string(id) +
                                    " of " + std::to_string(options.planes.size());
                        failed = true;
                        return false;
                    }
            auto sub = mhbuild::buildSubtree(T, lo.data(), hi.data(), top, planar ? plane.data() : nullptr);
            if (!sub) {
                std::lock_guard<std::mutex> lock(mutex);
                if (!failed) error = sub.error();
                failed = true;
                return false;
            }
            nodeCount += sub->nodes.size();
            tiles[k] = pack(sub.value());
            return true;
        };
        for (uint32_t j; !failed && (j = next++) < owned;) {
            const uint32_t k = mine[j];
            // Row-major tile index = the top pyramid's finest level; emission visits it in preorder.
            const uint32_t tx = k % m, ty = k / m, x0 = tx * T, y0 = ty * T;
            const uint32_t w = x0 < res ? std::min(T, res - x0) : 0, h = y0 < res ? std::min(T, res - y0) : 0;
            auto tr = Clock::now();
            const bool empty = w == T && h == T && options.emptyBlock && options.emptyBlock(x0, y0, w, h);
            if (empty) {
                std::call_once(emptyOnce, [&] {
                    std::fill(lo.begin(), lo.end(), kDepthEmpty),
                        std::fill(hi.begin(), hi.end(), kDepthEmpty);
                    std::fill(plane.begin(), plane.end(), 0u);
                    auto sub =
                        mhbuild::buildSubtree(T, lo.data(), hi.data(), top, planar ? plane.data() : nullptr);
                    if (sub)
                        emptyTile = pack(sub.value()), emptyTile.built = true;
                    else
                        emptyError = sub.error();
                });
                if (!emptyTile.built) {
                    std::lock_guard<std::mutex> lock(mutex);
                    if (!failed) error = "the empty tile: " + emptyError;
                    failed = true;
                    break;
                }
                ++emptyCount;
            } else if (w && h) {
                enter.resize(size_t(w) * h), exit.resize(size_t(w) * h);
                if (planar) texelPlane.assign(size_t(w) * h, 0u);
                if (auto r =
                        source(x0, y0, w, h, enter.data(), exit.data(), planar ? texelPlane.data() : nullptr);
                    !r) {
                    std::lock_guard<std::mutex> lock(mutex);
                    if (!failed)
                        error = "tile (" + std::to_string(x0) + ", " + std::to_string(y0) + "): " + r.error();
                    failed = true;
                    break;
                }
            }
            render += secondsSince(tr);
            auto tb = Clock::now();
            if (empty) {
                nodeCount += emptyTile.nodes.size();
                tiles[k] = emptyTile;
            } else if (!reduceTile(k, w, h)) {
                break;
            }
            tiles[k].built = true;
            const uint64_t held = nodeCount;
            if (options.maxNodes && held > options.maxNodes) {
                std::lock_guard<std::mutex> lock(mutex);
                if (!failed)
                    error = "the tree passed " + std::to_string(held) + " nodes (" +
                            std::to_string((held * sizeof(MhTree::Node)) >> 20) + " MiB) after " +
                            std::to_string(done + 1) + " of " + std::to_string(owned) +
                            " tiles, over its bound of " + std::to_string(options.maxNodes) + " nodes";
                failed = true;
                break;
            }
            reduce += secondsSince(tb);
            const uint32_t finished = ++done;
            if (options.progress) {
                std::lock_guard<std::mutex> lock(mutex);
                options.progress(double(finished) / owned);
            }
        }
        std::lock_guard<std::mutex> lock(mutex);
        st.coveredTexels += covered, st.closedTexels += closed;
        st.renderSeconds += render, st.reduceSeconds += reduce;
    };
    uint32_t threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    threads = std::max(1u, std::min(threads, owned));
    std::vector<std::thread> pool;
    for (uint32_t i = 1; i < threads; ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& th : pool) th.join();
    if (failed) return fail("MH: " + error);
    st.tiles = owned, st.tileSide = T, st.emptyTiles = emptyCount;
    st.nodes = nodeCount;
    if (stats) *stats = st;
    return {};
}

Result<MhTree> assembleMhTree(const MhTileGrid& grid, std::vector<MhTile>&& tiles, MhTiledStats* stats,
                              const std::vector<DepthPlane>& planes) {
    const uint32_t top = grid.top, count = grid.count();
    if (tiles.size() != count)
        return fail("MH: " + std::to_string(tiles.size()) + " tiles for a grid of " + std::to_string(count));
    for (uint32_t k = 0; k < count; ++k)
        if (!tiles[k].built || tiles[k].nodes.empty())
            return fail("MH: tile " + std::to_string(k) + " of " + std::to_string(count) + " is missing");
    auto ta = Clock::now();
    Top tp;
    tp.lo.resize(top + 1), tp.hi.resize(top + 1), tp.flags.resize(top + 1);
    tp.lo[top].resize(count), tp.hi[top].resize(count), tp.flags[top].resize(count);
    const bool planar = !planes.empty();
    if (planar) tp.plane.resize(top + 1), tp.plane[top].resize(count);
    for (uint32_t k = 0; k < count; ++k) {
        tp.lo[top][k] = tiles[k].lo, tp.hi[top][k] = tiles[k].hi, tp.flags[top][k] = tiles[k].flags;
        if (planar) tp.plane[top][k] = tiles[k].plane;
    }
    for (uint32_t l = top; l > 0; --l) {
        const size_t pn = size_t(1) << (l - 1);
        tp.lo[l - 1].resize(pn * pn), tp.hi[l - 1].resize(pn * pn), tp.flags[l - 1].resize(pn * pn);
        if (planar) tp.plane[l - 1].resize(pn * pn);
        mhbuild::reduceLevel(1u << l, tp.lo[l].data(), tp.hi[l].data(), tp.flags[l].data(),
                             tp.lo[l - 1].data(), tp.hi[l - 1].data(), tp.flags[l - 1].data(),
                             planar ? tp.plane[l].data() : nullptr,
                             planar ? tp.plane[l - 1].data() : nullptr);
    }
    MhTree tree;
    tree.resolution = grid.resolution, tree.levels = grid.levels;
    tree.planes = planes;
    size_t total = 0;
    for (const auto& s : tiles) total += s.nodes.size();
    tree.nodes.reserve(total + (size_t(count) * 4) / 3 + 1);
    emit(tp, top, 0, 0, 0, tiles, tree.nodes);
    std::vector<MhTile>().swap(tiles);
#ifdef __GLIBC__
    malloc_trim(0); // the tiles' small blocks back to the system before the encoders allocate theirs
#endif
    if (stats) stats->nodes = tree.nodes.size(), stats->assembleSeconds = secondsSince(ta);
    return tree;
}

Result<MhTree> buildMhTreeTiled(uint32_t res, const DualTileSource& source, const MhTiledOptions& options,
                                MhTiledStats* stats) {
    auto grid = mhTileGrid(res, options.tile);
    if (!grid) return fail(grid.error());
    std::vector<MhTile> tiles;
    MhTiledStats st;
    if (auto r = buildMhTiles(*grid, source, options, {}, tiles, &st); !r) return fail(r.error());
    auto tree = assembleMhTree(*grid, std::move(tiles), &st, options.planes);
    if (tree && stats) *stats = st;
    return tree;
}

Result<void> validateMhTile(const MhTileGrid& grid, const MhTile& tile, size_t planes) {
    const size_t limit = (size_t(grid.tile) * grid.tile * 4) / 3 + 1; // a full quadtree over the tile
    if (tile.nodes.empty() || tile.nodes.size() > limit)
        return fail(std::to_string(tile.nodes.size()) + " nodes, outside 1.." + std::to_string(limit));
    const MhPackedNode& root = tile.nodes[0];
    if (root.lo != tile.lo || root.hi != tile.hi || root.plane != tile.plane)
        return fail("root interval or plane differs from the tile's");
    if ((tile.flags & ~3u) != 0 || !(tile.flags & 1u) || ((tile.flags & 2u) != 0) != ((root.bits & 15u) != 0))
        return fail("root flags " + std::to_string(tile.flags) + " do not match its children");
    // Preorder: each node's present children follow it, one level deeper, only above the texels.
    std::vector<uint32_t> remaining; // per node on the path from the root: its children not yet seen
    for (size_t i = 0; i < tile.nodes.size(); ++i) {
        const MhPackedNode& q = tile.nodes[i];
        if (i > 0) {
            while (!remaining.empty() && remaining.back() == 0) remaining.pop_back();
            if (remaining.empty()) return fail("node " + std::to_string(i) + " follows a complete subtree");
            --remaining.back();
        }
        const uint32_t depth = grid.top + uint32_t(remaining.size());
        if ((q.bits >> 8) != depth || (q.bits & 0xE0u) != 0)
            return fail("node " + std::to_string(i) + ": bits " + std::to_string(q.bits) +
                        " (expected depth " + std::to_string(depth) + ")");
        if (q.plane > planes)
            return fail("node " + std::to_string(i) + ": plane id " + std::to_string(q.plane) + " of " +
                        std::to_string(planes));
        if (q.lo > q.hi && q.plane == 0)
            return fail("node " + std::to_string(i) + ": interval lo > hi without a plane");
        const uint32_t children = uint32_t(std::popcount(q.bits & 15u));
        if (children && depth >= grid.levels)
            return fail("node " + std::to_string(i) + ": a texel with children");
        if (!children && !(q.bits & 16u) && i > 0)
            return fail("node " + std::to_string(i) + ": a leaf without a value");
        remaining.push_back(children);
    }
    while (!remaining.empty() && remaining.back() == 0) remaining.pop_back();
    if (!remaining.empty()) return fail("the nodes end inside a subtree");
    return {};
}

DualTileSource dualTileSourceOf(const DualDepthMap& map) {
    return [&map](uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, uint32_t* enter, uint32_t* exit,
                  uint32_t* plane) -> Result<void> {
        const uint32_t r = map.resolution;
        if (x0 + w > r || y0 + h > r || map.enter.size() != size_t(r) * r ||
            map.exit.size() != map.enter.size())
            return fail("tile outside the map");
        if (plane && map.enterPlane.size() != map.enter.size()) return fail("the map has no plane ids");
        for (uint32_t y = 0; y < h; ++y) {
            std::copy_n(map.enter.begin() + (size_t(y0 + y) * r + x0), w, enter + size_t(y) * w);
            std::copy_n(map.exit.begin() + (size_t(y0 + y) * r + x0), w, exit + size_t(y) * w);
            if (plane)
                std::copy_n(map.enterPlane.begin() + (size_t(y0 + y) * r + x0), w, plane + size_t(y) * w);
        }
        return {};
    };
}

} // namespace ml
