// CPVS insertion (paper section 3.2), bottom-up compression (section 4.1) and the bake driver.
//
// Insertion walks every grid cell top-down, children in Z order (the 4 near-slice children before the 4
// far ones), so for any x, y footprint the volumes along z are completed near to far. Per footprint and
// level it keeps the last completed node and `next`, the nearest resolved transition slice t > zref
// (zref = that node's first slice). A later volume [z, z + S) of the same footprint is identical to that
// node iff no column of the footprint changes state inside (zref, z + S - 1], i.e. next >= z + S; it then
// re-uses the node and the recursion ends, as for homogeneous volumes (min-max test on t). `next` of a new
// node comes from its near children: a homogeneous lit child gives its min t, a shadowed one none (INF),
// a re-used one its stored next (no transition lies between), an 8^3 node the first tile step > z0.
#include "shadows/static/cpvs.h"
#include "shadows/static/cpvs_internal.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace ml {
namespace cpvs_detail {

namespace {

constexpr uint32_t kInf = 0xFFFFFFFFu;
constexpr uint32_t kNone = 0xFFFFFFFFu;

struct Ref {
    uint8_t kind; // 0 lit, 1 shadowed, 2 node
    uint32_t id;
    uint32_t next; // nearest transition slice t > this volume's first slice over its footprint
};

struct Entry {
    uint32_t node = kNone, next = 0;
};

// 16 bits (4x4, bit x + 4 y) of an 8x8 tile mask (bit x + 8 y) for the quadrant (cx, cy).
inline uint64_t quadrant(uint64_t m, uint32_t cx, uint32_t cy) {
    uint64_t q = 0;
    for (uint32_t r = 0; r < 4; ++r) q |= ((m >> (8 * (4 * cy + r) + 4 * cx)) & 0xFu) << (4 * r);
    return q;
}

class Inserter {
  public:
    // Footprints of the tiles [tx0, tx0 + tw) x [ty0, ty0 + tw) only (tw a power of two, the block of cells
    // inserted): the per-footprint entries are kept for those alone.
    Inserter(const CpvsPrecompute& pre, Dag& dag, uint32_t topLevel, uint32_t tx0, uint32_t ty0, uint32_t tw)
        : pre_(pre), dag_(dag), tx0_(tx0), ty0_(ty0), tw_(tw) {
        entries_.resize(topLevel + 1);
        for (uint32_t k = 0; k <= topLevel; ++k) entries_[k].resize(size_t(tw >> k) * (tw >> k));
        dag_.levels.resize(topLevel + 1);
    }

    Ref build(uint32_t k, uint32_t fx, uint32_t fy, uint32_t z0) {
        const uint32_t size = 8u << k, w = pre_.tiles >> k;
        const size_t f = size_t(fy) * w + fx;
        const uint32_t mn = pre_.minT[k][f], mx = pre_.maxT[k][f];
        if (mn >= z0 + size) return {0, 0, mn}; // all columns lit through the volume
        if (mx <= z0) return {1, 0, kInf};      // all columns shadowed from its first slice
        Entry& e = entries_[k][size_t(fy - (ty0_ >> k)) * (tw_ >> k) + (fx - (tx0_ >> k))];
        if (e.node != kNone && e.next >= z0 + size) return {2, e.node, e.next};

        Node node;
        uint32_t next = kInf;
        if (k == 0) {
            next = leafChildren(fx, fy, z0, node);
        } else {
            for (uint32_t c = 0; c < 8; ++c) {
                Ref r = build(k - 1, 2 * fx + (c & 1u), 2 * fy + ((c >> 1) & 1u), z0 + (c >> 2) * (size / 2));
                if (c < 4) next = std::min(next, r.next);
                attach(node, c, r);
            }
        }
        uint32_t id = uint32_t(dag_.levels[k].size());
        dag_.levels[k].push_back(node);
        e = {id, next};
        return {2, id, next};
    }

  private:
    static void attach(Node& node, uint32_t c, const Ref& r) {
        if (r.kind == 2) {
            node.childMask |= uint8_t(1u << c);
            node.child[c] = r.id;
        } else if (r.kind == 1) {
            node.shadowMask |= uint8_t(1u << c);
        }
    }

