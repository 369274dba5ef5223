// MMH construction: hashing, windowed matching, merging and serialization (see mmh.h).
#include "shadows/static/mmh.h"

#include <algorithm>
#include <type_traits>
#include <unordered_map>

namespace ml {

namespace {

uint64_t mix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// A node's interval, narrowed by merges: always inside the tree's [lo, hi], so 32 bits hold it.
struct Range {
    uint32_t lo, hi;
};

// Merge state, 44 B a tree node with the layout positions, beside the tree's 28 (the moon's tree at
// 65536^2: 45 M nodes): what matching needs is dropped before the serializer allocates its own arrays.
struct Builder {
    const MhTree& tree;
    size_t n;
    std::vector<int32_t> parent;
    std::vector<uint8_t> height, flags;
    std::vector<uint64_t> hash;
    std::vector<Range> J;
    std::vector<uint32_t> val; // inside its interval
    std::vector<uint8_t> fixed, dropped;
    std::vector<int32_t> redirect;

    explicit Builder(const MhTree& t) : tree(t), n(t.nodes.size()) {
        parent.assign(n, -1), height.assign(n, 0), flags.assign(n, 0), hash.assign(n, 0);
        J.resize(n), val.assign(n, 0), fixed.assign(n, 0), dropped.assign(n, 0), redirect.assign(n, -1);
        for (size_t i = n; i-- > 0;) {
            const MhTree::Node& nd = tree.nodes[i];
            J[i] = {nd.lo, nd.hi};
            uint32_t f = 0, h = 0;
            for (uint32_t c = 0; c < 4; ++c)
                if (nd.child[c] >= 0) {
                    const MhTree::Node& ch = tree.nodes[nd.child[c]];
                    parent[nd.child[c]] = int32_t(i);
                    f |= ch.type() << (2 * c);
                    h = std::max<uint32_t>(h, height[nd.child[c]] + 1u);
                }
            flags[i] = uint8_t(f), height[i] = uint8_t(h);
            uint64_t hv = mix64(f);
            for (uint32_t c = 0; c < 4; ++c)
                if (nd.child[c] >= 0 && tree.nodes[nd.child[c]].inner())
                    hv = mix64(hv ^ (hash[nd.child[c]] + c));
            hash[i] = hv;
        }
    }
    void fix(size_t i) {
        if (fixed[i] || !tree.nodes[i].valued) return;
        val[i] = J[i].lo + (J[i].hi - J[i].lo) / 2u;
        fixed[i] = 1;
    }
    // Value of the nearest valued node at or above i (every such node is already fixed).
    int64_t base(int32_t i) const { // int64: callers subtract it from intervals
        while (!tree.nodes[i].valued) i = parent[i];
        return val[i];
    }
    template <class F> void walkPairs(int32_t a, int32_t b, F f) const {
        std::vector<std::pair<int32_t, int32_t>> st;
        auto pushChildren = [&](int32_t x, int32_t y) {
            for (uint32_t c = 0; c < 4; ++c)
                if (tree.nodes[x].child[c] >= 0)
                    st.push_back({tree.nodes[x].child[c], tree.nodes[y].child[c]});
        };
        pushChildren(a, b);
        while (!st.empty()) {
            auto [x, y] = st.back();
            st.pop_back();
            if (!f(x, y)) return;
            if (tree.nodes[x].inner()) pushChildren(x, y);
        }
    }
};

} // namespace

Result<std::vector<uint32_t>> encodeMMH(const MhTree& tree, const MmhOptions& options, MmhStats* statsOut) {
    if (tree.planar()) return fail("MMH: a planar tree (DAG-MH's values) has no MMH encoding");
    Builder b(tree);
    MmhStats st;
    // Unmerged layout positions bound every redirected offset (merging only removes words between).
    // Counted, not written: at 65536^2 the written layout would add about 0.8 GB to the peak.
    std::vector<uint32_t> hpos, gpos;
    mhfmt::layoutPositions(tree, hpos, gpos);
    const uint32_t maxH = b.height[0];
    std::vector<std::vector<int32_t>> byHeight(maxH + 1);
    for (size_t i = 0; i < b.n; ++i) byHeight[b.height[i]].push_back(int32_t(i)); // preorder within a height
    b.fix(0);
    struct Stat {
        int64_t lMin, lMax, hMin, hMax;
    };
    std::vector<Stat> stat;
    std::vector<int64_t> baseOf;
    for (uint32_t h = maxH; h-- > 1;) {
        const auto& cands = byHeight[h];
        for (int32_t i : cands)
            if (!b.dropped[i]) b.fix(size_t(i));
        stat.assign(cands.size(), {});
        baseOf.assign(cands.size(), 0);
        std::vector<std::vector<uint32_t>> lists; // positions into cands, depth-first order
        std::unordered_map<uint64_t, uint32_t> listOf;
        for (uint32_t k = 0; k < cands.size(); ++k) {
            int32_t node = cands[k];
            if (b.dropped[node]) continue;
            int64_t a = b.base(node);
            baseOf[k] = a;
            Stat s{INT64_MAX, INT64_MIN, INT64_MAX, INT64_MIN};
            b.walkPairs(node, node, [&](int32_t x, int32_t) {
                if (tree.nodes[x].valued) {
                    int64_t lo = int64_t(b.J[x].lo) - a, hi = int64_t(b.J[x].hi) - a;
                    s.lMin = std::min(s.lMin, lo), s.lMax = std::max(s.lMax, lo);
                    s.hMin = std::min(s.hMin, hi), s.hMax = std::max(s.hMax, hi);
                }
                return true;
            });
            stat[k] = s;
            auto [it, inserted] = listOf.try_emplace(b.hash[node], uint32_t(lists.size()));
            if (inserted) lists.emplace_back();
            lists[it->second].push_back(k);
        }
        for (const auto& list : lists) {
            const size_t size = list.size();
            for (size_t i = size; i-- > 0;) {
                const uint32_t ka = list[i];
                const int32_t A = cands[ka];
                for (size_t j = i + 1; j < size && j <= i + options.window; ++j) {
                    const uint32_t kb = list[j];
                    const int32_t B = cands[kb];
                    if (b.redirect[B] >= 0) continue;
                    ++st.candidates;
                    const Stat &sa = stat[ka], &sb = stat[kb];
                    if (sa.hMin < sb.lMin || sb.hMin < sa.lMin || sa.lMax > sb.hMax || sb.lMax > sa.hMax) {
                        ++st.rejectedStats;
                        continue;
                    }
                    if (gpos[B] <= hpos[A] || gpos[B] - hpos[A] > mhfmt::kMaxOffset) {
                        ++st.rejectedOffset;
                        continue;
                    }
                    const int64_t aA = baseOf[ka], aB = baseOf[kb];
                    bool ok = b.flags[A] == b.flags[B];
                    if (ok)
                        b.walkPairs(A, B, [&](int32_t x, int32_t y) {
                            if (b.flags[x] != b.flags[y]) return ok = false;
                            if (tree.nodes[x].valued) {
                                int64_t lo = std::max(int64_t(b.J[x].lo) - aA, int64_t(b.J[y].lo) - aB);
                                int64_t hi = std::min(int64_t(b.J[x].hi) - aA, int64_t(b.J[y].hi) - aB);
                                if (lo > hi) return ok = false;
                            }
                            return true;
                        });
                    if (!ok) {
                        ++st.rejectedFull;
                        continue;
                    }
                    b.walkPairs(A, B, [&](int32_t x, int32_t y) {
                        // Inside J[y]: the check above found the shifted intervals overlapping.
                        if (tree.nodes[x].valued)
                            b.J[y] = {uint32_t(std::max<int64_t>(b.J[y].lo, int64_t(b.J[x].lo) - aA + aB)),
                                      uint32_t(std::min<int64_t>(b.J[y].hi, int64_t(b.J[x].hi) - aA + aB))};
                        b.dropped[x] = 1;
                        ++st.droppedNodes;
                        return true;
                    });
                    b.redirect[A] = B;
                    ++st.merges;
                    break;
                }
            }
        }
    }
    for (size_t i = 0; i < b.n; ++i)
        if (!b.dropped[i]) b.fix(i);
    auto release = [](auto& v) { std::decay_t<decltype(v)>().swap(v); };
    release(b.J), release(b.hash), release(b.height), release(b.flags), release(b.fixed), release(byHeight);
    release(stat), release(baseOf);
    // Relative values: value minus the nearest valued ancestor's value (mod 2^32).
    std::vector<uint32_t> rel(b.n, 0);
    for (size_t i = 0; i < b.n; ++i) {
        if (b.dropped[i] || !tree.nodes[i].valued) continue;
        int64_t above = i == 0 ? 0 : b.base(b.parent[i]);
        rel[i] = uint32_t(b.val[i]) - uint32_t(above);
    }
    release(b.parent), release(b.val);
    if (statsOut) *statsOut = st;
    std::vector<uint32_t>().swap(hpos), std::vector<uint32_t>().swap(gpos); // the serializer makes its own
    return mhfmt::serialize(tree, rel, &b.redirect, &b.dropped, mhfmt::kMagicMMH, nullptr, nullptr,
                            options.layout);
}

Result<std::vector<uint32_t>> encodeMMH(const DualDepthMap& map, const MmhOptions& options) {
    auto tree = buildMhTree(map);
    if (!tree) return fail(tree.error());
    return encodeMMH(*tree, options);
}

Result<void> validateMMH(const uint32_t* data, size_t size) {
    return mhfmt::validate(data, size, mhfmt::kMagicMMH);
}
stat::ByteBreakdown breakdownMMH(const uint32_t* data, size_t size) {
    return mhfmt::breakdown(data, size);
}

} // namespace ml
