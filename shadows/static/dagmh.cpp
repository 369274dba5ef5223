// DAG-MH construction (DAG + treelets + skip list + chunked values) and validation; see dagmh.h and
// docs/dagmh-encoding.md.
#include "shadows/static/dagmh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <numeric>
#include <map>
#include <string>
#include <unordered_map>

namespace ml {

namespace dagfmt {

void descendToSkipLevel(const uint32_t* data, uint32_t base, uint32_t X, uint32_t Y, uint32_t out[4]) {
    const uint32_t S = skipLevel(data, base);
    const uint32_t nodes = base + data[base + kNodeOffset];
    uint32_t kind = data[base + kRootKind], ptr = data[base + kRootPtr], depth = 0, vcount = 0, vlast = 0;
    uint32_t dlast = 0;
    while (kind == 1u && depth < S) {
        uint32_t flags = data[nodes + ptr];
        if ((flags & 256u) != 0u) vlast = vcount, dlast = depth;
        uint32_t s = S - depth - 1u;
        uint32_t c = (((Y >> s) & 1u) << 1u) | ((X >> s) & 1u);
        uint32_t t = (flags >> (2u * c)) & 3u;
        if (t == 0u) {
            kind = 0u;
            break;
        }
        uint32_t rank = 0, n = 0;
        for (uint32_t i = 0; i < 4; ++i) {
            uint32_t present = ((flags >> (2u * i)) & 3u) != 0u ? 1u : 0u;
            if (i < c) rank += present;
            n += present;
        }
        uint32_t child = data[nodes + ptr + 1u + rank];
        vcount += rank == 0u ? ((flags >> 8u) & 1u) : data[nodes + ptr + n + rank];
        ptr = child, depth += 1u, kind = t;
    }
    if (kind == 0u) ptr = 0u, vcount = 0u, depth = 0u; // resolved: only v_last matters
    out[0] = kind | depth << 8u | dlast << 16u, out[1] = ptr, out[2] = vcount, out[3] = vlast;
}

namespace {

// The walk behind cellBounds: the lookup's descent (dagmhDescend, the treelet step) taken into every
// child instead of one, with the lookup's v_last / d_last bookkeeping, so each region of texels that
// resolves to one value (an absent child, a node at level L, a treelet leaf) adds that value once.
struct BoundsWalk {
    const uint32_t* data;
    uint32_t L, B, X, Y, nodes, treelets; // (X, Y): the cell at level B
    uint32_t lo = 0xFFFFFFFFu, hi = 0u;
    uint32_t memoIndex = 0xFFFFFFFFu, memoValue = 0u; // consecutive regions mostly share a value