    // An 8^3 node over one tile: its 4^3 children straight from the tile's visibility masks (the paper's
    // finest level never queries the depth maps again). Returns next for the tile.
    uint32_t leafChildren(uint32_t tx, uint32_t ty, uint32_t z0, Node& node) {
        const size_t tile = size_t(ty) * pre_.tiles + tx;
        const uint32_t first = pre_.stepFirst[tile], end = pre_.stepFirst[tile + 1];
        uint64_t masks[8];
        uint32_t j = first;
        uint64_t m = 0;
        while (j < end && pre_.stepStart[j] <= z0) m = pre_.stepMask[j++];
        const uint32_t next = j < end ? pre_.stepStart[j] : kInf; // steps are the tile's distinct t
        for (uint32_t dz = 0; dz < 8; ++dz) {
            while (j < end && pre_.stepStart[j] <= z0 + dz) m = pre_.stepMask[j++];
            masks[dz] = m;
        }
        for (uint32_t c = 0; c < 8; ++c) {
            uint32_t cx = c & 1u, cy = (c >> 1) & 1u, cz = c >> 2;
            uint64_t leaf = 0;
            for (uint32_t dz = 0; dz < 4; ++dz) leaf |= quadrant(masks[4 * cz + dz], cx, cy) << (16 * dz);
            Ref r{0, 0, 0};
            if (leaf == ~uint64_t(0)) {
                r.kind = 1;
            } else if (leaf != 0) {
                r.kind = 2;
                r.id = uint32_t(dag_.leaves.size());
                dag_.leaves.push_back(leaf);
            }
            attach(node, c, r);
        }
        return next;
    }

    const CpvsPrecompute& pre_;
    Dag& dag_;
    uint32_t tx0_, ty0_, tw_;
    std::vector<std::vector<Entry>> entries_;
};

// Sorts items, drops duplicates; remap[old] = new index. Deterministic: output in content order.
template <class T> std::vector<uint32_t> sortUnique(std::vector<T>& items) {
    std::vector<uint32_t> order(items.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        if (items[a] < items[b]) return true;
        if (items[b] < items[a]) return false;
        return a < b;
    });
    std::vector<uint32_t> remap(items.size());
    std::vector<T> out;
    out.reserve(items.size());
    for (uint32_t i = 0; i < order.size(); ++i) {
        // equality on the full content: a node is merged only with an identical one
        if (out.empty() || out.back() < items[order[i]]) out.push_back(items[order[i]]);
        remap[order[i]] = uint32_t(out.size() - 1);
    }
    items = std::move(out);
    return remap;
}

} // namespace

namespace {

// Inserts the cells [x0, x0 + w) x [y0, y0 + w) x [0, G) into a fresh Dag; grid entry of cell (x, y, z) at
// (x - x0) + w ((y - y0) + w z).
Dag insertCells(const CpvsPrecompute& pre, uint32_t log2Resolution, uint32_t gridLog2, uint32_t x0,
                uint32_t y0, uint32_t w, const std::function<void(float)>& progress) {
    Dag dag;
    dag.resolution = pre.resolution;
    dag.log2Resolution = log2Resolution;
    dag.gridLog2 = gridLog2;
    dag.cellLog2 = log2Resolution - gridLog2;
    const uint32_t topLevel = dag.cellLog2 - 3, cell = 1u << dag.cellLog2, g = 1u << gridLog2;
    const uint32_t tilesPerCell = cell / 8;
    Inserter ins(pre, dag, topLevel, x0 * tilesPerCell, y0 * tilesPerCell, w * tilesPerCell);
    dag.grid.resize(size_t(w) * w * g);
    for (uint32_t z = 0; z < g; ++z) { // z outermost: each footprint sees its volumes near to far
        for (uint32_t y = 0; y < w; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                Ref r = ins.build(topLevel, x0 + x, y0 + y, z * cell);
                dag.grid[(size_t(z) * w + y) * w + x] = r.kind == 2 ? 2u + r.id : r.kind;
            }
        if (progress) progress(float(z + 1) / float(g));
    }
    return dag;
}

} // namespace

Dag insert(const CpvsPrecompute& pre, uint32_t log2Resolution, uint32_t gridLog2,
           const std::function<void(float)>& progress) {
    return insertCells(pre, log2Resolution, gridLog2, 0, 0, 1u << gridLog2, progress);
}

Dag insertBlock(const CpvsPrecompute& pre, uint32_t log2Resolution, uint32_t gridLog2,
                const CellBlock& block) {
    return insertCells(pre, log2Resolution, gridLog2, block.x0, block.y0, block.w, {});
}

void compressBottomUp(Dag& dag) {
    std::vector<uint32_t> remap = sortUnique(dag.leaves);
    for (auto& level : dag.levels) {
        for (Node& n : level)
            for (uint32_t c = 0; c < 8; ++c)
                if ((n.childMask >> c) & 1u) n.child[c] = remap[n.child[c]];
        remap = sortUnique(level);
    }
    for (uint32_t& e : dag.grid)
        if (e >= 2) e = 2 + remap[e - 2];
}

