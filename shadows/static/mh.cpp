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
    std::vector<std::vector<uint32_t>> plane; // planar builds only (mhbuild::reduceLevel's planes)
};

// The point covered by the most of the 4 intervals; returns the covering subset as a 4-bit mask and its
// size in `covered`. Ties: the widest intersection, then the lowest mask candidate order (child 0 first).
// Empty intervals (lo > hi: a planar tree's plane-only nodes) cover no point and are never candidates;
// all four empty gives mask 0. A plain tree has none, so its choice is the rule without that clause.
uint32_t bestSubset(const uint32_t lo[4], const uint32_t hi[4], uint32_t& covered) {
    // All four share a point (empty cells, closed slabs): the loop below would find all four at the
    // first candidate with the greatest lo, and every such candidate has the same width. (An empty
    // interval makes max lo > min hi, so this never takes one.)
    covered = 4;
    if (std::max(std::max(lo[0], lo[1]), std::max(lo[2], lo[3])) <=
        std::min(std::min(hi[0], hi[1]), std::min(hi[2], hi[3])))
        return 15u;
    uint32_t bestMask = 0, bestCount = 0;
    uint64_t bestWidth = 0;
    for (int k = 0; k < 4; ++k) {
        if (lo[k] > hi[k]) continue;
        uint32_t p = lo[k], mask = 0, count = 0, l = 0, h = 0xFFFFFFFFu;
        for (int i = 0; i < 4; ++i)
            if (lo[i] <= p && p <= hi[i])
                mask |= 1u << i, ++count, l = std::max(l, lo[i]), h = std::min(h, hi[i]);
        uint64_t width = uint64_t(h) - l;
        if (count > bestCount || (count == bestCount && width > bestWidth))
            bestMask = mask, bestCount = count, bestWidth = width;
    }
    covered = bestCount;
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
    node.plane = pyr.plane.empty() ? 0u : pyr.plane[level][i];
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

// reduceLevel with planes (mh.h, "Planar trees"): the constant covering the most children with an
// interval, against the plane id shared by the most children; the plane only when it covers more.
void reduceLevelPlanar(uint32_t n, const uint32_t* clo, const uint32_t* chi, uint8_t* cfl, uint32_t* plo,
                       uint32_t* phi, uint8_t* pfl, const uint32_t* cpl, uint32_t* ppl) {
    const uint32_t pn = n / 2;
    for (uint32_t py = 0; py < pn; ++py)
        for (uint32_t px = 0; px < pn; ++px) {
            size_t ci[4];
            uint32_t lo[4], hi[4], pl[4];
            for (uint32_t c = 0; c < 4; ++c) {
                ci[c] = size_t(2 * py + (c >> 1)) * n + 2 * px + (c & 1u);
                lo[c] = clo[ci[c]], hi[c] = chi[ci[c]], pl[c] = cpl[ci[c]];
            }
            // Constants: bestSubset's rule (children with an empty interval take no part).
            uint32_t ccount = 0;
            const uint32_t cmask = bestSubset(lo, hi, ccount);
            // Planes: the id shared by the most children (ties: the first child's).
            uint32_t pmask = 0, pcount = 0;
            for (uint32_t k = 0; k < 4; ++k) {
                if (pl[k] == 0) continue;
                uint32_t mask = 0, count = 0;
                for (uint32_t i = 0; i < 4; ++i)
                    if (pl[i] == pl[k]) mask |= 1u << i, ++count;
                if (count > pcount) pmask = mask, pcount = count;
            }
            const uint32_t mask = pcount > ccount ? pmask : cmask;
            uint32_t l0 = 0, h0 = 0xFFFFFFFFu, common = 0;
            bool shared = true, empty = false;
            uint8_t below = 0;
            for (uint32_t c = 0; c < 4; ++c) {
                if (mask & (1u << c)) {
                    if (lo[c] > hi[c]) empty = true;
                    l0 = std::max(l0, lo[c]), h0 = std::min(h0, hi[c]);
                    if (common == 0) common = pl[c];
                    shared = shared && pl[c] != 0 && pl[c] == common;
                    cfl[ci[c]] &= ~1u;
                }
                if (cfl[ci[c]] & 3u) below = 2;
            }
            // The parent holds every texel its chosen children held: the intersection of their intervals
            // (empty: kept as lo = 1 > hi = 0) and their plane when they all share one.
            if (empty || l0 > h0) l0 = 1u, h0 = 0u;
            const size_t pi = size_t(py) * pn + px;
            plo[pi] = l0, phi[pi] = h0, ppl[pi] = shared ? common : 0u;
            pfl[pi] = uint8_t(1u | below);
        }
}

// The bottom-up pass over a pyramid whose finest level L is filled: levels L-1 .. 0.
void reducePyramid(Pyramid& pyr, uint32_t L) {
    for (uint32_t l = L; l > 0; --l) {
        const uint32_t pn = 1u << (l - 1);
        pyr.lo[l - 1].resize(size_t(pn) * pn), pyr.hi[l - 1].resize(size_t(pn) * pn);
        pyr.flags[l - 1].assign(size_t(pn) * pn, 1u);
        const bool planar = !pyr.plane.empty();
        if (planar) pyr.plane[l - 1].resize(size_t(pn) * pn);
        mhbuild::reduceLevel(1u << l, pyr.lo[l].data(), pyr.hi[l].data(), pyr.flags[l].data(),
                             pyr.lo[l - 1].data(), pyr.hi[l - 1].data(), pyr.flags[l - 1].data(),
                             planar ? pyr.plane[l].data() : nullptr,
                             planar ? pyr.plane[l - 1].data() : nullptr);
    }
}

} // namespace

