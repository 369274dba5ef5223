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
    const uint32_t S = data[base + kSkipLevel];
    const uint32_t nodes = base + data[base + kNodeOffset];
    uint32_t kind = data[base + kRootKind], ptr = data[base + kRootPtr], depth = 0, vcount = 0, vlast = 0;
    while (kind == 1u && depth < S) {
        uint32_t flags = data[nodes + ptr];
        if ((flags & 256u) != 0u) vlast = vcount;
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
    out[0] = kind | depth << 8u, out[1] = ptr, out[2] = vcount, out[3] = vlast;
}

} // namespace dagfmt

namespace {

// ---- value chunks (docs/dagmh-encoding.md) ----

struct ChunkCode {
    uint32_t rep = 0, bitmap = 0, cl = 0, cf = 0, b = 0;
    std::vector<uint32_t> k; // factor per set bit, in bit order
};

// Smallest b (0..31, else 32 = raw) with c_l + c_f * k_i in [lo_i, hi_i], 0 <= k_i < 2^b, for all i.
// Two lattices are tried for each b, smallest b first: the exact one through every lower bound
// (c_f = gcd), and c_l = min lo, c_f = ceil(span / (2^b - 1)), k_i = ceil((lo_i - c_l) / c_f), which
// uses the interval widths; every k_i is in range by construction and membership in [lo_i, hi_i] is
// checked with the decoder's arithmetic.
void fitFactors(const std::vector<uint32_t>& lo, const std::vector<uint32_t>& hi, ChunkCode& out) {
    const size_t m = lo.size();
    out.k.assign(m, 0);
    if (m == 0) return;
    uint32_t minLo = *std::min_element(lo.begin(), lo.end()), maxLo = *std::max_element(lo.begin(), lo.end());
    uint32_t minHi = *std::min_element(hi.begin(), hi.end());
    if (maxLo <= minHi) { // one common point: 0 bits
        out.b = 0, out.cl = maxLo, out.cf = 0;
        return;
    }
    const uint64_t span = uint64_t(maxLo) - minLo;
    // Lattice through every lower bound: c_f = G = gcd(lo_i - min lo), k_i = (lo_i - min lo) / G decodes
    // to lo_i exactly. Depths that came from float interpolation are multiples of a power of two, so
    // G often removes several low bits. Bits needed: b_G = bits(span / G).
    uint32_t G = 0;
    for (size_t i = 0; i < m; ++i) G = std::gcd(G, lo[i] - minLo);
    uint32_t bG = uint32_t(std::bit_width(uint32_t(span / G)));
    for (uint32_t b = 1; b <= 31; ++b) {
        if (b >= bG) {
            out.b = bG, out.cl = minLo, out.cf = G;
            for (size_t i = 0; i < m; ++i) out.k[i] = (lo[i] - minLo) / G;
            return;
        }
        uint64_t steps = (uint64_t(1) << b) - 1u;
        uint64_t g = std::max<uint64_t>(1, (span + steps - 1) / steps);
        if (g > 0xFFFFFFFFull) continue;
        bool ok = true;
        for (size_t i = 0; i < m && ok; ++i) {
            uint64_t k = (uint64_t(lo[i]) - minLo + g - 1) / g;
            uint64_t v = uint64_t(minLo) + g * k;
            uint32_t decoded = minLo + uint32_t(g) * uint32_t(k); // the decoder's uint32 arithmetic
            ok = k <= steps && v <= hi[i] && decoded == v && decoded >= lo[i];
            out.k[i] = uint32_t(k);
        }
        if (ok) {
            out.b = b, out.cl = minLo, out.cf = uint32_t(g);
            return;
        }
    }
    out.b = 32, out.cl = 0, out.cf = 1; // raw fallback: the value itself
    for (size_t i = 0; i < m; ++i) out.k[i] = lo[i];
}

// The representative is the point covered by the most intervals; every distinct maximal-coverage
// subset is tried and the one whose remaining values need the fewest factor bits wins.
ChunkCode encodeChunk(const uint32_t* lo, const uint32_t* hi, uint32_t count) {
    uint32_t bestCov = 0;
    std::vector<std::pair<uint32_t, uint32_t>> cands; // (mask, point)
    for (uint32_t i = 0; i < count; ++i) {
        uint32_t p = lo[i], mask = 0, cov = 0;
        for (uint32_t j = 0; j < count; ++j)
            if (lo[j] <= p && p <= hi[j]) mask |= 1u << j, ++cov;
        if (cov > bestCov) bestCov = cov, cands.clear();
        if (cov == bestCov) cands.push_back({mask, p});
    }
    std::sort(cands.begin(), cands.end());
    cands.erase(std::unique(cands.begin(), cands.end(), [](auto& a, auto& b) { return a.first == b.first; }),
                cands.end());
    ChunkCode best;
    uint64_t bestBits = UINT64_MAX;
    std::vector<uint32_t> rl, rh;
    for (auto [mask, p] : cands) {
        rl.clear(), rh.clear();
        for (uint32_t j = 0; j < count; ++j)
            if (!(mask & (1u << j))) rl.push_back(lo[j]), rh.push_back(hi[j]);
        ChunkCode c;
        // A point in the intersection of the covered intervals: the largest lo among them (p itself).
        c.rep = p;
        c.bitmap = ~mask & stat::lowMask(count);
        fitFactors(rl, rh, c);
        uint64_t bits = uint64_t(rl.size()) * c.b;
        if (bits < bestBits) bestBits = bits, best = std::move(c);
    }
    return best;
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
    std::vector<uint32_t> vlo, vhi;
    for (const auto& nd : tree.nodes)
        if (nd.valued) vlo.push_back(nd.lo), vhi.push_back(nd.hi);
    const uint32_t numValues = uint32_t(vlo.size());
    const uint32_t numChunks = (numValues + kChunkValues - 1) / kChunkValues;
    std::vector<uint32_t> chunks(size_t(numChunks) * kChunkWords, 0), factors;
    uint64_t bitPos = 0;
    for (uint32_t c = 0; c < numChunks; ++c) {
        uint32_t count = std::min(kChunkValues, numValues - c * kChunkValues);
        ChunkCode code = encodeChunk(&vlo[size_t(c) * kChunkValues], &vhi[size_t(c) * kChunkValues], count);
        bitPos = (bitPos + 7) / 8 * 8;
        if (bitPos / 8 >= kMaxFactorBytes) return fail("DAG-MH: factor stream exceeds 64 MiB");
        uint32_t* w = &chunks[size_t(c) * kChunkWords];
        w[0] = code.rep, w[1] = code.bitmap, w[2] = code.cl, w[3] = code.cf;
        w[4] = code.b | uint32_t(bitPos / 8) << 6;
        st.rawChunks += code.b == 32;
        st.factors += code.k.size();
        for (uint32_t k : code.k) {
            for (uint32_t bit = 0; bit < code.b; ++bit, ++bitPos) {
                if ((bitPos >> 5) >= factors.size()) factors.push_back(0);
                if ((k >> bit) & 1u) factors[bitPos >> 5] |= 1u << (bitPos & 31);
            }
        }
        st.factorBits += uint64_t(code.k.size()) * code.b;
    }
    if (factors.size() < (bitPos + 31) / 32) factors.resize((bitPos + 31) / 32, 0);
    st.chunks = numChunks;
    // ---- assemble ----
    const uint32_t S = uint32_t(std::clamp<int32_t>(int32_t(L) - 7, 0, 6));
    const uint32_t skipEntries = 1u << (2 * S);
    std::vector<uint32_t> out(kHeaderWords, 0);
    out[kMagicWord] = kMagic, out[kVersion] = 1, out[kResolution] = tree.resolution, out[kLevels] = L;
    out[kSkipLevel] = S, out[kRootKind] = refKind[0], out[kRootPtr] = refPtr[0];
    out[kValues] = numValues, out[kChunks] = numChunks;
    out[kSkipOffset] = kHeaderWords;
    out[kNodeOffset] = out[kSkipOffset] + skipEntries * kSkipWords;
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
    if (data[kVersion] != 1) return bad("unsupported version " + std::to_string(data[kVersion]));
    if (data[kTotalWords] != size)
        return bad("total words " + std::to_string(data[kTotalWords]) + " != buffer size " +
                   std::to_string(size));
    if (data[kChecksum] != stat::checksumWords(data, size, kChecksum)) return bad("checksum mismatch");
    const uint32_t L = data[kLevels], res = data[kResolution], S = data[kSkipLevel];
    if (L > 16 || res == 0 || res > (1u << L) || (L > 0 && res <= (1u << (L - 1))))
        return bad("resolution does not match levels");
    if (S > L || S > 8) return bad("skip level " + std::to_string(S) + " out of range");
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
    if (!section(kSkipOffset, uint64_t(kSkipWords) << (2 * S)) || !section(kNodeOffset, data[kNodeWords]) ||
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
        uint32_t b = w[4] & 63u;
        if (b > 32) return bad("chunk " + std::to_string(c) + " bit width " + std::to_string(b));
        if (uint64_t(w[4] >> 6) * 8u + uint64_t(stat::popc(w[1])) * b > factorBits)
            return bad("chunk " + std::to_string(c) + " factors past the stream");
    }
    return {};
}

stat::ByteBreakdown breakdownDAGMH(const uint32_t* data, size_t size) {
    using namespace dagfmt;
    stat::ByteBreakdown b;
    b.header = kHeaderWords * 4u;
    if (size < kHeaderWords) return b;
    b.skipList = (uint64_t(kSkipWords) << (2 * data[kSkipLevel])) * 4u;
    b.nodes = uint64_t(data[kNodeWords]) * 4u;
    b.treelets = uint64_t(data[kTreelets]) * kTreeletWords * 4u;
    b.values = uint64_t(data[kChunks]) * kChunkWords * 4u;
    b.factors = uint64_t(data[kFactorWords]) * 4u;
    return b;
}

} // namespace ml