    // Adds value `vlast`, held by the node at depth `dlast` above the node (nx, ny) at depth `depth`.
    void take(uint32_t vlast, uint32_t dlast, uint32_t depth, uint32_t nx, uint32_t ny) {
        if (vlast != memoIndex) {
            const uint32_t s = depth - dlast;
            memoIndex = vlast;
            memoValue = dagmhValue(data, 0, vlast, (nx >> s) << (L - dlast), (ny >> s) << (L - dlast));
        }
        lo = std::min(lo, memoValue), hi = std::max(hi, memoValue);
    }
    // Above the cell (depth < B) only the child towards (X, Y) is followed.
    bool onPath(uint32_t depth, uint32_t c) const {
        if (depth >= B) return true;
        const uint32_t s = B - depth - 1u;
        return c == ((((Y >> s) & 1u) << 1u) | ((X >> s) & 1u));
    }
    void inner(uint32_t ptr, uint32_t depth, uint32_t nx, uint32_t ny, uint32_t vcount, uint32_t vlast,
               uint32_t dlast) {
        const uint32_t flags = data[nodes + ptr];
        if ((flags & 256u) != 0u) vlast = vcount, dlast = depth;
        if (depth >= L) return take(vlast, dlast, depth, nx, ny);
        uint32_t n = 0;
        for (uint32_t i = 0; i < 4; ++i) n += ((flags >> (2u * i)) & 3u) != 0u;
        uint32_t rank = 0;
        for (uint32_t c = 0; c < 4; ++c) {
            const uint32_t t = (flags >> (2u * c)) & 3u;
            const uint32_t cx = 2u * nx + (c & 1u), cy = 2u * ny + (c >> 1u);
            if (t != 0u && onPath(depth, c)) {
                const uint32_t child = data[nodes + ptr + 1u + rank];
                const uint32_t vc =
                    vcount + (rank == 0u ? ((flags >> 8u) & 1u) : data[nodes + ptr + n + rank]);
                if (t == 1u)
                    inner(child, depth + 1u, cx, cy, vc, vlast, dlast);
                else
                    treelet(child, depth + 1u, cx, cy, vc, vlast, dlast);
            } else if (t == 0u && onPath(depth, c)) {
                take(vlast, dlast, depth + 1u, cx, cy); // the child's texels keep v_last
            }
            rank += t != 0u;
        }
    }
    void treelet(uint32_t ptr, uint32_t depth, uint32_t nx, uint32_t ny, uint32_t vcount, uint32_t vlast,
                 uint32_t dlast) {
        const uint32_t* tw = data + treelets + kTreeletWords * ptr;
        treeletAt(tw, 0u, 0u, depth, nx, ny, vcount, vlast, dlast);
    }
    // Treelet position at level `lvl` with bit index `idx` (lvl + 21 c1 + 5 c2 + c3), node (nx, ny) at
    // `depth`; vcount is the treelet's (a set bit's value index is vcount + set bits before it).
    void treeletAt(const uint32_t* tw, uint32_t lvl, uint32_t idx, uint32_t depth, uint32_t nx, uint32_t ny,
                   uint32_t vcount, uint32_t vlast, uint32_t dlast) {
        const uint32_t wi = idx >> 5u;
        if (((tw[wi] >> (idx & 31u)) & 1u) != 0u) {
            uint32_t before = stat::popc(tw[wi] & stat::lowMask(idx & 31u));
            if (wi > 0u) before += stat::popc(tw[0]);
            if (wi > 1u) before += stat::popc(tw[1]);
            vlast = vcount + before, dlast = depth;
        }
        if (lvl == 3u || depth >= L) return take(vlast, dlast, depth, nx, ny);
        const uint32_t mul = lvl == 0u ? 21u : (lvl == 1u ? 5u : 1u);
        for (uint32_t c = 0; c < 4; ++c)
            if (onPath(depth, c))
                treeletAt(tw, lvl + 1u, idx + 1u + c * mul, depth + 1u, 2u * nx + (c & 1u),
                          2u * ny + (c >> 1u), vcount, vlast, dlast);
    }
};

} // namespace

uint32_t chooseBoundsLevel(uint32_t L, uint32_t S, uint64_t restWords) {
    const uint64_t budgetBytes = std::max<uint64_t>(restWords * 4 / 16, 65536);
    uint32_t B = S;
    while (B < std::min<uint32_t>({L, S + 4u, 9u}) && (uint64_t(4) << (2 * (B + 1))) <= budgetBytes) ++B;
    return B;
}

uint32_t cellBounds(const uint32_t* data, uint32_t X, uint32_t Y) {
    const uint32_t S = skipLevel(data), B = boundsLevel(data);
    const uint32_t* e = data + data[kSkipOffset] + kSkipWords * (((Y >> (B - S)) << S) + (X >> (B - S)));
    BoundsWalk w{data, data[kLevels], B, X, Y, data[kNodeOffset], data[kTreeletOffset]};
    const uint32_t kind = e[0] & 255u, depth = (e[0] >> 8u) & 255u, dlast = e[0] >> 16u;
    if (kind == 0u) {
        w.take(e[3], dlast, B, X, Y); // resolved above S: the whole cell has v_last
    } else {
        // The entry's node contains the cell: at depth S (inner) or at or above it (a treelet).
        const uint32_t nx = X >> (B - depth), ny = Y >> (B - depth);
        if (kind == 1u)
            w.inner(e[1], depth, nx, ny, e[2], e[3], dlast);
        else
            w.treelet(e[1], depth, nx, ny, e[2], e[3], dlast);
    }
    return packBounds(w.lo, w.hi);
}

} // namespace dagfmt

namespace {

// ---- value chunks (docs/dagmh-encoding.md) ----

struct Val {
    uint32_t lo, hi, px, py;
};

struct ChunkCode {
    uint32_t rep = 0, bitmap = 0, a = 0, bx = 0, by = 0, sh = 0, b = 0;
    std::vector<uint32_t> k; // factor per set bit, in bit order
};

// The decoder's arithmetic (dagmhValue) for a slot with a factor.
uint32_t decodeFactor(const ChunkCode& c, const Val& v, uint32_t f) {
    if (c.b == 32) return f;
    uint32_t wy = (c.by << 5) | c.sh;
    uint32_t by = uint32_t(int32_t(wy) >> 5);
    return c.a + c.bx * v.px + by * v.py + (f << (wy & 31u));
}

constexpr int64_t kMaxSlopeY = (int64_t(1) << 26) - 1; // B_y is stored in 27 bits (signed)

// Spread of the residual intervals under the plane (bx, by): max(lo - P) - min(hi - P).
int64_t spread(const std::vector<const Val*>& v, int64_t bx, int64_t by) {
    int64_t maxU = INT64_MIN, minW = INT64_MAX;
    for (const Val* p : v) {
        int64_t pr = bx * int64_t(p->px) + by * int64_t(p->py);
        maxU = std::max(maxU, int64_t(p->lo) - pr), minW = std::min(minW, int64_t(p->hi) - pr);
    }
    return maxU - minW;
}

// Plane + factors for the values in v (all with a factor): value = A + bx px + by py + (k << sh).
// The plane minimises the spread (a convex piecewise-linear function of the integer slopes): least
// squares on the interval midpoints as the start, then an integer pattern search. Every value is then
// checked with the decoder's uint32 arithmetic; on any miss the chunk falls back to raw values.
void fitPlane(const std::vector<const Val*>& v, ChunkCode& out) {
    const size_t m = v.size();
    out.k.assign(m, 0);
    out.bx = out.by = out.sh = 0;
    if (m == 0) {
        out.b = 0, out.a = 0;
        return;
    }
    int64_t bx = 0, by = 0;
    int64_t best = spread(v, 0, 0);
    if (m >= 2 && best > 0) {
        double mx = 0, my = 0, mv = 0;
        for (const Val* p : v) mx += p->px, my += p->py, mv += (double(p->lo) + double(p->hi)) * 0.5;
        mx /= double(m), my /= double(m), mv /= double(m);
        double sxx = 0, sxy = 0, syy = 0, sxv = 0, syv = 0;
        for (const Val* p : v) {
            double dx = p->px - mx, dy = p->py - my, dv = (double(p->lo) + double(p->hi)) * 0.5 - mv;
            sxx += dx * dx, sxy += dx * dy, syy += dy * dy, sxv += dx * dv, syv += dy * dv;
        }
        double det = sxx * syy - sxy * sxy, fx = 0, fy = 0;
        if (det > 1e-9 * std::max(1.0, sxx * syy))
            fx = (syy * sxv - sxy * syv) / det, fy = (sxx * syv - sxy * sxv) / det;
        else if (sxx > 0)
            fx = sxv / sxx;
        else if (syy > 0)
            fy = syv / syy;
        auto clampS = [](double f, int64_t lim) {
            return int64_t(std::llround(std::clamp(f, -double(lim), double(lim))));
        };
        int64_t cx = clampS(fx, INT32_MAX), cy = clampS(fy, kMaxSlopeY);
        int64_t s = spread(v, cx, cy);
        if (s < best) best = s, bx = cx, by = cy;
        // Pattern search over the 8 neighbours with halving steps.
        for (int64_t step = int64_t(1) << 12; step >= 1 && best > 0; step >>= 1) {
            for (int iter = 0; iter < 64; ++iter) {
                bool moved = false;
                for (int d = 0; d < 8; ++d) {
                    static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1},
                                         kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
                    int64_t nx = bx + kDx[d] * step, ny = by + kDy[d] * step;
                    if (nx > INT32_MAX || nx < INT32_MIN || ny > kMaxSlopeY || ny < -kMaxSlopeY - 1) continue;
                    int64_t t = spread(v, nx, ny);
                    if (t < best) best = t, bx = nx, by = ny, moved = true;
                }
                if (!moved) break;
            }
        }
    }
    int64_t maxU = INT64_MIN, minW = INT64_MAX;
    uint64_t minWidth = UINT64_MAX;
    for (const Val* p : v) {
        int64_t pr = bx * int64_t(p->px) + by * int64_t(p->py);
        maxU = std::max(maxU, int64_t(p->lo) - pr), minW = std::min(minW, int64_t(p->hi) - pr);
        minWidth = std::min<uint64_t>(minWidth, uint64_t(p->hi) - p->lo);
    }
    // Lattice step 2^sh: every residual interval is at least 2^sh - 1 wide, so each holds a point.
    uint32_t sh = std::min<uint32_t>(31, uint32_t(std::bit_width(minWidth + 1)) - 1);
    const int64_t a = minW;
    uint64_t steps = maxU > a ? (uint64_t(maxU - a) + (uint64_t(1) << sh) - 1) >> sh : 0;
    out.b = uint32_t(std::bit_width(steps));
    out.bx = uint32_t(int32_t(bx)), out.by = uint32_t(int32_t(by)) & 0x07FFFFFFu, out.sh = sh;
    out.a = uint32_t(uint64_t(a));
    bool ok = out.b < 32;
    for (size_t i = 0; i < m && ok; ++i) {
        int64_t pr = bx * int64_t(v[i]->px) + by * int64_t(v[i]->py);
        int64_t u = int64_t(v[i]->lo) - pr;
        out.k[i] = u > a ? uint32_t((uint64_t(u - a) + (uint64_t(1) << sh) - 1) >> sh) : 0u;
        uint32_t d = decodeFactor(out, *v[i], out.k[i]);
        ok = d >= v[i]->lo && d <= v[i]->hi;
    }
    if (!ok) { // raw fallback: the value itself
        out.b = 32, out.a = out.bx = out.by = out.sh = 0;
        for (size_t i = 0; i < m; ++i) out.k[i] = v[i]->lo;
    }
}

// Chooses the representative (its coverage set decodes to it with no factor) and the plane for the
// rest. Representative candidates: none; every distinct maximal-coverage set (up to 8); then, twice,
// the coverage sets of the two values at the extremes of the residual spread under the best plane so
// far (an off-plane group, e.g. a second surface or empty texels, is better served by the
// representative than by widening every factor). The fewest factor bits win; ties keep the earlier.
ChunkCode encodeChunk(const Val* vals, uint32_t count) {
    auto coverage = [&](uint32_t p) {
        uint32_t mask = 0;
        for (uint32_t j = 0; j < count; ++j)
            if (vals[j].lo <= p && p <= vals[j].hi) mask |= 1u << j;
        return mask;
    };
    std::vector<std::pair<uint32_t, uint32_t>> cands{{0u, 0u}}; // (covered mask, point)
    uint32_t bestCov = 0;
    std::vector<std::pair<uint32_t, uint32_t>> maxSets;
    for (uint32_t i = 0; i < count; ++i) {
        uint32_t mask = coverage(vals[i].lo), cov = uint32_t(std::popcount(mask));
        if (cov > bestCov) bestCov = cov, maxSets.clear();
        if (cov == bestCov) maxSets.push_back({mask, vals[i].lo});
    }
    std::sort(maxSets.begin(), maxSets.end());
    maxSets.erase(
        std::unique(maxSets.begin(), maxSets.end(), [](auto& a, auto& b) { return a.first == b.first; }),
        maxSets.end());
    if (bestCov >= 2) {
        if (maxSets.size() > 8) maxSets.resize(8);
        cands.insert(cands.end(), maxSets.begin(), maxSets.end());
    }
    std::vector<const Val*> rest;
    std::vector<uint32_t> tried;
    ChunkCode best;
    uint64_t bestBits = UINT64_MAX;
    auto tryMask = [&](uint32_t mask, uint32_t p) {
        if (std::find(tried.begin(), tried.end(), mask) != tried.end()) return;
        tried.push_back(mask);
        rest.clear();
        for (uint32_t j = 0; j < count; ++j)
            if (!(mask & (1u << j))) rest.push_back(&vals[j]);
        ChunkCode c;
        c.rep = p;
        c.bitmap = ~mask & stat::lowMask(count);
        fitPlane(rest, c);
        uint64_t bits = uint64_t(rest.size()) * c.b;
        if (bits < bestBits) bestBits = bits, best = std::move(c);
    };
    for (auto [mask, p] : cands) tryMask(mask, p);
    for (int round = 0; round < 2 && bestBits > 0 && best.b < 32; ++round) {
        const int64_t bx = int32_t(best.bx), by = int32_t(best.by << 5) >> 5;
        int64_t maxU = INT64_MIN, minW = INT64_MAX;
        uint32_t jU = 0, jW = 0;
        for (uint32_t j = 0; j < count; ++j) {
            int64_t pr = bx * int64_t(vals[j].px) + by * int64_t(vals[j].py);
            int64_t u = int64_t(vals[j].lo) - pr, w = int64_t(vals[j].hi) - pr;
            if (u > maxU) maxU = u, jU = j;
            if (w < minW) minW = w, jW = j;
        }
        tryMask(coverage(vals[jU].lo), vals[jU].lo);
        tryMask(coverage(vals[jW].lo), vals[jW].lo);
    }
    return best;
}

// Full-resolution texel at the top-left corner of every node's cell.
std::vector<std::array<uint32_t, 2>> nodeCorners(const MhTree& tree) {
    std::vector<std::array<uint32_t, 2>> pos(tree.nodes.size(), {0u, 0u});
    for (size_t i = 0; i < tree.nodes.size(); ++i) {
        const auto& nd = tree.nodes[i];
        if (nd.depth >= tree.levels) continue;
        uint32_t s = tree.levels - nd.depth - 1u;
        for (uint32_t c = 0; c < 4; ++c)
            if (nd.child[c] >= 0)
                pos[nd.child[c]] = {pos[i][0] + ((c & 1u) << s), pos[i][1] + ((c >> 1) << s)};
    }
    return pos;
}

struct VecHash {
    size_t operator()(const std::vector<uint32_t>& v) const {
        uint64_t h = 1469598103934665603ull;
        for (uint32_t w : v) h = (h ^ w) * 1099511628211ull;
        return size_t(h);
    }
};

} // namespace

