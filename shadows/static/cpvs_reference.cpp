// CPVS verification against the voxelisation derived directly from the depth maps, and a brute-force
// uncompressed sparse voxel octree for small resolutions (the tests show the DAG encodes exactly it).
#include "shadows/static/cpvs.h"

#include <algorithm>
#include <bit>
#include <cstring>

namespace ml {

namespace {

class ColumnWalk {
  public:
    ColumnWalk(const uint32_t* d, CpvsVerifyReport& r) : d_(d), r_(r) {}

    void column(uint32_t x, uint32_t y, CpvsColumn ref) {
        x_ = x;
        y_ = y;
        ref_ = ref;
        const uint32_t gl = d_[kCpvsHGridLog2], cellLog2 = d_[kCpvsHLog2Resolution] - gl, g = 1u << gl;
        const uint32_t grid = d_[kCpvsHGrid];
        for (uint32_t cz = 0; cz < g; ++cz) {
            uint32_t e = d_[grid + ((cz << gl | (y >> cellLog2)) << gl | (x >> cellLog2))];
            if (e == kCpvsLit || e == kCpvsShadowed)
                run(cz << cellLog2, 1u << cellLog2, e == kCpvsShadowed);
            else
                walk(e, cellLog2, cz << cellLog2);
        }
    }

  private:
    void walk(uint32_t ptr, uint32_t sizeLog2, uint32_t z0) {
        const uint32_t half = 1u << (sizeLog2 - 1), h = d_[ptr];
        const uint32_t cxy = ((x_ & half) ? 1u : 0u) | ((y_ & half) ? 2u : 0u);
        for (uint32_t cz = 0; cz < 2; ++cz) {
            const uint32_t bit = 1u << (cxy | cz << 2), zc = z0 + cz * half;
            if (!(h & bit)) {
                run(zc, half, (h >> 8) & bit);
                continue;
            }
            uint32_t p = d_[ptr + 1 + std::popcount(h & (bit - 1))];
            if (half > 4) {
                walk(p, sizeLog2 - 1, zc);
                continue;
            }
            uint64_t leaf = uint64_t(d_[p]) | uint64_t(d_[p + 1]) << 32;
            for (uint32_t dz = 0; dz < 4; ++dz)
                run(zc + dz, 1, (leaf >> ((x_ & 3) + 4 * (y_ & 3) + 16 * dz)) & 1u);
        }
    }
    // slices [z, z + len) hold `shadowed`; the reference wants lit below litEnd, shadowed from shadowBegin
    void run(uint32_t z, uint32_t len, bool shadowed) {
        const uint32_t end = z + len;
        const uint32_t litHi = std::min(end, ref_.litEnd), shLo = std::max(z, ref_.shadowBegin);
        const uint64_t lit = litHi > z ? litHi - z : 0, sh = end > shLo ? end - shLo : 0;
        r_.checked += lit + sh;
        r_.undefined += len - lit - sh;
        r_.mismatches += shadowed ? lit : sh;
    }

    const uint32_t* d_;
    CpvsVerifyReport& r_;
    uint32_t x_ = 0, y_ = 0;
    CpvsColumn ref_;
};

} // namespace

Result<CpvsSpace> cpvsSpaceOf(const uint32_t* d) {
    float nearPlane, farPlane;
    std::memcpy(&nearPlane, &d[kCpvsHNearBits], 4);
    std::memcpy(&farPlane, &d[kCpvsHFarBits], 4);
    return makeCpvsSpace(d[kCpvsHResolution], nearPlane, farPlane, CpvsSlicing(d[kCpvsHSlicing]));
}

uint64_t cpvsThresholdMismatches(const uint32_t* d, const CpvsSpace& space) {
    // the stored slice thresholds must be the ones eq. 1 (or the linear slicing) gives: the lookup's
    // depth -> slice map
    uint64_t bad = 0;
    for (uint32_t s = 0; s <= space.resolution; ++s) bad += d[d[kCpvsHThresholds] + s] != space.thresholds[s];
    return bad;
}

namespace {

// ColumnWalk for the 16 columns of an aligned 4x4 block at once: above the leaves a node's child is chosen
// by x & half and y & half with half >= 4, the same for all 16, so the descent is shared and only the
// runs are checked per column (the same counts as 16 ColumnWalks; a 65536^2 verify descends 16x less).
class BundleWalk {
  public:
    BundleWalk(const uint32_t* d, CpvsVerifyReport& r) : d_(d), r_(r) {}

