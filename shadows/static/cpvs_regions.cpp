// CPVS region build (paper section 4.3): sub-DAGs built per region, merged into one DAG.
//
// The grid's x, y extent is split into (2^r)^2 square blocks of cells (every z: a block is a column of the
// volume, so insertion, which re-uses nodes only along z within one x, y footprint, creates exactly the
// nodes the global insertion creates there). Each block is inserted and compressed bottom-up (section 4.1)
// alone, so only one region's uncompressed nodes exist at a time, and the work per region is independent
// (what a parallel build would distribute). The compressed sub-DAGs are merged pairwise, bottom-up, level
// by level, with the sorted-layer merge of section 4.3:
//
//   * after bottom-up compression every level of a sub-DAG is strictly increasing in node content
//     (childMask, shadowMask, child ids), leaves in mask value;
//   * merging two strictly increasing leaf lists gives the merged list and maps old -> new index that are
//     strictly increasing, so re-labelling the children of a level by them keeps that level strictly
//     increasing (equal child masks use the same slots, unused slots stay 0): the next level merges the
//     same way, up to the grid cells;
//   * two nodes become one only when their full content compares equal (children already merged, so
//     equal ids mean identical subtrees). No hash is involved, so no collision can occur.
//
// The merged levels are the strictly increasing lists of all distinct subtrees: exactly what the global
// insert + compressBottomUp produces, byte for byte after the layout. Sub-DAGs are merged in
// binary-counter order (after region i, merge while the two newest sub-DAGs hold as many regions), so at
// most log2(regions) + 1 compressed sub-DAGs are alive, and neighbouring regions (Z order) merge first.
#include "shadows/static/cpvs.h"
#include "shadows/static/cpvs_internal.h"

#include <algorithm>
#include <chrono>
#include <utility>

namespace ml::cpvs_detail {

namespace {

struct SubDag {
    std::vector<std::vector<Node>> levels; // each strictly increasing in content
    std::vector<uint64_t> leaves;          // strictly increasing
    std::vector<CellBlock> blocks;         // the grid cells this sub-DAG covers, entries into levels.back()
    uint32_t regions = 0;

    uint64_t bytes() const {
        uint64_t b = leaves.size() * sizeof(uint64_t);
        for (const auto& l : levels) b += l.size() * sizeof(Node);
        for (const auto& c : blocks) b += c.grid.size() * sizeof(uint32_t);
        return b;
    }
};

uint64_t dagBytes(const Dag& d) {
    uint64_t b = d.leaves.size() * sizeof(uint64_t) + d.grid.size() * sizeof(uint32_t);
    for (const auto& l : d.levels) b += l.size() * sizeof(Node);
    return b;
}

// Merges two strictly increasing lists into one; an element of a equal (full content) to one of b is kept
// once. ra[i] / rb[j] = index of a[i] / b[j] in the result; both maps are strictly increasing.
template <class T>
std::vector<T> mergeSorted(const std::vector<T>& a, const std::vector<T>& b, std::vector<uint32_t>& ra,
                           std::vector<uint32_t>& rb) {
    std::vector<T> out;
    out.reserve(a.size() + b.size());
    ra.resize(a.size());
    rb.resize(b.size());
    size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        const uint32_t at = uint32_t(out.size());
        if (a[i] < b[j]) {
            out.push_back(a[i]);
            ra[i++] = at;
        } else if (b[j] < a[i]) {
            out.push_back(b[j]);
            rb[j++] = at;
        } else { // neither is less: identical content
            out.push_back(a[i]);
            ra[i++] = at;
            rb[j++] = at;
        }
    }
    for (; i < a.size(); ++i) {
        ra[i] = uint32_t(out.size());
        out.push_back(a[i]);
    }
    for (; j < b.size(); ++j) {
        rb[j] = uint32_t(out.size());
        out.push_back(b[j]);
    }
    return out;
}

void relabelChildren(std::vector<Node>& level, const std::vector<uint32_t>& remap) {
    for (Node& n : level)
        for (uint32_t c = 0; c < 8; ++c)
            if ((n.childMask >> c) & 1u) n.child[c] = remap[n.child[c]];
}

void relabelGrid(std::vector<CellBlock>& blocks, const std::vector<uint32_t>& remap) {
    for (CellBlock& b : blocks)
        for (uint32_t& e : b.grid)
            if (e >= 2) e = 2 + remap[e - 2];
}

// Section 4.3: a and b merged level by level from the leaves up. liveBytesPeak: at least otherBytes (the
// other live sub-DAGs) + the inputs + the result.
SubDag mergeSubDags(SubDag a, SubDag b, uint64_t otherBytes, uint64_t& liveBytesPeak) {
    SubDag out;
    out.regions = a.regions + b.regions;
    out.levels.resize(a.levels.size());
    std::vector<uint32_t> ra, rb;
    const uint64_t inputs = a.bytes() + b.bytes();
    uint64_t produced = 0;
    out.leaves = mergeSorted(a.leaves, b.leaves, ra, rb);
    produced += out.leaves.size() * sizeof(uint64_t);
    std::vector<uint64_t>().swap(a.leaves);
    std::vector<uint64_t>().swap(b.leaves);
    for (size_t k = 0; k < a.levels.size(); ++k) {
        relabelChildren(a.levels[k], ra);
        relabelChildren(b.levels[k], rb);
        std::vector<uint32_t> na, nb;
        out.levels[k] = mergeSorted(a.levels[k], b.levels[k], na, nb);
        produced += out.levels[k].size() * sizeof(Node);
        std::vector<Node>().swap(a.levels[k]);
        std::vector<Node>().swap(b.levels[k]);
        ra = std::move(na);
        rb = std::move(nb);
    }
    liveBytesPeak = std::max(liveBytesPeak, otherBytes + inputs + produced);
    relabelGrid(a.blocks, ra);
    relabelGrid(b.blocks, rb);
    out.blocks = std::move(a.blocks);
    for (CellBlock& c : b.blocks) out.blocks.push_back(std::move(c));
    return out;
}

// Z order of the blocks: even bits x, odd bits y.
uint32_t deinterleave(uint32_t v) {
    uint32_t r = 0;
    for (uint32_t i = 0; 2 * i < 32; ++i) r |= ((v >> (2 * i)) & 1u) << i;
    return r;
}

} // namespace

