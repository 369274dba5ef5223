// DAG-MH construction (DAG + treelets + skip list + chunked values) and validation; see dagmh.h and
// docs/dagmh-encoding.md.
#include "shadows/static/dagmh.h"

#include "shadows/static/dagmh_values.h"

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
    DagmhHeader h = dagmhHeader(data, 0u);

    // Adds value `vlast`, held by the node at depth `dlast` above the node (nx, ny) at depth `depth`, for
    // the texels of that node's cell inside the bounds cell. A plane value is smallest and largest at
    // corners of that block (the plane's floor is monotone in x and in y).
    void take(uint32_t vlast, uint32_t dlast, uint32_t depth, uint32_t nx, uint32_t ny) {
        const uint32_t s = depth - dlast, px = (nx >> s) << (L - dlast), py = (ny >> s) << (L - dlast);
        if (vlast == memoIndex) {
            lo = std::min(lo, memoValue), hi = std::max(hi, memoValue);
            return;
        }
        const dagtwin::DagmhChunk c = dagtwin::dagmhChunk(data, h, vlast >> 5u);
        if (!dagmhSlotPlanar(c, vlast & 31u)) {
            memoIndex = vlast;
            memoValue = dagtwin::dagmhChunkValue(data, h, c, vlast & 31u, px, py, px, py);
            lo = std::min(lo, memoValue), hi = std::max(hi, memoValue);
            return;
        }
        // The node's cell at `depth` clipped to the bounds cell (X, Y) at level B.
        const uint32_t side = depth >= B ? 1u << (L - depth) : 1u << (L - B);
        const uint32_t x0 = depth >= B ? nx << (L - depth) : X << (L - B);
        const uint32_t y0 = depth >= B ? ny << (L - depth) : Y << (L - B);
        for (uint32_t k = 0; k < 4; ++k) {
            const uint32_t v =
                dagtwin::dagmhChunkValue(data, h, c, vlast & 31u, px, py, x0 + (k & 1u ? side - 1u : 0u),
                                         y0 + (k & 2u ? side - 1u : 0u));
            lo = std::min(lo, v), hi = std::max(hi, v);
        }
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
    // ---- values, in preorder (= node index order), chunks of 32 (dagmh_values.h) ----
    std::vector<dagval::Val> vals;
    {
        std::vector<std::array<uint32_t, 2>> pos = nodeCorners(tree);
        for (size_t i = 0; i < n; ++i)
            if (tree.nodes[i].valued) {
                const auto& nd = tree.nodes[i];
                if (nd.planarOnly() && (nd.plane == 0 || nd.plane > tree.planes.size()))
                    return fail("DAG-MH: node " + std::to_string(i) + " has an empty interval and no plane");
                vals.push_back({nd.lo, nd.hi, pos[i][0], pos[i][1], nd.planarOnly() ? nd.plane : 0u});
            }
    }
    const uint32_t numValues = uint32_t(vals.size());
    const uint32_t numChunks = (numValues + kChunkValues - 1) / kChunkValues;
    dagval::Stats vst;
    auto sections = dagval::encodeValues(vals, tree.planes, &vst);
    if (!sections) return fail(sections.error());
    const std::vector<uint32_t>&chunks = sections->chunks, &slopes = sections->slopes,
          &planes = sections->planes, &factors = sections->factors;
    st.rawChunks = vst.rawClasses, st.factors = vst.factors, st.factorBits = vst.factorBits;
    st.planarValues = vst.planarValues, st.planes = planes.size() / kPlaneWords;
    st.slopes = slopes.size() / kSlopeWords;
    st.chunks = numChunks;
    // ---- assemble ----
    // Skip level: the deepest S <= min(L, 8) whose list (16 B per cell) stays within an eighth of the
    // rest of the structure. Each level it resolves saves a lookup one dependent node read (flags,
    // child, count), so dense maps take it as deep as the budget allows; nearly empty maps keep a
    // short list.
    const uint64_t restWords = nodeWords.size() + uint64_t(kTreeletWords) * treelets.size() +
                               uint64_t(chunks.size()) + slopes.size() + planes.size() + factors.size();
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
    out[kSlopeOffset] = out[kChunkOffset] + uint32_t(chunks.size());
    out[kSlopes] = uint32_t(slopes.size() / kSlopeWords);
    out[kPlaneOffset] = out[kSlopeOffset] + uint32_t(slopes.size());
    out[kPlanes] = uint32_t(planes.size() / kPlaneWords);
    out[kFactorOffset] = out[kPlaneOffset] + uint32_t(planes.size());
    out[kFactorWords] = uint32_t(factors.size());
    out[kTotalWords] = out[kFactorOffset] + out[kFactorWords];
    out.resize(out[kTotalWords], 0);
    std::copy(nodeWords.begin(), nodeWords.end(), out.begin() + out[kNodeOffset]);
    for (size_t t = 0; t < treelets.size(); ++t)
        std::copy(treelets[t].begin(), treelets[t].end(),
                  out.begin() + out[kTreeletOffset] + kTreeletWords * t);
    std::copy(chunks.begin(), chunks.end(), out.begin() + out[kChunkOffset]);
    std::copy(slopes.begin(), slopes.end(), out.begin() + out[kSlopeOffset]);
    std::copy(planes.begin(), planes.end(), out.begin() + out[kPlaneOffset]);
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
    auto tree = buildMhTree(map, true); // planar where the map has its enter planes

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
    if (L > kMhMaxLevels || res == 0 || res > (1u << L) || (L > 0 && res <= (1u << (L - 1))))
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
        !section(kChunkOffset, uint64_t(chunkWords(data[kPlanes])) * numChunks) ||
        !section(kSlopeOffset, uint64_t(kSlopeWords) * data[kSlopes]) ||
        !section(kPlaneOffset, uint64_t(kPlaneWords) * data[kPlanes]) ||
        !section(kFactorOffset, data[kFactorWords]) || pos != size)
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
    // Chunks: bitmap within the chunk's values, widths <= 32, slope entries in the table, factors inside
    // the stream (which a uint32 bit position must address).
    if (data[kSlopes] == 0 || data[kSlopes] > kMaxSlopes) return bad("slope table size out of range");
    const uint32_t* slopes = data + data[kSlopeOffset];
    if (slopes[0] != 0 || slopes[1] != 0) return bad("slope entry 0 is not zero");
    if (data[kPlanes] > kMaxPlanes) return bad("plane table size out of range");
    if (uint64_t(data[kFactorWords]) * 32u > kMaxFactorBits + 64) return bad("factor stream too long");
    const uint32_t* ch = data + data[kChunkOffset];
    const uint64_t factorBits = uint64_t(data[kFactorWords]) * 32u;
    for (uint64_t c = 0; c < numChunks; ++c) {
        const uint32_t* w = ch + chunkWords(data[kPlanes]) * c;
        const uint32_t count = uint32_t(std::min<uint64_t>(kChunkValues, numValues - c * kChunkValues));
        const std::string name = "chunk " + std::to_string(c);
        if (w[0] & ~stat::lowMask(count)) return bad(name + " class bitmap past its values");
        if (w[3] >> 22) return bad(name + " has unknown width bits");
        const uint32_t b0 = w[3] & 63u, b1 = (w[3] >> 11) & 63u;
        if (b0 > 32 || b1 > 32) return bad(name + " bit width over 32");
        if ((w[5] & 0xFFFFu) >= data[kSlopes] || (w[5] >> 16) >= data[kSlopes])
            return bad(name + " slope entry past the table");
        const bool planarChunk = data[kPlanes] != 0;
        const uint32_t pm = planarChunk ? w[6] : 0u, pw = planarChunk ? w[7] : 0u;
        const uint32_t bp = pw >> kPlanarWidthShift, base = pw & stat::lowMask(kPlanarWidthShift);
        if (pm & ~stat::lowMask(count)) return bad(name + " planar bitmap past its values");
        if (w[0] & pm) return bad(name + " has a plane slot in class 1");
        if (bp > kPlanarWidthShift || (pm == 0 && pw != 0))
            return bad(name + " plane index width out of range");
        const uint64_t np = stat::popc(pm), n1 = stat::popc(w[0]);
        if (uint64_t(w[4]) + np * bp + n1 * b1 + (count - n1 - np) * b0 > factorBits)
            return bad(name + " factors past the stream");
        const DagmhHeader h = dagmhHeader(data, 0u);
        for (uint64_t r = 0; r < np; ++r) // every plane slot's plane inside the table
            if (uint64_t(base) + dagtwin::dagmhField(data, h, uint32_t(w[4] + r * bp), bp) >= data[kPlanes])
                return bad(name + " names a plane past the table");
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
    const DagmhHeader h = dagmhHeader(data, 0u);
    for (size_t n = 0; n < tree.nodes.size(); ++n) {
        const auto& nd = tree.nodes[n];
        if (!nd.valued) continue;
        const uint32_t px = pos[n][0], py = pos[n][1];
        if (nd.planarOnly()) {
            // A plane value: its plane's value at the cell's corners (the texels in between lie on it too).
            const uint32_t e = px + (1u << (tree.levels - nd.depth)) - 1u,
                           f = py + (1u << (tree.levels - nd.depth)) - 1u;
            const DepthPlane& q = tree.planes[nd.plane - 1];
            bool ok = true;
            for (uint32_t c = 0; c < 4; ++c) {
                const uint32_t x = c & 1u ? e : px, y = c & 2u ? f : py;
                ok = ok && int64_t(dagmhValue(data, h, i, px, py, x, y)) == q.at(x, y);
            }
            bad += !ok, ++i;
            continue;
        }
        uint32_t v = dagmhValue(data, h, i++, px, py, px, py);
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
    b.values = (uint64_t(data[kChunks]) * chunkWords(data[kPlanes]) + uint64_t(data[kSlopes]) * kSlopeWords +
                uint64_t(data[kPlanes]) * kPlaneWords) *
               4u; // chunks, slopes, planes
    b.factors = uint64_t(data[kFactorWords]) * 4u;
    return b;
}

} // namespace ml