    void bundle(uint32_t x, uint32_t y, const CpvsColumn* refs) { // refs[i]: column x + i % 4, y + i / 4
        x_ = x;
        y_ = y;
        refs_ = refs;
        const uint32_t gl = d_[kCpvsHGridLog2], cellLog2 = d_[kCpvsHLog2Resolution] - gl, g = 1u << gl;
        const uint32_t grid = d_[kCpvsHGrid];
        for (uint32_t cz = 0; cz < g; ++cz) {
            uint32_t e = d_[grid + ((cz << gl | (y >> cellLog2)) << gl | (x >> cellLog2))];
            if (e == kCpvsLit || e == kCpvsShadowed)
                runAll(cz << cellLog2, 1u << cellLog2, e == kCpvsShadowed);
            else
                walk(e, cellLog2, cz << cellLog2);
        }
    }

  private:
    void walk(uint32_t ptr, uint32_t sizeLog2, uint32_t z0) {
        const uint32_t half = 1u << (sizeLog2 - 1), h = d_[ptr];
        const uint32_t cxy = ((x_ & half) ? 1u : 0u) | ((y_ & half) ? 2u : 0u);
        for (uint32_t cz = 0; cz < 2; ++cz) {
            const uint32_t bit = 1u << (cxy | cz << 2), zc = z0 + cz * half;
            if (!(h & bit)) {
                runAll(zc, half, (h >> 8) & bit);
                continue;
            }
            uint32_t p = d_[ptr + 1 + std::popcount(h & (bit - 1))];
            if (half > 4) {
                walk(p, sizeLog2 - 1, zc);
                continue;
            }
            const uint64_t leaf = uint64_t(d_[p]) | uint64_t(d_[p + 1]) << 32;
            for (uint32_t i = 0; i < 16; ++i) // bit (x & 3) + 4 (y & 3) + 16 dz: column i is bit i
                for (uint32_t dz = 0; dz < 4; ++dz) run(refs_[i], zc + dz, 1, (leaf >> (i + 16 * dz)) & 1u);
        }
    }
    void runAll(uint32_t z, uint32_t len, bool shadowed) {
        for (uint32_t i = 0; i < 16; ++i) run(refs_[i], z, len, shadowed);
    }
    // as ColumnWalk::run
    void run(const CpvsColumn& ref, uint32_t z, uint32_t len, bool shadowed) {
        const uint32_t end = z + len;
        const uint32_t litHi = std::min(end, ref.litEnd), shLo = std::max(z, ref.shadowBegin);
        const uint64_t lit = litHi > z ? litHi - z : 0, sh = end > shLo ? end - shLo : 0;
        r_.checked += lit + sh;
        r_.undefined += len - lit - sh;
        r_.mismatches += shadowed ? lit : sh;
    }

    const uint32_t* d_;
    CpvsVerifyReport& r_;
    uint32_t x_ = 0, y_ = 0;
    const CpvsColumn* refs_ = nullptr;
};

} // namespace

void verifyCpvsBlock(const uint32_t* d, const CpvsSpace& space, uint32_t x0, uint32_t y0, uint32_t w,
                     uint32_t h, const uint32_t* enter, const uint32_t* exit, CpvsVerifyReport& report) {
    if (x0 % 4 == 0 && y0 % 4 == 0 && w % 4 == 0 && h % 4 == 0) {
        BundleWalk walk(d, report);
        CpvsColumn refs[16];
        for (uint32_t by = 0; by < h; by += 4)
            for (uint32_t bx = 0; bx < w; bx += 4) {
                for (uint32_t i = 0; i < 16; ++i) {
                    const size_t t = size_t(by + i / 4) * w + bx + i % 4;
                    refs[i] = cpvsReferenceColumn(space, enter[t], exit[t]);
                }
                walk.bundle(x0 + bx, y0 + by, refs);
            }
        return;
    }
    ColumnWalk walk(d, report);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const size_t i = size_t(y) * w + x;
            walk.column(x0 + x, y0 + y, cpvsReferenceColumn(space, enter[i], exit[i]));
        }
}