Result<std::vector<uint32_t>> encodeDAGMH(const MhTree& tree, DagMhStats* statsOut) {
    using namespace dagfmt;
    const size_t n = tree.nodes.size();
    const uint32_t L = tree.levels;
    std::vector<uint8_t> height(n, 0);
    std::vector<int32_t> parent(n, -1);
    std::vector<uint64_t> total(n, 0);
    for (size_t i = n; i-- > 0;) {
        const auto& nd = tree.nodes[i];
        total[i] = nd.valued;
        for (uint32_t c = 0; c < 4; ++c)
            if (nd.child[c] >= 0) {
                parent[nd.child[c]] = int32_t(i);
                height[i] = std::max<uint8_t>(height[i], uint8_t(height[nd.child[c]] + 1));
                total[i] += total[nd.child[c]];
            }
    }
    DagMhStats st;
    st.values = total[0];
    if (total[0] == 0 || total[0] > 0xFFFFFFFFull) return fail("DAG-MH: value count out of range");
    // ---- structure, bottom-up (reverse preorder visits children first) ----
    std::vector<uint32_t> nodeWords;
    std::vector<std::array<uint32_t, 3>> treelets;
    std::unordered_map<std::vector<uint32_t>, uint32_t, VecHash> nodeIds;
    std::map<std::array<uint32_t, 3>, uint32_t> treeletIds;
    std::vector<uint32_t> refKind(n, 0), refPtr(n, 0);
    for (size_t i = n; i-- > 0;) {
        bool top = i == 0 || height[parent[i]] >= 4;
        if (!top && height[i] <= 3) continue;
        const auto& nd = tree.nodes[i];
        if (height[i] <= 3) {
            std::array<uint32_t, 3> bits{0, 0, 0};
            // (node, level, bit index so far)
            std::vector<std::array<int32_t, 3>> stack{{int32_t(i), 0, 0}};
            while (!stack.empty()) {
                auto [m, lvl, idx] = stack.back();
                stack.pop_back();
                if (tree.nodes[m].valued) bits[idx >> 5] |= 1u << (idx & 31);
                for (int32_t c = 0; c < 4; ++c) {
                    int32_t ch = tree.nodes[m].child[c];
                    if (ch < 0) continue;
                    int32_t mul = lvl == 0 ? 21 : (lvl == 1 ? 5 : 1);
                    // child bit index: its level (lvl + 1) + sum of path terms; idx already holds lvl.
                    stack.push_back({ch, lvl + 1, idx + 1 + c * mul});
                }
            }
            ++st.treeTreelets;
            auto [it, inserted] = treeletIds.try_emplace(bits, uint32_t(treelets.size()));
            if (inserted) treelets.push_back(bits);
            refKind[i] = 2, refPtr[i] = it->second;
            continue;
        }
        std::vector<uint32_t> words{nd.valued ? 256u : 0u};
        std::vector<uint32_t> prefixes;
        uint64_t before = nd.valued;
        bool first = true;
        for (uint32_t c = 0; c < 4; ++c) {
            int32_t ch = nd.child[c];
            if (ch < 0) continue;
            words[0] |= refKind[ch] << (2 * c);
            words.push_back(refPtr[ch]);
            if (!first) prefixes.push_back(uint32_t(before));
            first = false;
            before += total[ch];
        }
        words.insert(words.end(), prefixes.begin(), prefixes.end());
        ++st.treeInner;
        auto it = nodeIds.find(words);
        if (it == nodeIds.end()) {
            it = nodeIds.emplace(words, uint32_t(nodeWords.size())).first;
            nodeWords.insert(nodeWords.end(), words.begin(), words.end());
        }
        refKind[i] = 1, refPtr[i] = it->second;
    }
    st.innerNodes = nodeIds.size(), st.treelets = treelets.size();
    // ---- values, in preorder (= node index order), chunks of 32 ----
    std::vector<Val> vals;
    {
        std::vector<std::array<uint32_t, 2>> pos = nodeCorners(tree);
        for (size_t i = 0; i < n; ++i)
            if (tree.nodes[i].valued)
                vals.push_back({tree.nodes[i].lo, tree.nodes[i].hi, pos[i][0], pos[i][1]});
    }
    const uint32_t numValues = uint32_t(vals.size());
    const uint32_t numChunks = (numValues + kChunkValues - 1) / kChunkValues;
    std::vector<uint32_t> chunks(size_t(numChunks) * kChunkWords, 0), factors;
    uint64_t bitPos = 0;
    for (uint32_t c = 0; c < numChunks; ++c) {
        uint32_t count = std::min(kChunkValues, numValues - c * kChunkValues);
        ChunkCode code = encodeChunk(&vals[size_t(c) * kChunkValues], count);
        bitPos = (bitPos + 7) / 8 * 8;
        if (bitPos / 8 >= kMaxFactorBytes) return fail("DAG-MH: factor stream exceeds 64 MiB");
        uint32_t* w = &chunks[size_t(c) * kChunkWords];
        w[0] = code.rep, w[1] = code.bitmap, w[2] = code.a, w[3] = code.bx, w[4] = code.by << 5 | code.sh;
        w[5] = code.b | uint32_t(bitPos / 8) << 6;
        st.rawChunks += code.b == 32;
        st.factors += code.k.size();
        auto put = [&](uint32_t k, uint32_t bits) {
            for (uint32_t bit = 0; bit < bits; ++bit, ++bitPos) {
                if ((bitPos >> 5) >= factors.size()) factors.push_back(0);
                if ((k >> bit) & 1u) factors[bitPos >> 5] |= 1u << (bitPos & 31);
            }
        };
        for (uint32_t k : code.k) put(k, code.b);
        st.factorBits += uint64_t(code.k.size()) * code.b;
    }
    if (factors.size() < (bitPos + 31) / 32) factors.resize((bitPos + 31) / 32, 0);
    st.chunks = numChunks;
    // ---- assemble ----
    // Skip level: the deepest S <= min(L, 8) whose list (16 B per cell) stays within an eighth of the
    // rest of the structure. Each level it resolves saves a lookup one dependent node read (flags,
    // child, count), so dense maps take it as deep as the budget allows; nearly empty maps keep a
    // short list.
    const uint64_t restWords = nodeWords.size() + uint64_t(kTreeletWords) * treelets.size() +
                               uint64_t(kChunkWords) * numChunks + factors.size();
    uint32_t S = 0;
    while (S < std::min<uint32_t>(L, 8) && (uint64_t(kSkipWords) << (2 * (S + 1))) * 8 <= restWords) ++S;
    const uint32_t skipEntries = 1u << (2 * S);
    std::vector<uint32_t> out(kHeaderWords, 0);
    out[kMagicWord] = kMagic, out[kVersion] = kVersionNumber, out[kResolution] = tree.resolution,
    out[kLevels] = L;
    const uint32_t B = chooseBoundsLevel(L, S, restWords);
    out[kSkipLevel] = S | B << 8, out[kRootKind] = refKind[0], out[kRootPtr] = refPtr[0];
    out[kValues] = numValues, out[kChunks] = numChunks;
    out[kSkipOffset] = kHeaderWords;
    const uint32_t boundsOffset = out[kSkipOffset] + skipEntries * kSkipWords;
    out[kNodeOffset] = boundsOffset + (1u << (2 * B)); // one bounds word per cell of level B
    out[kNodeWords] = uint32_t(nodeWords.size());
    out[kTreeletOffset] = out[kNodeOffset] + out[kNodeWords];
    out[kTreelets] = uint32_t(treelets.size());
    out[kChunkOffset] = out[kTreeletOffset] + kTreeletWords * out[kTreelets];
    out[kFactorOffset] = out[kChunkOffset] + kChunkWords * numChunks;
    out[kFactorWords] = uint32_t(factors.size());
    out[kTotalWords] = out[kFactorOffset] + out[kFactorWords];
    out.resize(out[kTotalWords], 0);
    std::copy(nodeWords.begin(), nodeWords.end(), out.begin() + out[kNodeOffset]);
    for (size_t t = 0; t < treelets.size(); ++t)
        std::copy(treelets[t].begin(), treelets[t].end(),
                  out.begin() + out[kTreeletOffset] + kTreeletWords * t);
    std::copy(chunks.begin(), chunks.end(), out.begin() + out[kChunkOffset]);
    std::copy(factors.begin(), factors.end(), out.begin() + out[kFactorOffset]);
    for (uint32_t Y = 0; Y < (1u << S); ++Y)
        for (uint32_t X = 0; X < (1u << S); ++X)
            descendToSkipLevel(out.data(), 0, X, Y, &out[kHeaderWords + kSkipWords * ((Y << S) + X)]);
    for (uint32_t Y = 0; Y < (1u << B); ++Y) // after the skip entries and values it decodes from
        for (uint32_t X = 0; X < (1u << B); ++X)
            out[boundsOffset + (Y << B) + X] = cellBounds(out.data(), X, Y);
    out[kChecksum] = stat::checksumWords(out.data(), out.size(), kChecksum);
    if (statsOut) *statsOut = st;
    return out;
}