namespace {

inline uint64_t mix64(uint64_t x) { // splitmix64 finaliser
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

class TopDown {
  public:
    TopDown(Dag& dag, uint32_t hashBits) : dag_(dag) {
        const uint64_t keep = hashBits >= 64 ? ~0ull : (uint64_t(1) << hashBits) - 1;
        // hashes bottom-up from contents (leaf masks), so roots of identical subtrees hash alike at once
        leafHash_.resize(dag.leaves.size());
        for (size_t i = 0; i < dag.leaves.size(); ++i) leafHash_[i] = mix64(dag.leaves[i]) & keep;
        hash_.resize(dag.levels.size());
        confirmed_.resize(dag.levels.size());
        for (size_t k = 0; k < dag.levels.size(); ++k) {
            const auto& below = k == 0 ? leafHash_ : hash_[k - 1];
            hash_[k].resize(dag.levels[k].size());
            for (size_t i = 0; i < dag.levels[k].size(); ++i) {
                const Node& n = dag.levels[k][i];
                uint64_t h = mix64(0x5eedull + n.childMask + (uint64_t(n.shadowMask) << 8) + (k << 16));
                for (uint32_t c = 0; c < 8; ++c)
                    h = mix64(h ^ ((n.childMask >> c) & 1u ? below[n.child[c]] + c : c));
                hash_[k][i] = h & keep;
            }
        }
    }

    uint64_t collisions = 0;

    void run() {
        const uint32_t top = uint32_t(dag_.levels.size()) - 1;
        // level top: the nodes the grid references, in grid order
        std::vector<uint32_t> ids;
        for (uint32_t e : dag_.grid)
            if (e >= 2) ids.push_back(e - 2);
        std::vector<std::vector<Node>> levels(dag_.levels.size());
        std::vector<uint32_t> remap = mergeLevel(top, ids, levels[top]);
        for (uint32_t& e : dag_.grid)
            if (e >= 2) e = 2 + remap[e - 2];
        for (uint32_t k = top + 1; k-- > 0;) {
            // the next level holds only the children of the surviving nodes: merged-away subtrees are
            // never looked at again (section 4.2)
            ids.clear();
            for (const Node& n : levels[k])
                for (uint32_t c = 0; c < 8; ++c)
                    if ((n.childMask >> c) & 1u) ids.push_back(n.child[c]);
            std::vector<uint32_t> childRemap;
            if (k == 0) {
                std::vector<uint64_t> leaves;
                childRemap = mergeLeaves(ids, leaves);
                dag_.leaves = std::move(leaves);
            } else {
                childRemap = mergeLevel(k - 1, ids, levels[k - 1]);
            }
            for (Node& n : levels[k])
                for (uint32_t c = 0; c < 8; ++c)
                    if ((n.childMask >> c) & 1u) n.child[c] = childRemap[n.child[c]];
        }
        dag_.levels = std::move(levels);
    }

  private:
    // Merges the listed nodes of level k: equal hash AND confirmed equal content -> one node. Returns a
    // map old id -> new id (only the listed entries are meaningful). Children still hold old ids.
    std::vector<uint32_t> mergeLevel(uint32_t k, const std::vector<uint32_t>& ids, std::vector<Node>& out) {
        std::vector<uint32_t> remap(dag_.levels[k].size(), kNone);
        std::unordered_map<uint64_t, std::vector<uint32_t>> reps; // hash -> kept old ids
        std::vector<uint32_t> newId(dag_.levels[k].size(), kNone);
        for (uint32_t id : ids) {
            if (remap[id] != kNone) continue;
            auto& cands = reps[hash_[k][id]];
            uint32_t found = kNone;
            for (uint32_t r : cands) {
                if (equal(k, r, id)) {
                    found = r;
                    break;
                }
                ++collisions; // same hash, different subtree: kept apart
            }
            if (found == kNone) {
                cands.push_back(id);
                newId[id] = uint32_t(out.size());
                out.push_back(dag_.levels[k][id]);
                found = id;
            }
            remap[id] = newId[found];
        }
        return remap;
    }

    std::vector<uint32_t> mergeLeaves(const std::vector<uint32_t>& ids, std::vector<uint64_t>& out) {
        std::vector<uint32_t> remap(dag_.leaves.size(), kNone);
        std::unordered_map<uint64_t, uint32_t> byValue; // the key is the full content: exact
        for (uint32_t id : ids) {
            if (remap[id] != kNone) continue;
            auto [it, fresh] = byValue.emplace(dag_.leaves[id], uint32_t(out.size()));
            if (fresh) out.push_back(dag_.leaves[id]);
            remap[id] = it->second;
        }
        return remap;
    }

    // Full structural comparison of two subtrees of the insertion DAG (the hash is never trusted alone).
    // Confirmed pairs are memoised, so shared subtrees are compared once.
    bool equal(uint32_t k, uint32_t a, uint32_t b) {
        if (a == b) return true;
        const Node &na = dag_.levels[k][a], &nb = dag_.levels[k][b];
        if (na.childMask != nb.childMask || na.shadowMask != nb.shadowMask) return false;
        if (hash_[k][a] != hash_[k][b]) return false;
        const uint64_t key = uint64_t(a) << 32 | b;
        if (confirmed_[k].count(key)) return true;
        for (uint32_t c = 0; c < 8; ++c) {
            if (!((na.childMask >> c) & 1u)) continue;
            bool same = k == 0 ? dag_.leaves[na.child[c]] == dag_.leaves[nb.child[c]]
                               : equal(k - 1, na.child[c], nb.child[c]);
            if (!same) return false;
        }
        confirmed_[k].insert(key);
        return true;
    }

    Dag& dag_;
    std::vector<uint64_t> leafHash_;
    std::vector<std::vector<uint64_t>> hash_;
    std::vector<std::unordered_set<uint64_t>> confirmed_; // per level: (a << 32 | b) proven equal
};

} // namespace

uint64_t compressTopDown(Dag& dag, uint32_t hashBits) {
    TopDown t(dag, hashBits);
    t.run();
    return t.collisions;
}

} // namespace cpvs_detail

