// CPVS flat layout (paper section 6.3), validation and the CPU twin of shaders/static/cpvs_lookup.glsl.
//
// Words (all offsets are word indices from the CPVS's first word; docs/cpvs-layout.md has byte counts):
//   [0, 16)            header (CpvsHeader)
//   thresholds         N + 1 quantised slice boundaries T[s]
//   grid               (2^g)^3 entries, cell size C = N >> g: kCpvsLit, kCpvsShadowed, or the offset of
//                      the C^3 node (0 and 1 point into the header, so they are never node offsets)
//   inner nodes        top level first; one word childMask | shadowMask << 8, then one word per set
//                      childMask bit (child order x + 2 y + 4 z): the child's offset, an inner node or,
//                      under an 8^3 node, a leaf
//   leaves             2 words per 4^3 leaf, bit x + 4 y + 16 z (low word first)
// Validation visits every node reachable from the grid once per level, so a damaged pointer, count or
// size is rejected before any lookup can read outside [0, totalWords) or loop.
#include "shadows/static/cpvs.h"
#include "shadows/static/cpvs_internal.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

namespace ml {
namespace cpvs_detail {

Result<std::vector<uint32_t>> writeLayout(const CpvsSpace& space, const Dag& dag) {
    const uint32_t n = space.resolution, g = 1u << dag.gridLog2, top = uint32_t(dag.levels.size()) - 1;
    // word offset of every node, levels top first
    std::vector<std::vector<uint32_t>> offset(dag.levels.size());
    const uint32_t thresholds = kCpvsHeaderWords, grid = thresholds + n + 1, nodes = grid + g * g * g;
    // Every pointer and region offset is a uint32 word index: counted in 64 bits, refused past 2^32 - 1
    // words (16 GiB) rather than wrapped.
    uint64_t at = nodes;
    for (uint32_t k = top + 1; k-- > 0;) {
        offset[k].resize(dag.levels[k].size());
        for (size_t i = 0; i < dag.levels[k].size(); ++i) {
            offset[k][i] = uint32_t(at);
            at += 1 + uint32_t(std::popcount(dag.levels[k][i].childMask));
            if (at > 0xFFFFFFFFull) break;
        }
    }
    const uint64_t total64 = at + 2 * uint64_t(dag.leaves.size());
    if (total64 > 0xFFFFFFFFull)
        return fail("cpvs: the layout needs " + std::to_string(total64) +
                    " words, past the 2^32 - 1 a uint32 word offset addresses");
    const uint32_t leaves = uint32_t(at), total = uint32_t(total64);
    std::vector<uint32_t> w(total, 0u);
    w[kCpvsHMagic] = kCpvsMagic;
    w[kCpvsHVersion] = space.slicing == CpvsSlicing::Linear ? kCpvsVersionLinear : kCpvsVersion;
    w[kCpvsHSlicing] = uint32_t(space.slicing);
    w[kCpvsHResolution] = n;
    w[kCpvsHLog2Resolution] = space.log2Resolution;
    w[kCpvsHGridLog2] = dag.gridLog2;
    std::memcpy(&w[kCpvsHNearBits], &space.nearPlane, 4);
    std::memcpy(&w[kCpvsHFarBits], &space.farPlane, 4);
    w[kCpvsHTotalWords] = total;
    w[kCpvsHThresholds] = thresholds;
    w[kCpvsHGrid] = grid;
    w[kCpvsHNodes] = nodes;
    w[kCpvsHNodeWords] = leaves - nodes;
    w[kCpvsHLeaves] = leaves;
    w[kCpvsHLeafWords] = total - leaves;
    for (uint32_t s = 0; s <= n; ++s) w[thresholds + s] = space.thresholds[s];
    for (size_t i = 0; i < dag.grid.size(); ++i)
        w[grid + i] = dag.grid[i] < 2 ? dag.grid[i] : offset[top][dag.grid[i] - 2];
    for (uint32_t k = 0; k <= top; ++k)
        for (size_t i = 0; i < dag.levels[k].size(); ++i) {
            const Node& nd = dag.levels[k][i];
            uint32_t p = offset[k][i];
            w[p++] = uint32_t(nd.childMask) | uint32_t(nd.shadowMask) << 8;
            for (uint32_t c = 0; c < 8; ++c)
                if ((nd.childMask >> c) & 1u)
                    w[p++] = k == 0 ? leaves + 2 * nd.child[c] : offset[k - 1][nd.child[c]];
        }
    for (size_t i = 0; i < dag.leaves.size(); ++i) {
        w[leaves + 2 * i] = uint32_t(dag.leaves[i]);
        w[leaves + 2 * i + 1] = uint32_t(dag.leaves[i] >> 32);
    }
    w[kCpvsHChecksum] = cpvsChecksum(w.data(), w.size());
    return w;
}

} // namespace cpvs_detail

uint32_t cpvsChecksum(const uint32_t* data, size_t words) {
    // FNV-1a per word. Each step h = (h ^ w) * p is a bijection of h for a fixed w and of w for a fixed h,
    // so any change confined to one word (any number of its bits) changes the result.
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < words; ++i) h = (h ^ (i == kCpvsHChecksum ? 0u : data[i])) * 16777619u;
    return h;
}