Result<Dag> mergeRegions(uint32_t log2Resolution, uint32_t gridLog2, uint32_t regionLog2, RegionStats& st,
                         const std::function<void(float)>& progress, const RegionSource& source,
                         uint64_t maxLiveBytes) {
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    const uint32_t r = std::min(regionLog2, gridLog2), perAxis = 1u << r, w = 1u << (gridLog2 - r);
    const uint32_t count = perAxis * perAxis;
    st = RegionStats{};
    st.regions = count;
    std::vector<SubDag> stack; // binary counter: regions per entry strictly decrease from the bottom
    auto stackBytes = [&] {
        uint64_t b = 0;
        for (const auto& s : stack) b += s.bytes();
        return b;
    };
    auto mergeTop = [&] {
        SubDag b = std::move(stack.back());
        stack.pop_back();
        SubDag a = std::move(stack.back());
        stack.pop_back();
        const uint64_t other = stackBytes();
        stack.push_back(mergeSubDags(std::move(a), std::move(b), other, st.liveBytesPeak));
    };
    auto overBound = [&]() -> Result<void> {
        if (maxLiveBytes && st.liveBytesPeak > maxLiveBytes)
            return fail("cpvs: the DAG under construction passed " + std::to_string(st.liveBytesPeak >> 20) +
                        " MiB, over its bound of " + std::to_string(maxLiveBytes >> 20) + " MiB");
        return {};
    };
    for (uint32_t i = 0; i < count; ++i) {
        CellBlock block;
        block.x0 = deinterleave(i) * w;
        block.y0 = deinterleave(i >> 1) * w;
        block.w = w;
        auto t0 = Clock::now();
        auto inserted = source(block);
        if (!inserted) return fail(inserted.error());
        Dag& d = inserted.value();
        if (d.grid.size() != size_t(w) * w * (size_t(1) << gridLog2) ||
            d.levels.size() != log2Resolution - gridLog2 - 2)
            return fail("cpvs: region " + std::to_string(i) + " has a grid or levels of the wrong size");
        auto t1 = Clock::now();
        uint64_t nodes = 0;
        for (const auto& l : d.levels) nodes += l.size();
        st.nodesInserted += nodes;
        st.leavesInserted += d.leaves.size();
        st.regionNodesPeak = std::max(st.regionNodesPeak, nodes);
        st.regionLeavesPeak = std::max<uint64_t>(st.regionLeavesPeak, d.leaves.size());
        st.liveBytesPeak = std::max(st.liveBytesPeak, stackBytes() + dagBytes(d));
        compressBottomUp(d); // relabels the block's grid too
        auto t2 = Clock::now();
        SubDag s;
        s.levels = std::move(d.levels);
        s.leaves = std::move(d.leaves);
        s.regions = 1;
        block.grid = std::move(d.grid);
        s.blocks.push_back(std::move(block));
        stack.push_back(std::move(s));
        st.insertMs += ms(t0, t1);
        st.compressMs += ms(t1, t2);
        auto t3 = Clock::now();
        while (stack.size() >= 2 && stack[stack.size() - 1].regions == stack[stack.size() - 2].regions)
            mergeTop();
        st.mergeMs += ms(t3, Clock::now());
        if (auto b = overBound(); !b) return fail(b.error());
        if (progress) progress(float(i + 1) / float(count));
    }
    auto t4 = Clock::now();
    while (stack.size() >= 2) mergeTop();
    st.mergeMs += ms(t4, Clock::now());
    if (auto b = overBound(); !b) return fail(b.error());

    Dag dag;
    dag.resolution = 1u << log2Resolution;
    dag.log2Resolution = log2Resolution;
    dag.gridLog2 = gridLog2;
    dag.cellLog2 = log2Resolution - gridLog2;
    const uint32_t g = 1u << gridLog2;
    dag.grid.assign(size_t(g) * g * g, 0u);
    SubDag& all = stack.back();
    for (const CellBlock& b : all.blocks)
        for (uint32_t z = 0; z < g; ++z)
            for (uint32_t y = 0; y < b.w; ++y)
                for (uint32_t x = 0; x < b.w; ++x)
                    dag.grid[(size_t(z) * g + b.y0 + y) * g + b.x0 + x] =
                        b.grid[(size_t(z) * b.w + y) * b.w + x];
    dag.levels = std::move(all.levels);
    dag.leaves = std::move(all.leaves);
    return dag;
}

Dag buildRegions(const CpvsPrecompute& pre, uint32_t log2Resolution, uint32_t gridLog2, uint32_t regionLog2,
                 RegionStats& st, const std::function<void(float)>& progress) {
    auto dag = mergeRegions(
        log2Resolution, gridLog2, regionLog2, st, progress,
        [&](const CellBlock& block) -> Result<Dag> {
            return insertBlock(pre, log2Resolution, gridLog2, block);
        },
        0);
    return std::move(dag.value()); // no bound and a source that cannot fail: always a value
}

} // namespace ml::cpvs_detail