Result<CpvsBake> bakeCpvs(const DualDepthMap& map, const CpvsParams& params) {
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    auto report = [&](float f) {
        if (params.progress) params.progress(f);
    };
    auto t0 = Clock::now();
    auto space = makeCpvsSpace(params.resolution, params.nearPlane, params.farPlane, params.slicing);
    if (!space) return fail(space.error());
    if (space->resolution > kCpvsWholeMapMax) // the map alone is 8 B a texel: larger maps bake in tiles
        return fail("cpvs: a whole-map bake stops at " + std::to_string(kCpvsWholeMapMax) + "^2, not " +
                    std::to_string(space->resolution) + "^2 (bakeCpvsTiled builds larger maps)");
    const uint32_t gridLog2 = std::min(params.gridLog2, space->log2Resolution - 3);
    auto pre = cpvsPrecompute(*space, map, 1u << (space->log2Resolution - gridLog2));
    if (!pre) return fail(pre.error());
    report(0.2f);
    auto t1 = Clock::now();
    CpvsBake bake;
    CpvsStats& st = bake.stats;
    st.tileSteps = pre->stepStart.size();
    cpvs_detail::Dag dag;
    if (params.compression == CpvsCompression::Regions) {
        cpvs_detail::RegionStats rs;
        dag = cpvs_detail::buildRegions(*pre, space->log2Resolution, gridLog2, params.regionLog2, rs,
                                        [&](float f) { report(0.2f + 0.7f * f); });
        st.nodesInserted = rs.nodesInserted;
        st.leavesInserted = rs.leavesInserted;
        st.regions = rs.regions;
        st.regionNodesPeak = rs.regionNodesPeak;
        st.regionLeavesPeak = rs.regionLeavesPeak;
        st.liveBytesPeak = rs.liveBytesPeak;
        // the phases interleave per region: their sums
        st.insertMs = rs.insertMs;
        st.compressMs = rs.compressMs + rs.mergeMs;
        st.mergeMs = rs.mergeMs;
    } else {
        dag = cpvs_detail::insert(*pre, space->log2Resolution, gridLog2,
                                  [&](float f) { report(0.2f + 0.5f * f); });
        st.leavesInserted = dag.leaves.size();
        for (const auto& l : dag.levels) st.nodesInserted += l.size();
        st.regionNodesPeak = st.nodesInserted;
        st.regionLeavesPeak = st.leavesInserted;
        st.liveBytesPeak = dag.leaves.size() * sizeof(uint64_t) + dag.grid.size() * sizeof(uint32_t) +
                           st.nodesInserted * sizeof(cpvs_detail::Node);
        auto t2 = Clock::now();
        if (params.compression == CpvsCompression::BottomUp) cpvs_detail::compressBottomUp(dag);
        if (params.compression == CpvsCompression::TopDown)
            st.hashCollisions = cpvs_detail::compressTopDown(dag, params.hashBits);
        st.insertMs = ms(t1, t2);
        st.compressMs = ms(t2, Clock::now());
    }
    report(0.9f);
    auto t3 = Clock::now();
    auto words = cpvs_detail::writeLayout(*space, dag);
    if (!words) return fail(words.error());
    bake.data = std::move(words.value());
    auto t4 = Clock::now();
    st.leavesFinal = dag.leaves.size();
    for (const auto& l : dag.levels) {
        st.nodesFinal += l.size();
        st.nodesPerLevel.push_back(l.size());
    }
    st.precomputeMs = ms(t0, t1);
    st.layoutMs = ms(t3, t4);
    st.bytes = cpvsBytes(bake.data.data());
    report(1.0f);
    return bake;
}

} // namespace ml