Result<std::vector<uint32_t>> encodeDAGMH(const DualDepthMap& map) {
    auto tree = buildMhTree(map);
    if (!tree) return fail(tree.error());
    return encodeDAGMH(*tree);
}

Result<void> validateDAGMH(const uint32_t* data, size_t size) {
    using namespace dagfmt;
    auto bad = [](const std::string& why) { return fail("DAG-MH: " + why); };
    if (!data || size < kHeaderWords)
        return bad("buffer of " + std::to_string(size) + " words is shorter than its header");
    if (data[kMagicWord] != kMagic) return bad("wrong magic");
    if (data[kVersion] != kVersionNumber)
        return bad("unsupported version " + std::to_string(data[kVersion]) + " (this build reads version " +
                   std::to_string(kVersionNumber) + ": rebake)");
    if (data[kTotalWords] != size)
        return bad("total words " + std::to_string(data[kTotalWords]) + " != buffer size " +
                   std::to_string(size));
    if (data[kChecksum] != stat::checksumWords(data, size, kChecksum)) return bad("checksum mismatch");
    if (data[kReserved] != 0) return bad("reserved header word is not 0");
    const uint32_t L = data[kLevels], res = data[kResolution], S = skipLevel(data), B = boundsLevel(data);
    if (L > 16 || res == 0 || res > (1u << L) || (L > 0 && res <= (1u << (L - 1))))
        return bad("resolution does not match levels");
    if (S > L || S > 8) return bad("skip level " + std::to_string(S) + " out of range");
    if (B < S || B > std::min<uint32_t>(L, 9) || (data[kSkipLevel] >> 16) != 0)
        return bad("bounds level " + std::to_string(B) + " out of range");
    const uint64_t numValues = data[kValues], numChunks = data[kChunks];
    if (numValues == 0 || numChunks != (numValues + kChunkValues - 1) / kChunkValues)
        return bad("value/chunk counts disagree");
    // Sections must follow each other exactly.
    uint64_t pos = kHeaderWords;
    auto section = [&](uint32_t field, uint64_t words) {
        bool ok = data[field] == pos;
        pos += words;
        return ok;
    };
    if (!section(kSkipOffset, (uint64_t(kSkipWords) << (2 * S)) + (uint64_t(1) << (2 * B))) ||
        !section(kNodeOffset, data[kNodeWords]) ||
        !section(kTreeletOffset, uint64_t(kTreeletWords) * data[kTreelets]) ||
        !section(kChunkOffset, kChunkWords * numChunks) || !section(kFactorOffset, data[kFactorWords]) ||
        pos != size)
        return bad("section offsets do not tile the buffer");
    // Treelets: only 85 bits used.
    const uint32_t* tl = data + data[kTreeletOffset];
    const uint32_t numTreelets = data[kTreelets];
    for (uint32_t t = 0; t < numTreelets; ++t)
        if (tl[3 * t + 2] >> 21) return bad("treelet " + std::to_string(t) + " uses bits past 85");
    auto treeletTotal = [&](uint32_t t) {
        return uint64_t(stat::popc(tl[3 * t]) + stat::popc(tl[3 * t + 1]) + stat::popc(tl[3 * t + 2]));
    };
    // Nodes: parsed in order; children point backwards, counts must add up.
    const uint32_t* nd = data + data[kNodeOffset];
    const uint32_t nodeWords = data[kNodeWords];
    std::vector<uint64_t> totalAt(nodeWords, 0);
    std::vector<uint8_t> isStart(nodeWords, 0);
    for (uint32_t p = 0; p < nodeWords;) {
        uint32_t flags = nd[p];
        if (flags >> 9) return bad("node " + std::to_string(p) + " has unknown flag bits");
        uint32_t cnt = 0;
        for (uint32_t c = 0; c < 4; ++c) {
            uint32_t t = (flags >> (2 * c)) & 3u;
            if (t == 3) return bad("node " + std::to_string(p) + " has child type 3");
            cnt += t != 0;
        }
        if (cnt == 0 || uint64_t(p) + 2 * cnt > nodeWords)
            return bad("node " + std::to_string(p) + " is empty or runs past the node array");
        uint64_t acc = (flags >> 8) & 1u;
        uint32_t rank = 0;
        for (uint32_t c = 0; c < 4; ++c) {
            uint32_t t = (flags >> (2 * c)) & 3u;
            if (!t) continue;
            if (rank > 0 && nd[p + cnt + rank] != acc)
                return bad("node " + std::to_string(p) + " prefix count mismatch");
            uint32_t ptr = nd[p + 1 + rank];
            if (t == 1) {
                if (ptr >= p || !isStart[ptr])
                    return bad("node " + std::to_string(p) + " points to a non-node");
                acc += totalAt[ptr];
            } else {
                if (ptr >= numTreelets) return bad("node " + std::to_string(p) + " points past the treelets");
                acc += treeletTotal(ptr);
            }
            ++rank;
        }
        if (acc > numValues) return bad("node " + std::to_string(p) + " counts more values than stored");
        isStart[p] = 1, totalAt[p] = acc;
        p += 2 * cnt;
    }
    const uint32_t rootKind = data[kRootKind], rootPtr = data[kRootPtr];
    if (rootKind == 1) {
        if (rootPtr >= nodeWords || !isStart[rootPtr] || !(nd[rootPtr] & 256u) ||
            totalAt[rootPtr] != numValues)
            return bad("root node invalid");
    } else if (rootKind == 2) {
        if (rootPtr >= numTreelets || !(tl[3 * rootPtr] & 1u) || treeletTotal(rootPtr) != numValues)
            return bad("root treelet invalid");
    } else {
        return bad("root kind " + std::to_string(rootKind));
    }
    // Skip list: must equal the traversal from the root.
    for (uint32_t Y = 0; Y < (1u << S); ++Y)
        for (uint32_t X = 0; X < (1u << S); ++X) {
            uint32_t expect[4];
            descendToSkipLevel(data, 0, X, Y, expect);
            const uint32_t* e = data + data[kSkipOffset] + kSkipWords * ((Y << S) + X);
            if (!std::equal(expect, expect + 4, e))
                return bad("skip entry (" + std::to_string(X) + "," + std::to_string(Y) +
                           ") differs from the tree");
        }
    // Chunks: bitmap within the chunk's values, bit width <= 32, factors inside the stream.
    const uint32_t* ch = data + data[kChunkOffset];
    const uint64_t factorBits = uint64_t(data[kFactorWords]) * 32u;
    for (uint64_t c = 0; c < numChunks; ++c) {
        const uint32_t* w = ch + kChunkWords * c;
        uint32_t count = uint32_t(std::min<uint64_t>(kChunkValues, numValues - c * kChunkValues));
        if (w[1] & ~stat::lowMask(count))
            return bad("chunk " + std::to_string(c) + " bitmap past its values");
        uint32_t b = w[5] & 63u;
        if (b > 32) return bad("chunk " + std::to_string(c) + " bit width " + std::to_string(b));
        if (uint64_t(w[5] >> 6) * 8u + uint64_t(stat::popc(w[1])) * b > factorBits)
            return bad("chunk " + std::to_string(c) + " factors past the stream");
    }
    // Value bounds: must equal the walk from each skip entry (last: it decodes values, so every section it
    // reads has been checked above).
    const uint32_t* bounds = data + data[kSkipOffset] + (uint64_t(kSkipWords) << (2 * S));
    for (uint32_t Y = 0; Y < (1u << B); ++Y)
        for (uint32_t X = 0; X < (1u << B); ++X)
            if (bounds[(Y << B) + X] != cellBounds(data, X, Y))
                return bad("value bounds of cell (" + std::to_string(X) + "," + std::to_string(Y) +
                           ") differ from its values");
    return {};
}