namespace mhbuild {

void reduceLevel(uint32_t n, const uint32_t* clo, const uint32_t* chi, uint8_t* cfl, uint32_t* plo,
                 uint32_t* phi, uint8_t* pfl, const uint32_t* cpl, uint32_t* ppl) {
    if (cpl) return reduceLevelPlanar(n, clo, chi, cfl, plo, phi, pfl, cpl, ppl);
    const uint32_t pn = n / 2;
    for (uint32_t py = 0; py < pn; ++py)
        for (uint32_t px = 0; px < pn; ++px) {
            size_t ci[4];
            uint32_t lo[4], hi[4];
            for (uint32_t c = 0; c < 4; ++c) {
                ci[c] = size_t(2 * py + (c >> 1)) * n + 2 * px + (c & 1u);
                lo[c] = clo[ci[c]], hi[c] = chi[ci[c]];
            }
            uint32_t covered = 0;
            const uint32_t mask = bestSubset(lo, hi, covered);
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

Result<Subtree> buildSubtree(uint32_t size, const uint32_t* lo, const uint32_t* hi, uint32_t depthOffset,
                             const uint32_t* plane) {
    uint32_t L = 0;
    while ((1u << L) < size) ++L;
    if ((1u << L) != size) return fail("MH: tile side " + std::to_string(size) + " is not a power of two");
    Pyramid pyr;
    pyr.lo.resize(L + 1), pyr.hi.resize(L + 1), pyr.flags.resize(L + 1);
    pyr.lo[L].assign(lo, lo + size_t(size) * size), pyr.hi[L].assign(hi, hi + size_t(size) * size);
    pyr.flags[L].assign(size_t(size) * size, 1u);
    if (plane) pyr.plane.resize(L + 1), pyr.plane[L].assign(plane, plane + size_t(size) * size);
    reducePyramid(pyr, L);
    Subtree t;
    t.lo = pyr.lo[0][0], t.hi = pyr.hi[0][0], t.flags = pyr.flags[0][0];
    t.plane = plane ? pyr.plane[0][0] : 0u;
    buildNodes(pyr, 0, 0, 0, depthOffset, t.nodes);
    return t;
}

} // namespace mhbuild

Result<MhTree> buildMhTree(const DualDepthMap& map, bool planar) {
    const uint32_t res = map.resolution;
    if (res == 0 || res > kMhMaxResolution)
        return fail("MH: resolution " + std::to_string(res) + " outside 1.." +
                    std::to_string(kMhMaxResolution));
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
    planar = planar && !map.enterPlane.empty();
    if (planar) {
        if (map.enterPlane.size() != map.enter.size())
            return fail("MH: the map's plane ids do not match its texels");
        const uint32_t n = 1u << L;
        pyr.plane.resize(L + 1);
        pyr.plane[L].assign(size_t(n) * n, 0u);
        for (uint32_t y = 0; y < res; ++y)
            for (uint32_t x = 0; x < res; ++x) {
                const uint32_t id = map.enterPlane[size_t(y) * res + x];
                if (id > map.planes.size())
                    return fail("MH: texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                ") names plane " + std::to_string(id) + " of " +
                                std::to_string(map.planes.size()));
                pyr.plane[L][size_t(y) * n + x] = id;
            }
    }
    reducePyramid(pyr, L);
    MhTree tree;
    tree.resolution = res, tree.levels = L;
    buildNodes(pyr, 0, 0, 0, 0, tree.nodes);
    if (planar) tree.planes = map.planes;
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

namespace {
// One placement of the node array: groups in preorder of their parent, the groups in `aligned` (by
// owner node) preceded by zero words up to a multiple of 2^shift (positions count from the record's
// first word, headerWords before the node array).
struct Placed {
    std::vector<uint32_t> nodes, hpos, gpos; // hpos/gpos: node-array positions
    std::vector<int32_t> pending;            // redirected inner nodes, patched last
    uint32_t valued = 0, inner = 0, padding = 0;
};

Placed place(const MhTree& tree, const std::vector<uint32_t>& value, const std::vector<int32_t>* redirect,
             const std::vector<uint8_t>& aligned, uint32_t headerWords, uint32_t shift) {
    const size_t count = tree.nodes.size();
    Placed p;
    p.hpos.assign(count, 0), p.gpos.assign(count, 0);
    const MhTree::Node& root = tree.nodes[0];
    p.nodes.push_back(value[0]), ++p.valued;
    if (root.inner()) p.hpos[0] = uint32_t(p.nodes.size()), p.nodes.push_back(0), ++p.inner;
    // Iterative preorder over inner nodes: emit each one's child group, then its inner children.
    std::vector<int32_t> stack;
    if (root.inner()) stack.push_back(0);
    const uint32_t mask = (1u << shift) - 1u;
    while (!stack.empty()) {
        int32_t n = stack.back();
        stack.pop_back();
        if (!aligned.empty() && aligned[n])
            while ((headerWords + p.nodes.size()) & mask) p.nodes.push_back(0), ++p.padding;
        p.gpos[n] = uint32_t(p.nodes.size());
        const MhTree::Node& node = tree.nodes[n];
        for (uint32_t c = 0; c < 4; ++c) {
            int32_t ch = node.child[c];
            if (ch < 0) continue;
            const MhTree::Node& cn = tree.nodes[ch];
            if (cn.valued) p.nodes.push_back(value[ch]), ++p.valued;
            if (cn.inner()) p.hpos[ch] = uint32_t(p.nodes.size()), p.nodes.push_back(0), ++p.inner;
        }
        // Skipped nodes (MMH) are never reached: their parents are redirected.
        for (int c = 3; c >= 0; --c) {
            int32_t ch = node.child[c];
            if (ch < 0 || !tree.nodes[ch].inner()) continue;
            if (redirect && (*redirect)[ch] >= 0)
                p.pending.push_back(ch);
            else
                stack.push_back(ch);
        }
    }
    return p;
}
} // namespace

void layoutPositions(const MhTree& tree, std::vector<uint32_t>& hpos, std::vector<uint32_t>& gpos) {
    const size_t count = tree.nodes.size();
    hpos.assign(count, 0), gpos.assign(count, 0);
    const MhTree::Node& root = tree.nodes[0];
    uint64_t words = 1;
    if (root.inner()) hpos[0] = uint32_t(words++);
    std::vector<int32_t> stack;
    if (root.inner()) stack.push_back(0);
    while (!stack.empty()) { // place()'s walk, counting
        int32_t n = stack.back();
        stack.pop_back();
        gpos[n] = uint32_t(words);
        const MhTree::Node& node = tree.nodes[n];
        for (uint32_t c = 0; c < 4; ++c) {
            int32_t ch = node.child[c];
            if (ch < 0) continue;
            words += tree.nodes[ch].valued;
            if (tree.nodes[ch].inner()) hpos[ch] = uint32_t(words++);
        }
        for (int c = 3; c >= 0; --c)
            if (node.child[c] >= 0 && tree.nodes[node.child[c]].inner()) stack.push_back(node.child[c]);
    }
}

Result<std::vector<uint32_t>> serialize(const MhTree& tree, const std::vector<uint32_t>& value,
                                        const std::vector<int32_t>* redirect,
                                        const std::vector<uint8_t>* skip, uint32_t magic,
                                        std::vector<uint32_t>* headerPos, std::vector<uint32_t>* groupPos,
                                        const Layout& layout) {
    const size_t count = tree.nodes.size();
    // Every written inner node with the owner of the group its header reaches.
    auto eachHeader = [&](const Placed& p, auto&& f) {
        for (size_t n = 0; n < count; ++n) {
            if (!tree.nodes[n].inner() || (skip && (*skip)[n])) continue;
            if (n != 0 && p.hpos[n] == 0) continue; // not reached (inside a redirected subtree)
            int32_t owner = redirect && (*redirect)[n] >= 0 ? (*redirect)[n] : int32_t(n);
            if (!f(int32_t(n), owner)) return false;
        }
        return true;
    };
    std::vector<uint8_t> aligned;
    Placed p = place(tree, value, redirect, aligned, kHeaderWords, 0);
    uint32_t maxNear = std::min(layout.maxNear, kMaxOffset), shift = 0, headerWords = kHeaderWords;
    bool fits = eachHeader(
        p, [&](int32_t n, int32_t g) { return p.gpos[g] > p.hpos[n] && p.gpos[g] - p.hpos[n] <= maxNear; });
    if (!fits) {
        // Version 2: the smallest shift whose far positions reach every aligned group. For one shift,
        // align the groups reached from afar until no more are (padding only lengthens offsets, so the
        // set only grows and the loop ends).
        maxNear = std::min(layout.maxNear, kMaxNearOffset), headerWords = kHeaderWordsFar;
        for (shift = std::max(layout.minFarShift, 1u);; ++shift) {
            if (shift > kMaxFarShift) return fail("MH: node array too large for far groups");
            aligned.assign(count, 0);
            bool grew = true, reach = true;
            while (grew && reach) {
                p = place(tree, value, redirect, aligned, headerWords, shift);
                grew = false;
                eachHeader(p, [&](int32_t n, int32_t g) {
                    if (p.gpos[g] <= p.hpos[n])
                        return reach = false; // a backward redirect: no layout fixes it
                    if (p.gpos[g] - p.hpos[n] > maxNear && !aligned[g]) aligned[g] = 1, grew = true;
                    if (aligned[g] && ((uint64_t(headerWords) + p.gpos[g]) >> shift) > kMaxNearOffset)
                        return reach = false;
                    return true;
                });
            }
            if (reach) break;
        }
    }
    for (size_t n = 0; n < count; ++n) {
        if (!tree.nodes[n].inner() || (skip && (*skip)[n])) continue;
        if (n != 0 && p.hpos[n] == 0) continue;
        int32_t g = redirect && (*redirect)[n] >= 0 ? (*redirect)[n] : int32_t(n);
        uint32_t h = p.hpos[n], target = p.gpos[g];
        uint32_t field = 0;
        if (target > h && target - h <= maxNear)
            field = target - h;
        else if (shift != 0 && target > h)
            field = kFarBit | ((headerWords + target) >> shift);
        else
            return fail("MH: child offset " + std::to_string(int64_t(target) - int64_t(h)) +
                        " does not fit the layout"); // unreachable: placement checked every offset
        p.nodes[h] = childFlags(tree, int32_t(n)) | field << 8;
    }
    std::vector<uint32_t> out(headerWords, 0u);
    out[kMagic] = magic, out[kVersion] = shift ? 2 : 1, out[kResolution] = tree.resolution,
    out[kLevels] = tree.levels;
    out[kRootType] = tree.nodes[0].inner() ? 2u : 1u, out[kNodeOffset] = headerWords;
    if (uint64_t(headerWords) + p.nodes.size() > 0xFFFFFFFFu) return fail("MH: record past 2^32 words");
    out[kNodeWords] = uint32_t(p.nodes.size()), out[kTotalWords] = uint32_t(headerWords + p.nodes.size());
    out[kValued] = p.valued, out[kInnerRecords] = p.inner;
    if (shift) out[kFarShift] = shift, out[kPaddingWords] = p.padding;
    out.insert(out.end(), p.nodes.begin(), p.nodes.end());
    out[kChecksum] = stat::checksumWords(out.data(), out.size(), kChecksum);
    if (headerPos) *headerPos = std::move(p.hpos);
    if (groupPos) *groupPos = std::move(p.gpos);
    return out;
}

Result<void> validate(const uint32_t* data, size_t size, uint32_t magic) {
    if (!data || size < kHeaderWords)
        return fail("MH: buffer of " + std::to_string(size) + " words is shorter than its header");
    if (data[kMagic] != magic) return fail("MH: wrong magic");
    const uint32_t version = data[kVersion];
    if (version != 1 && version != 2) return fail("MH: unsupported version " + std::to_string(version));
    const uint32_t headerWords = version == 2 ? kHeaderWordsFar : kHeaderWords;
    if (size < headerWords)
        return fail("MH: buffer of " + std::to_string(size) + " words is shorter than its header");
    if (data[kTotalWords] != size)
        return fail("MH: total words " + std::to_string(data[kTotalWords]) + " != buffer size " +
                    std::to_string(size));
    if (data[kChecksum] != stat::checksumWords(data, size, kChecksum)) return fail("MH: checksum mismatch");
    uint32_t L = data[kLevels], res = data[kResolution];
    if (L > kMhMaxLevels || res == 0 || res > (1u << L) || (L > 0 && res <= (1u << (L - 1))))
        return fail("MH: resolution " + std::to_string(res) + " does not match " + std::to_string(L) +
                    " levels");
    if (data[kNodeOffset] != headerWords || uint64_t(headerWords) + data[kNodeWords] != size)
        return fail("MH: node array does not fill the buffer");
    if (data[kReserved] != 0) return fail("MH: reserved header word is not 0");
    const uint32_t shift = version == 2 ? data[kFarShift] : 0u,
                   padding = version == 2 ? data[kPaddingWords] : 0u;
    if (version == 2 && (shift == 0 || shift > kMaxFarShift))
        return fail("MH: far shift " + std::to_string(shift) + " outside 1.." + std::to_string(kMaxFarShift));
    // Every node word is a value, a child header or padding: the counts must add up to the node array
    // (the byte breakdown subtracts values from it; a forged count must not wrap it).
    if (data[kValued] == 0 || uint64_t(data[kValued]) + data[kInnerRecords] + padding != data[kNodeWords])
        return fail("MH: " + std::to_string(data[kValued]) + " values, " +
                    std::to_string(data[kInnerRecords]) + " child headers and " + std::to_string(padding) +
                    " padding words do not make the " + std::to_string(data[kNodeWords]) + " node words");
    const uint32_t begin = headerWords, end = uint32_t(size);
    const uint32_t farBit = shift ? kFarBit : 0u;
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
        uint64_t q = (off & farBit) ? uint64_t(off & (kFarBit - 1u)) << shift : uint64_t(hp) + off,
                 groupSize = 0;
        if (q <= hp) return fail("MH: child group of word " + std::to_string(hp) + " not after it");
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
    if (data[kVersion] == 2) b.header = kHeaderWordsFar * 4u; // padding words count as nodes
    b.values = uint64_t(data[kValued]) * 4u;
    b.nodes = uint64_t(data[kNodeWords]) * 4u - b.values;
    return b;
}

} // namespace mhfmt

Result<std::vector<uint32_t>> encodeMH(const MhTree& tree, const mhfmt::Layout& layout) {
    if (tree.planar()) return fail("MH: a planar tree (DAG-MH's values) has no MH encoding");
    std::vector<uint32_t> value(tree.nodes.size());
    for (size_t i = 0; i < tree.nodes.size(); ++i)
        value[i] = stat::midpoint(tree.nodes[i].lo, tree.nodes[i].hi);
    return mhfmt::serialize(tree, value, nullptr, nullptr, mhfmt::kMagicMH, nullptr, nullptr, layout);
}

Result<std::vector<uint32_t>> encodeMH(const DualDepthMap& map, const mhfmt::Layout& layout) {
    auto tree = buildMhTree(map);
    if (!tree) return fail(tree.error());
    return encodeMH(*tree, layout);
}

Result<void> validateMH(const uint32_t* data, size_t size) {
    return mhfmt::validate(data, size, mhfmt::kMagicMH);
}
stat::ByteBreakdown breakdownMH(const uint32_t* data, size_t size) {
    return mhfmt::breakdown(data, size);
}

} // namespace ml
