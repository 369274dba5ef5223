// MH construction, serialization and validation (see mh.h for the algorithm and the layout).
#include "shadows/static/mh.h"

#include <algorithm>
#include <string>

namespace ml {

size_t MhTree::valuedCount() const {
    size_t n = 0;
    for (const Node& node : nodes) n += node.valued;
    return n;
}

namespace {

struct Pyramid {
    // Per level l (resolution 2^l): interval bounds and flags (bit 0: keeps its value, bit 1: has a
    // present descendant).
    std::vector<std::vector<uint32_t>> lo, hi;
    std::vector<std::vector<uint8_t>> flags;
};

// The point covered by the most of the 4 intervals; returns the covering subset as a 4-bit mask.
// Ties: the widest intersection, then the lowest mask candidate order (child 0 first).
uint32_t bestSubset(const uint32_t lo[4], const uint32_t hi[4]) {
    uint32_t bestMask = 1, bestCount = 0;
    uint64_t bestWidth = 0;
    for (int k = 0; k < 4; ++k) {
        uint32_t p = lo[k], mask = 0, count = 0, l = 0, h = 0xFFFFFFFFu;
        for (int i = 0; i < 4; ++i)
            if (lo[i] <= p && p <= hi[i])
                mask |= 1u << i, ++count, l = std::max(l, lo[i]), h = std::min(h, hi[i]);
        uint64_t width = uint64_t(h) - l;
        if (count > bestCount || (count == bestCount && width > bestWidth))
            bestMask = mask, bestCount = count, bestWidth = width;
    }
    return bestMask;
}

// Preorder nodes of the pyramid's subtree at (level, x, y); node depths are level + depthOffset.
int32_t buildNodes(const Pyramid& pyr, uint32_t level, uint32_t x, uint32_t y, uint32_t depthOffset,
                   std::vector<MhTree::Node>& out) {
    uint32_t n = 1u << level;
    size_t i = size_t(y) * n + x;
    int32_t index = int32_t(out.size());
    MhTree::Node node;
    node.lo = pyr.lo[level][i], node.hi = pyr.hi[level][i];
    node.valued = (pyr.flags[level][i] & 1u) ? 1 : 0;
    node.depth = uint8_t(level + depthOffset);
    out.push_back(node);
    if (pyr.flags[level][i] & 2u) {
        uint32_t cn = n * 2;
        for (uint32_t c = 0; c < 4; ++c) {
            uint32_t cx = 2 * x + (c & 1u), cy = 2 * y + (c >> 1);
            if (pyr.flags[level + 1][size_t(cy) * cn + cx] & 3u) {
                int32_t ci = buildNodes(pyr, level + 1, cx, cy, depthOffset, out);
                out[index].child[c] = ci;
            }
        }
    }
    return index;
}

// The bottom-up pass over a pyramid whose finest level L is filled: levels L-1 .. 0.
void reducePyramid(Pyramid& pyr, uint32_t L) {
    for (uint32_t l = L; l > 0; --l) {
        const uint32_t pn = 1u << (l - 1);
        pyr.lo[l - 1].resize(size_t(pn) * pn), pyr.hi[l - 1].resize(size_t(pn) * pn);
        pyr.flags[l - 1].assign(size_t(pn) * pn, 1u);
        mhbuild::reduceLevel(1u << l, pyr.lo[l].data(), pyr.hi[l].data(), pyr.flags[l].data(),
                             pyr.lo[l - 1].data(), pyr.hi[l - 1].data(), pyr.flags[l - 1].data());
    }
}

} // namespace

namespace mhbuild {

void reduceLevel(uint32_t n, const uint32_t* clo, const uint32_t* chi, uint8_t* cfl, uint32_t* plo,
                 uint32_t* phi, uint8_t* pfl) {
    const uint32_t pn = n / 2;
    for (uint32_t py = 0; py < pn; ++py)
        for (uint32_t px = 0; px < pn; ++px) {
            size_t ci[4];
            uint32_t lo[4], hi[4];
            for (uint32_t c = 0; c < 4; ++c) {
                ci[c] = size_t(2 * py + (c >> 1)) * n + 2 * px + (c & 1u);
                lo[c] = clo[ci[c]], hi[c] = chi[ci[c]];
            }
            uint32_t mask = bestSubset(lo, hi);
            uint32_t l0 = 0, h0 = 0xFFFFFFFFu;
            uint8_t below = 0;
            for (uint32_t c = 0; c < 4; ++c) {
                if (mask & (1u << c)) l0 = std::max(l0, lo[c]), h0 = std::min(h0, hi[c]), cfl[ci[c]] &= ~1u;
                if (cfl[ci[c]] & 3u) below = 2;
            }
            size_t pi = size_t(py) * pn + px;
            plo[pi] = l0, phi[pi] = h0;
            pfl[pi] = uint8_t(1u | below);
        }
}

Result<Subtree> buildSubtree(uint32_t size, const uint32_t* lo, const uint32_t* hi, uint32_t depthOffset) {
    uint32_t L = 0;
    while ((1u << L) < size) ++L;
    if ((1u << L) != size) return fail("MH: tile side " + std::to_string(size) + " is not a power of two");
    Pyramid pyr;
    pyr.lo.resize(L + 1), pyr.hi.resize(L + 1), pyr.flags.resize(L + 1);
    pyr.lo[L].assign(lo, lo + size_t(size) * size), pyr.hi[L].assign(hi, hi + size_t(size) * size);
    pyr.flags[L].assign(size_t(size) * size, 1u);
    reducePyramid(pyr, L);
    Subtree t;
    t.lo = pyr.lo[0][0], t.hi = pyr.hi[0][0], t.flags = pyr.flags[0][0];
    buildNodes(pyr, 0, 0, 0, depthOffset, t.nodes);
    return t;
}

} // namespace mhbuild

Result<MhTree> buildMhTree(const DualDepthMap& map) {
    const uint32_t res = map.resolution;
    if (res == 0 || res > (1u << 16))
        return fail("MH: resolution " + std::to_string(res) + " outside 1..65536");
    if (map.enter.size() != size_t(res) * res || map.exit.size() != map.enter.size())
        return fail("MH: dual depth map holds " + std::to_string(map.enter.size()) +
                    " texels, expected res^2");
    uint32_t L = 0;
    while ((1u << L) < res) ++L;
    Pyramid pyr;
    pyr.lo.resize(L + 1), pyr.hi.resize(L + 1), pyr.flags.resize(L + 1);
    {
        uint32_t n = 1u << L;
        auto& lo = pyr.lo[L];
        auto& hi = pyr.hi[L];
        lo.assign(size_t(n) * n, 0u), hi.assign(size_t(n) * n, 0xFFFFFFFFu); // don't care outside
        pyr.flags[L].assign(size_t(n) * n, 1u);
        for (uint32_t y = 0; y < res; ++y)
            for (uint32_t x = 0; x < res; ++x) {
                uint32_t e = map.enter[size_t(y) * res + x], f = map.exit[size_t(y) * res + x];
                lo[size_t(y) * n + x] = e;
                hi[size_t(y) * n + x] = std::max(e, f); // a malformed exit < enter keeps just enter
            }
    }
    reducePyramid(pyr, L);
    MhTree tree;
    tree.resolution = res, tree.levels = L;
    buildNodes(pyr, 0, 0, 0, 0, tree.nodes);
    return tree;
}

namespace mhfmt {

namespace {
uint32_t childFlags(const MhTree& tree, int32_t n) {
    uint32_t f = 0;
    for (uint32_t c = 0; c < 4; ++c) {
        int32_t ch = tree.nodes[n].child[c];
        if (ch >= 0) f |= tree.nodes[ch].type() << (2 * c);
    }
    return f;
}
} // namespace

Result<std::vector<uint32_t>> serialize(const MhTree& tree, const std::vector<uint32_t>& value,
                                        const std::vector<int32_t>* redirect,
                                        const std::vector<uint8_t>* skip, uint32_t magic,
                                        std::vector<uint32_t>* headerPos, std::vector<uint32_t>* groupPos) {
    const size_t count = tree.nodes.size();
    std::vector<uint32_t> hpos(count, 0), gpos(count, 0);
    std::vector<uint32_t> nodes;
    std::vector<int32_t> pending; // redirected inner nodes, patched at the end
    uint32_t valued = 0, inner = 0;
    const MhTree::Node& root = tree.nodes[0];
    nodes.push_back(value[0]), ++valued;
    if (root.inner()) hpos[0] = uint32_t(nodes.size()), nodes.push_back(0), ++inner;
    // Iterative preorder over inner nodes: emit each one's child group, then its inner children.
    std::vector<int32_t> stack;
    if (root.inner()) stack.push_back(0);
    while (!stack.empty()) {
        int32_t n = stack.back();
        stack.pop_back();
        gpos[n] = uint32_t(nodes.size());
        const MhTree::Node& node = tree.nodes[n];
        for (uint32_t c = 0; c < 4; ++c) {
            int32_t ch = node.child[c];
            if (ch < 0) continue;
            const MhTree::Node& cn = tree.nodes[ch];
            if (cn.valued) nodes.push_back(value[ch]), ++valued;
            if (cn.inner()) hpos[ch] = uint32_t(nodes.size()), nodes.push_back(0), ++inner;
        }
        for (int c = 3; c >= 0; --c) {
            int32_t ch = node.child[c];
            if (ch < 0 || !tree.nodes[ch].inner()) continue;
            if (redirect && (*redirect)[ch] >= 0)
                pending.push_back(ch);
            else
                stack.push_back(ch);
        }
        if (skip) (void)skip; // skipped nodes are never reached: their parents are redirected
    }
    auto patch = [&](int32_t n, uint32_t target) -> Result<void> {
        uint32_t h = hpos[n];
        if (target <= h || target - h > kMaxOffset)
            return fail("MH: child offset " + std::to_string(int64_t(target) - int64_t(h)) +
                        " does not fit 24 bits");
        nodes[h] = childFlags(tree, n) | (target - h) << 8;
        return {};
    };
    for (size_t n = 0; n < count; ++n) {
        if (!tree.nodes[n].inner() || (skip && (*skip)[n])) continue;
        if (redirect && (*redirect)[n] >= 0) continue;
        if (n != 0 && hpos[n] == 0) continue; // not reached (inside a redirected subtree)
        if (auto r = patch(int32_t(n), gpos[n]); !r) return fail(r.error());
    }
    for (int32_t n : pending)
        if (auto r = patch(n, gpos[(*redirect)[n]]); !r) return fail(r.error());
    std::vector<uint32_t> out(kHeaderWords, 0u);
    out[kMagic] = magic, out[kVersion] = 1, out[kResolution] = tree.resolution, out[kLevels] = tree.levels;
    out[kRootType] = root.inner() ? 2u : 1u, out[kNodeOffset] = kHeaderWords;
    out[kNodeWords] = uint32_t(nodes.size()), out[kTotalWords] = uint32_t(kHeaderWords + nodes.size());
    out[kValued] = valued, out[kInnerRecords] = inner;
    out.insert(out.end(), nodes.begin(), nodes.end());
    out[kChecksum] = stat::checksumWords(out.data(), out.size(), kChecksum);
    if (headerPos) *headerPos = std::move(hpos);
    if (groupPos) *groupPos = std::move(gpos);
    return out;
}

Result<void> validate(const uint32_t* data, size_t size, uint32_t magic) {
    if (!data || size < kHeaderWords)
        return fail("MH: buffer of " + std::to_string(size) + " words is shorter than its header");
    if (data[kMagic] != magic) return fail("MH: wrong magic");
    if (data[kVersion] != 1) return fail("MH: unsupported version " + std::to_string(data[kVersion]));
    if (data[kTotalWords] != size)
        return fail("MH: total words " + std::to_string(data[kTotalWords]) + " != buffer size " +
                    std::to_string(size));
    if (data[kChecksum] != stat::checksumWords(data, size, kChecksum)) return fail("MH: checksum mismatch");
    uint32_t L = data[kLevels], res = data[kResolution];
    if (L > 16 || res == 0 || res > (1u << L) || (L > 0 && res <= (1u << (L - 1))))
        return fail("MH: resolution " + std::to_string(res) + " does not match " + std::to_string(L) +
                    " levels");
    if (data[kNodeOffset] != kHeaderWords || uint64_t(kHeaderWords) + data[kNodeWords] != size)
        return fail("MH: node array does not fill the buffer");
    if (data[kReserved] != 0) return fail("MH: reserved header word is not 0");
    // Every node word is a value or a child header: the two counts must add up to the node array (the
    // byte breakdown subtracts one from the other; a forged count must not wrap it).
    if (data[kValued] == 0 || uint64_t(data[kValued]) + data[kInnerRecords] != data[kNodeWords])
        return fail("MH: " + std::to_string(data[kValued]) + " values and " +
                    std::to_string(data[kInnerRecords]) + " child headers do not make the " +
                    std::to_string(data[kNodeWords]) + " node words");
    const uint32_t begin = kHeaderWords, end = uint32_t(size);
    uint32_t rootType = data[kRootType];
    if (rootType != 1 && rootType != 2) return fail("MH: bad root type " + std::to_string(rootType));
    if (begin + rootType > end) return fail("MH: root record past the end");
    if (rootType == 1) {
        if (data[kNodeWords] != 1) return fail("MH: a leaf root must be the only node word");
        return {};
    }
    // Walk every reachable header once (MMH groups are shared: visited marks keep this linear).
    std::vector<uint8_t> seen(size, 0);
    std::vector<uint32_t> stack{begin + 1};
    seen[begin + 1] = 1;
    while (!stack.empty()) {
        uint32_t hp = stack.back();
        stack.pop_back();
        uint32_t hdr = data[hp], off = hdr >> 8;
        if (off == 0) return fail("MH: zero child offset at word " + std::to_string(hp));
        uint64_t q = uint64_t(hp) + off, groupSize = 0;
        for (uint32_t c = 0; c < 4; ++c) groupSize += (0x64u >> (2u * ((hdr >> (2u * c)) & 3u))) & 3u;
        if (groupSize == 0) return fail("MH: inner record without children at word " + std::to_string(hp));
        if (q + groupSize > end)
            return fail("MH: child group of word " + std::to_string(hp) + " past the end");
        for (uint32_t c = 0; c < 4; ++c) {
            uint32_t t = (hdr >> (2u * c)) & 3u;
            if (t >= 2) {
                uint32_t h = uint32_t(q) + (t == 2 ? 1u : 0u);
                if (!seen[h]) seen[h] = 1, stack.push_back(h);
            }
            q += (0x64u >> (2u * t)) & 3u;
        }
    }
    return {};
}

stat::ByteBreakdown breakdown(const uint32_t* data, size_t size) {
    stat::ByteBreakdown b;
    b.header = kHeaderWords * 4u;
    if (size < kHeaderWords) return b;
    b.values = uint64_t(data[kValued]) * 4u;
    b.nodes = uint64_t(data[kNodeWords]) * 4u - b.values;
    return b;
}

} // namespace mhfmt

Result<std::vector<uint32_t>> encodeMH(const MhTree& tree) {
    std::vector<uint32_t> value(tree.nodes.size());
    for (size_t i = 0; i < tree.nodes.size(); ++i)
        value[i] = stat::midpoint(tree.nodes[i].lo, tree.nodes[i].hi);
    return mhfmt::serialize(tree, value, nullptr, nullptr, mhfmt::kMagicMH);
}

Result<std::vector<uint32_t>> encodeMH(const DualDepthMap& map) {
    auto tree = buildMhTree(map);
    if (!tree) return fail(tree.error());
    return encodeMH(*tree);
}

Result<void> validateMH(const uint32_t* data, size_t size) {
    return mhfmt::validate(data, size, mhfmt::kMagicMH);
}
stat::ByteBreakdown breakdownMH(const uint32_t* data, size_t size) {
    return mhfmt::breakdown(data, size);
}

} // namespace ml