uint64_t dagmhCheckValues(const MhTree& tree, const uint32_t* data) {
    uint64_t bad = 0;
    uint32_t i = 0;
    std::vector<std::array<uint32_t, 2>> pos = nodeCorners(tree);
    for (size_t n = 0; n < tree.nodes.size(); ++n) {
        const auto& nd = tree.nodes[n];
        if (!nd.valued) continue;
        uint32_t v = dagmhValue(data, 0, i++, pos[n][0], pos[n][1]);
        bad += v < nd.lo || v > nd.hi;
    }
    return bad;
}

stat::ByteBreakdown breakdownDAGMH(const uint32_t* data, size_t size) {
    using namespace dagfmt;
    stat::ByteBreakdown b;
    b.header = kHeaderWords * 4u;
    if (size < kHeaderWords) return b;
    b.skipList = (uint64_t(kSkipWords) << (2 * skipLevel(data))) * 4u;
    b.bounds = (uint64_t(1) << (2 * boundsLevel(data))) * 4u;
    b.nodes = uint64_t(data[kNodeWords]) * 4u;
    b.treelets = uint64_t(data[kTreelets]) * kTreeletWords * 4u;
    b.values = uint64_t(data[kChunks]) * kChunkWords * 4u;
    b.factors = uint64_t(data[kFactorWords]) * 4u;
    return b;
}

} // namespace ml