namespace {

struct Validator {
    const uint32_t* d;
    uint64_t nodes, nodesEnd, leaves, leavesEnd;
    // per node word: bit sizeLog2 - 3 set once validated as a node of that size (nodes are 8^3 .. 2^18 per
    // side: 16 bits hold every size a resolution up to kCpvsMaxResolution has)
    std::vector<uint16_t> seen;
    std::string error;

    bool node(uint64_t p, uint32_t sizeLog2) {
        if (p < nodes || p >= nodesEnd)
            return bad("node offset " + std::to_string(p) + " outside the node region");
        uint16_t& mark = seen[p - nodes];
        if ((mark >> (sizeLog2 - 3)) & 1u) return true;
        uint32_t h = d[p];
        if (h >> 16) return bad("node at " + std::to_string(p) + " has header bits above 16 set");
        if ((h & 0xFFu) & (h >> 8))
            return bad("node at " + std::to_string(p) + " marks a child both inner and shadowed");
        uint32_t children = uint32_t(std::popcount(h & 0xFFu));
        if (p + 1 + children > nodesEnd)
            return bad("node at " + std::to_string(p) + " runs past the node region");
        for (uint32_t i = 0; i < children; ++i) {
            uint64_t c = d[p + 1 + i];
            if (sizeLog2 == 3) {
                if (c < leaves || c + 2 > leavesEnd || (c - leaves) % 2)
                    return bad("leaf pointer " + std::to_string(c) + " at " + std::to_string(p + 1 + i) +
                               " invalid");
            } else if (!node(c, sizeLog2 - 1)) {
                return false;
            }
        }
        mark |= uint16_t(1u << (sizeLog2 - 3));
        return true;
    }
    bool bad(std::string m) {
        error = "cpvs: " + m;
        return false;
    }
};

} // namespace

Result<void> validateCpvs(const uint32_t* d, size_t words) {
    if (!d || words < kCpvsHeaderWords)
        return fail("cpvs: " + std::to_string(words) + " words, shorter than the header");
    if (d[kCpvsHMagic] != kCpvsMagic) return fail("cpvs: bad magic");
    if (d[kCpvsHVersion] != kCpvsVersion && d[kCpvsHVersion] != kCpvsVersionLinear)
        return fail("cpvs: version " + std::to_string(d[kCpvsHVersion]));
    // Version 1 is log slicing (the word was reserved, 0), version 2 linear: the word must agree.
    if (d[kCpvsHSlicing] != (d[kCpvsHVersion] == kCpvsVersionLinear ? 1u : 0u))
        return fail("cpvs: slicing word " + std::to_string(d[kCpvsHSlicing]) + " does not match version " +
                    std::to_string(d[kCpvsHVersion]));
    const uint64_t n = d[kCpvsHResolution], lg = d[kCpvsHLog2Resolution], gl = d[kCpvsHGridLog2];
    if (n < kCpvsMinResolution || n > kCpvsMaxResolution || lg > 31 || (uint64_t(1) << lg) != n)
        return fail("cpvs: resolution " + std::to_string(n) + " / log2 " + std::to_string(lg) + " invalid");
    if (gl + 3 > lg) return fail("cpvs: grid log2 " + std::to_string(gl) + " too large");
    float nearPlane, farPlane;
    std::memcpy(&nearPlane, &d[kCpvsHNearBits], 4);
    std::memcpy(&farPlane, &d[kCpvsHFarBits], 4);
    if (!(nearPlane > 0.0f) || !(farPlane > nearPlane) || !std::isfinite(farPlane))
        return fail("cpvs: near / far invalid");
    const uint64_t total = d[kCpvsHTotalWords];
    if (total > words)
        return fail("cpvs: " + std::to_string(total) + " words declared, " + std::to_string(words) +
                    " given (truncated)");
    const uint64_t g = uint64_t(1) << gl;
    const uint64_t th = d[kCpvsHThresholds], grid = d[kCpvsHGrid], nodes = d[kCpvsHNodes],
                   nodeWords = d[kCpvsHNodeWords], leaves = d[kCpvsHLeaves], leafWords = d[kCpvsHLeafWords];
    if (th != kCpvsHeaderWords || grid != th + n + 1 || nodes != grid + g * g * g ||
        leaves != nodes + nodeWords || leaves + leafWords != total || leafWords % 2)
        return fail("cpvs: region offsets inconsistent");
    if (cpvsChecksum(d, total) != d[kCpvsHChecksum]) return fail("cpvs: checksum mismatch");
    for (uint64_t s = 1; s <= n; ++s)
        if (d[th + s] < d[th + s - 1]) return fail("cpvs: slice thresholds decrease at " + std::to_string(s));
    Validator v{d, nodes, leaves, leaves, total, std::vector<uint16_t>(nodeWords, 0), {}};
    const uint32_t cellLog2 = uint32_t(lg - gl);
    for (uint64_t i = 0; i < g * g * g; ++i) {
        uint32_t e = d[grid + i];
        if (e == kCpvsLit || e == kCpvsShadowed) continue;
        if (!v.node(e, cellLog2)) return fail(v.error + " (grid cell " + std::to_string(i) + ")");
    }
    return {};
}