CpvsVerifyReport verifyCpvs(const uint32_t* d, const DualDepthMap& map) {
    CpvsVerifyReport r;
    const uint32_t n = d[kCpvsHResolution];
    auto space = cpvsSpaceOf(d);
    if (!space || map.resolution != n || map.enter.size() != size_t(n) * n ||
        map.exit.size() != size_t(n) * n) {
        r.mismatches = 1; // nothing comparable
        return r;
    }
    r.mismatches += cpvsThresholdMismatches(d, *space);
    verifyCpvsBlock(d, *space, 0, 0, n, n, map.enter.data(), map.exit.data(), r);
    return r;
}

namespace {

struct OctreeBuilder {
    uint32_t n;
    std::vector<uint8_t> vox; // x + N (y + N z)
    CpvsOctree& t;

    // kind 0 lit, 1 shadowed, 2 node / leaf (id)
    std::pair<uint8_t, uint32_t> build(uint32_t sizeLog2, uint32_t x0, uint32_t y0, uint32_t z0) {
        const uint32_t size = 1u << sizeLog2;
        uint64_t count = 0;
        for (uint32_t z = z0; z < z0 + size; ++z)
            for (uint32_t y = y0; y < y0 + size; ++y)
                for (uint32_t x = x0; x < x0 + size; ++x) count += vox[(size_t(z) * n + y) * n + x];
        if (count == 0) return {0, 0};
        if (count == uint64_t(size) * size * size) return {1, 0};
        if (size == 4) {
            uint64_t leaf = 0;
            for (uint32_t i = 0; i < 64; ++i)
                if (vox[(size_t(z0 + i / 16) * n + y0 + (i / 4) % 4) * n + x0 + i % 4])
                    leaf |= uint64_t(1) << i;
            t.leaves.push_back(leaf);
            return {2, uint32_t(t.leaves.size() - 1)};
        }
        CpvsOctree::Node node;
        const uint32_t h = size / 2;
        for (uint32_t c = 0; c < 8; ++c) {
            auto [kind, id] =
                build(sizeLog2 - 1, x0 + (c & 1) * h, y0 + ((c >> 1) & 1) * h, z0 + (c >> 2) * h);
            if (kind == 2) {
                node.childMask |= uint8_t(1u << c);
                node.child[c] = id;
            } else if (kind == 1) {
                node.shadowMask |= uint8_t(1u << c);
            }
        }
        auto& level = t.levels[sizeLog2 - 3];
        level.push_back(node);
        return {2, uint32_t(level.size() - 1)};
    }
};

} // namespace

CpvsOctree cpvsBuildOctree(uint32_t resolution,
                           const std::function<bool(uint32_t, uint32_t, uint32_t)>& shadowed) {
    CpvsOctree t;
    t.resolution = resolution;
    const uint32_t lg = uint32_t(std::countr_zero(resolution));
    t.levels.resize(lg - 2);
    OctreeBuilder b{resolution, std::vector<uint8_t>(size_t(resolution) * resolution * resolution), t};
    for (uint32_t z = 0; z < resolution; ++z)
        for (uint32_t y = 0; y < resolution; ++y)
            for (uint32_t x = 0; x < resolution; ++x)
                b.vox[(size_t(z) * resolution + y) * resolution + x] = shadowed(x, y, z) ? 1 : 0;
    t.rootKind = b.build(lg, 0, 0, 0).first;
    return t;
}

} // namespace ml