CpvsBytes cpvsBytes(const uint32_t* d) {
    CpvsBytes b;
    uint64_t g = uint64_t(1) << d[kCpvsHGridLog2];
    b.header = 4ull * kCpvsHeaderWords;
    b.thresholds = 4ull * (d[kCpvsHResolution] + 1);
    b.grid = 4ull * g * g * g;
    b.innerNodes = 4ull * d[kCpvsHNodeWords];
    b.leafMasks = 4ull * d[kCpvsHLeafWords];
    b.total = 4ull * d[kCpvsHTotalWords];
    return b;
}

// ----- The bias and PCF on arrays, from the one text (shaders/static/cpvs_decode.h), and the CPU twin of
// shaders/static/cpvs_lookup.glsl's cpvsVoxelNormal (keep the two in step, line by line) -----

void cpvsNormalOffset(const int32_t nq[3], int32_t radius, int32_t out[3]) {
    int32_t ax = nq[0] < 0 ? -nq[0] : nq[0], ay = nq[1] < 0 ? -nq[1] : nq[1], az = nq[2] < 0 ? -nq[2] : nq[2];
    int32_t m = std::max(ax, std::max(ay, az));
    for (int i = 0; i < 3; ++i) out[i] = cpvstwin::cpvsBiasAxis(nq[i], m, radius + 1);
}

uint32_t cpvsPcfLitCount(const uint32_t* data, uint32_t base, int32_t x, int32_t y, int32_t s,
                         const int32_t nq[3], int32_t radius) {
    return cpvsPcfLitLevel(data, base, x, y, s, nq[0], nq[1], nq[2], radius, 0u);
}

void cpvsVoxelNormal(const float nView[3], float ndcX, float ndcY, float tanHalfFov, float logFarOverNear,
                     int32_t out[3]) {
    // voxel u = N (ndc + 1) / 2, ndc = x / (z tan), slice w = N log(z / near) / log(far / near), depth
    // z = -z_view: du = N (dx - ndc tan dz) / (2 z tan), dw = N dz / (z L); the common N / z drops out.
    float nd = -nView[2];
    float v[3];
    v[0] = (nView[0] - ndcX * tanHalfFov * nd) / (2.0f * tanHalfFov);
    v[1] = (nView[1] - ndcY * tanHalfFov * nd) / (2.0f * tanHalfFov);
    v[2] = nd / logFarOverNear;
    float m = std::fmax(std::fabs(v[0]), std::fmax(std::fabs(v[1]), std::fabs(v[2])));
    for (int i = 0; i < 3; ++i) out[i] = m > 0.0f ? int32_t(std::floor(v[i] / m * 1024.0f + 0.5f)) : 0;
}

} // namespace ml
