// DAG-MH value encoder: two classes a chunk, each a plane with its own lattice step and factor width, the
// slopes from a shared table (docs/dagmh-encoding.md, "DAG-MH value encoding").
#include "shadows/static/dagmh_values.h"

#include "shadows/static/dagmh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>

namespace ml::dagval {

namespace {

// (D_x, D_y): the slopes per texel in 1/64 units (kOrthoSlopeFractionBits), int32 in the table: the
// rasteriser's depth planes of directional maps (raster_dual.h).
using Slope = std::pair<int64_t, int64_t>;
constexpr int64_t kMaxSlope = INT32_MAX;
constexpr uint32_t kFr = kOrthoSlopeFractionBits;

// The plane's part at texel (px, py), floor((D_x px + D_y py + 32) / 64): the rasteriser's expression.
int64_t planeAt(Slope s, uint32_t px, uint32_t py) {
    return depthPlaneSlopeAt(s.first, s.second, px, py);
}

// One class of a chunk: value = A + plane + (k << sh), or the raw value when b == 32.
struct ClassCode {
    uint32_t a = 0, sh = 0, b = 0;
    Slope slope{0, 0};
    std::vector<uint32_t> k; // one factor per slot of the class, in slot order
};

// The decoder's uint32 arithmetic (dagmhChunkValue, shaders/static/dagmh_decode.h).
uint32_t decodeClass(const ClassCode& c, const Val& v, uint32_t f) {
    if (c.b == 32) return f;
    const uint32_t bx = uint32_t(c.slope.first >> kFr), by = uint32_t(c.slope.second >> kFr);
    constexpr int64_t kMask = (int64_t(1) << kFr) - 1;
    const uint32_t fx = uint32_t(c.slope.first & kMask), fy = uint32_t(c.slope.second & kMask);
    return c.a + bx * v.px + by * v.py + ((fx * v.px + fy * v.py + (1u << (kFr - 1))) >> kFr) + (f << c.sh);
}

// The factors of the slots `v` under a fixed slope: A = min w, k = ceil((u - A) / 2^sh) with the lattice
// step 2^sh no wider than the narrowest interval, so every residual interval holds a lattice point. Each
// slot is decoded with the decoder's uint32 arithmetic; any miss (or b >= 32) makes the class raw.
ClassCode fitClass(const std::vector<const Val*>& v, Slope s) {
    ClassCode out;
    out.slope = s;
    out.k.assign(v.size(), 0);
    if (v.empty()) return out;
    int64_t maxU = INT64_MIN, minW = INT64_MAX;
    uint64_t minWidth = UINT64_MAX;
    for (const Val* p : v) {
        const int64_t pr = planeAt(s, p->px, p->py);
        maxU = std::max(maxU, int64_t(p->lo) - pr), minW = std::min(minW, int64_t(p->hi) - pr);
        minWidth = std::min<uint64_t>(minWidth, uint64_t(p->hi) - p->lo);
    }
    const uint32_t sh = std::min<uint32_t>(31, uint32_t(std::bit_width(minWidth + 1)) - 1);
    const uint64_t steps = maxU > minW ? (uint64_t(maxU - minW) + (uint64_t(1) << sh) - 1) >> sh : 0;
    out.b = uint32_t(std::bit_width(steps)), out.sh = sh, out.a = uint32_t(uint64_t(minW));
    bool ok = out.b < 32;
    for (size_t i = 0; i < v.size() && ok; ++i) {
        const int64_t u = int64_t(v[i]->lo) - planeAt(s, v[i]->px, v[i]->py);
        out.k[i] = u > minW ? uint32_t((uint64_t(u - minW) + (uint64_t(1) << sh) - 1) >> sh) : 0u;
        const uint32_t d = decodeClass(out, *v[i], out.k[i]);
        ok = d >= v[i]->lo && d <= v[i]->hi;
    }
    if (!ok) {
        out.b = 32, out.a = out.sh = 0, out.slope = {0, 0};
        for (size_t i = 0; i < v.size(); ++i) out.k[i] = v[i]->lo;
    }
    return out;
}

// Spread of the residual intervals under a slope: max(lo - P) - min(hi - P), nearly convex and piecewise
// linear in the slope (the plane's floor adds at most 1); the factor width follows its log2.
int64_t spread(const std::vector<const Val*>& v, int64_t bx, int64_t by) {
    int64_t maxU = INT64_MIN, minW = INT64_MAX;
    for (const Val* p : v) {
        const int64_t pr = planeAt({bx, by}, p->px, p->py);
        maxU = std::max(maxU, int64_t(p->lo) - pr), minW = std::min(minW, int64_t(p->hi) - pr);
    }
    return maxU - minW;
}

// The slope of smallest spread (1/64 units): least squares on the interval midpoints as the start, then a
// pattern search over the 8 neighbours with steps 2^18 .. 1, against the zero slope.
Slope searchSlope(const std::vector<const Val*>& v) {
    const size_t m = v.size();
    int64_t bx = 0, by = 0, best = m ? spread(v, 0, 0) : 0;
    if (m < 2 || best <= 0) return {0, 0};
    double mx = 0, my = 0, mv = 0;
    for (const Val* p : v) mx += p->px, my += p->py, mv += (double(p->lo) + double(p->hi)) * 0.5;
    mx /= double(m), my /= double(m), mv /= double(m);
    double sxx = 0, sxy = 0, syy = 0, sxv = 0, syv = 0;
    for (const Val* p : v) {
        const double dx = p->px - mx, dy = p->py - my, dv = (double(p->lo) + double(p->hi)) * 0.5 - mv;
        sxx += dx * dx, sxy += dx * dy, syy += dy * dy, sxv += dx * dv, syv += dy * dv;
    }
    const double det = sxx * syy - sxy * sxy;
    double fx = 0, fy = 0;
    if (det > 1e-9 * std::max(1.0, sxx * syy))
        fx = (syy * sxv - sxy * syv) / det, fy = (sxx * syv - sxy * sxv) / det;
    else if (sxx > 0)
        fx = sxv / sxx;
    else if (syy > 0)
        fy = syv / syy;
    auto clampS = [](double f) {
        return int64_t(
            std::llround(std::clamp(f * double(1u << kFr), double(-kMaxSlope), double(kMaxSlope))));
    };
    const int64_t cx = clampS(fx), cy = clampS(fy);
    if (const int64_t s = spread(v, cx, cy); s < best) best = s, bx = cx, by = cy;
    static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1}, kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
    for (int64_t step = int64_t(1) << 18; step >= 1 && best > 0; step >>= 1)
        for (int iter = 0; iter < 64; ++iter) {
            bool moved = false;
            for (int d = 0; d < 8; ++d) {
                const int64_t nx = bx + kDx[d] * step, ny = by + kDy[d] * step;
                if (nx > kMaxSlope || nx < -kMaxSlope || ny > kMaxSlope || ny < -kMaxSlope) continue;
                if (const int64_t t = spread(v, nx, ny); t < best) best = t, bx = nx, by = ny, moved = true;
            }
            if (!moved) break;
        }
    return {bx, by};
}

// The slope table: entry 0 is the zero slope; a slope is added when a class's code with it (charged the
// entry's 64 bits) beats the codes with the zero slope and the recently used entries. Directional maps
// share few slopes (every horizontal surface has the same one), so most classes reuse an entry.
struct SlopeTable {
    std::vector<Slope> entries{{0, 0}};
    std::map<Slope, uint32_t> index{{{0, 0}, 0u}};
    std::vector<uint32_t> recent; // most recent first, distinct, at most kRecent
    // Spot maps' neighbouring chunks differ in slope by the perspective; a near entry costs fewer bits
    // than a new one (6 entries: 2.2 % more factor and slope bytes on the night city's spots 0-7 at 4096^2).
    static constexpr size_t kRecent = 16;

    void use(uint32_t e) {
        recent.erase(std::remove(recent.begin(), recent.end(), e), recent.end());
        recent.insert(recent.begin(), e);
        if (recent.size() > kRecent) recent.pop_back();
    }
};

// The best code for one class: the searched slope (new entries cost 64 bits), the zero slope and the
// recent entries. Returns the code and its cost in bits.
std::pair<ClassCode, uint64_t> bestClass(const std::vector<const Val*>& v, const SlopeTable& t, bool search) {
    ClassCode best = fitClass(v, {0, 0});
    uint64_t bestBits = uint64_t(v.size()) * best.b;
    auto consider = [&](Slope s, uint64_t extra) {
        ClassCode c = fitClass(v, s);
        const uint64_t bits = uint64_t(v.size()) * c.b + (c.b == 32 ? 0 : extra);
        if (bits < bestBits) bestBits = bits, best = std::move(c);
    };
    for (uint32_t e : t.recent) consider(t.entries[e], 0);
    if (search && bestBits > 0) {
        const Slope s = searchSlope(v);
        consider(s, t.index.count(s) ? 0 : 64);
    }
    return {std::move(best), bestBits};
}

struct ChunkCode {
    uint32_t mask = 0; // bit j: slot j is in class 1
    ClassCode c[2];
    uint64_t bits = UINT64_MAX;
};

// Chooses the split of a chunk's slots into two classes. Candidates: everything in class 0; each distinct
// maximal coverage set (the slots whose intervals share a point, up to 8) as class 1 (a class that
// needs no factor); the slots at least 2^t wide for each width level t present (closed casters next to
// open ones: a roof slab's wide intervals and the ground's one-point intervals on different planes); and
// twice, under the best class-0 plane so far, the slots whose residual lies beyond its median by more
// than 1.5 median deviations (a second surface) and the coverage sets of the two slots at the extremes
// of the residual spread. The fewest factor bits (with new slope entries) win.
ChunkCode encodeChunk(const Val* vals, uint32_t count, const SlopeTable& table) {
    std::vector<uint32_t> masks{0u};
    auto coverage = [&](uint32_t p) {
        uint32_t mask = 0;
        for (uint32_t j = 0; j < count; ++j)
            if (vals[j].lo <= p && p <= vals[j].hi) mask |= 1u << j;
        return mask;
    };
    {
        uint32_t bestCov = 0;
        std::vector<uint32_t> maxSets;
        for (uint32_t i = 0; i < count; ++i) {
            const uint32_t mask = coverage(vals[i].lo), cov = uint32_t(std::popcount(mask));
            if (cov > bestCov) bestCov = cov, maxSets.clear();
            if (cov == bestCov) maxSets.push_back(mask);
        }
        std::sort(maxSets.begin(), maxSets.end());
        maxSets.erase(std::unique(maxSets.begin(), maxSets.end()), maxSets.end());
        if (bestCov >= 2)
            masks.insert(masks.end(), maxSets.begin(), maxSets.begin() + std::min<size_t>(8, maxSets.size()));
        uint64_t levels = 0; // bit t: some slot's width has bit width t
        for (uint32_t j = 0; j < count; ++j)
            levels |= uint64_t(1) << std::bit_width(uint64_t(vals[j].hi) - vals[j].lo);
        for (uint32_t t = 1; t < 34; ++t) {
            if (!((levels >> t) & 1u) || !(levels & ((uint64_t(1) << t) - 1))) continue;
            uint32_t mask = 0;
            for (uint32_t j = 0; j < count; ++j)
                if (uint64_t(vals[j].hi) - vals[j].lo >= (uint64_t(1) << (t - 1))) mask |= 1u << j;
            masks.push_back(mask);
        }
    }
    ChunkCode best;
    std::vector<uint32_t> tried;
    std::vector<const Val*> cls[2];
    auto tryMask = [&](uint32_t mask) {
        if (std::find(tried.begin(), tried.end(), mask) != tried.end()) return;
        tried.push_back(mask);
        cls[0].clear(), cls[1].clear();
        for (uint32_t j = 0; j < count; ++j) cls[(mask >> j) & 1u].push_back(&vals[j]);
        ChunkCode c;
        c.mask = mask;
        auto [c1, bits1] = bestClass(cls[1], table, true);
        if (bits1 >= best.bits) return;
        auto [c0, bits0] = bestClass(cls[0], table, true);
        c.c[0] = std::move(c0), c.c[1] = std::move(c1), c.bits = bits0 + bits1;
        if (c.bits < best.bits) best = std::move(c);
    };
    for (uint32_t mask : masks) tryMask(mask);
    bool haveChunkSlope = false;
    Slope chunkSlope{0, 0};
    for (int round = 0; round < 2 && best.bits > 0; ++round) {
        // Under the best class-0 plane so far, or (its class raw: one outlier, such as an empty texel among
        // a plane's values, spreads it past 31 bits) under the slope searched over the whole chunk, once.
        ClassCode p = best.c[0]; // a copy: tryMask may replace best
        if (p.b == 32) {
            if (!haveChunkSlope) {
                std::vector<const Val*> all;
                for (uint32_t j = 0; j < count; ++j) all.push_back(&vals[j]);
                chunkSlope = searchSlope(all), haveChunkSlope = true;
            }
            p.slope = chunkSlope;
        }
        std::vector<int64_t> r(count);
        for (uint32_t j = 0; j < count; ++j)
            r[j] = (int64_t(vals[j].lo) + int64_t(vals[j].hi)) / 2 - planeAt(p.slope, vals[j].px, vals[j].py);
        std::vector<int64_t> s = r;
        std::nth_element(s.begin(), s.begin() + count / 2, s.end());
        const int64_t med = s[count / 2];
        for (auto& x : s) x = std::abs(x - med);
        std::nth_element(s.begin(), s.begin() + count / 2, s.end());
        const int64_t dev = s[count / 2];
        uint32_t mask = 0;
        for (uint32_t j = 0; j < count; ++j)
            if (std::abs(r[j] - med) > dev + (dev >> 1) + 1) mask |= 1u << j;
        tryMask(mask);
        // The coverage sets of the two slots at the extremes of the residual spread under that plane: an
        // off-plane group (empty texels, a second surface) that shares a point is then a class of its own.
        int64_t maxU = INT64_MIN, minW = INT64_MAX;
        uint32_t jU = 0, jW = 0;
        for (uint32_t j = 0; j < count; ++j) {
            const int64_t pr = planeAt(p.slope, vals[j].px, vals[j].py);
            const int64_t u = int64_t(vals[j].lo) - pr, w = int64_t(vals[j].hi) - pr;
            if (u > maxU) maxU = u, jU = j;
            if (w < minW) minW = w, jW = j;
        }
        tryMask(coverage(vals[jU].lo));
        tryMask(coverage(vals[jW].lo));
    }
    return best;
}

// The chosen split's classes of 1-2 bit factors at step 1 once more (one-point values: an open surface),
// each slope tried at its 17 x 17 neighbours (1/64 units): a class on one rasterised plane lies within a
// few steps of its slope after the search, but near it the spread is flat up to the plane's floor (0 or
// 1), where the pattern search stops. The fewest factor bits win (a new table entry charged 64 bits).
void refineClasses(const Val* vals, uint32_t count, ChunkCode& code, const SlopeTable& table) {
    constexpr int64_t kRadius = 8;
    for (int k = 0; k < 2; ++k) {
        ClassCode& c = code.c[k];
        if (c.b == 0 || c.b > 2 || c.sh != 0 || c.k.empty()) continue;
        std::vector<const Val*> v;
        for (uint32_t j = 0; j < count; ++j)
            if (((code.mask >> j) & 1u) == uint32_t(k)) v.push_back(&vals[j]);
        const Slope s0 = c.slope;
        uint64_t bestBits = uint64_t(v.size()) * c.b + (table.index.count(s0) ? 0 : 64);
        for (int64_t dy = -kRadius; dy <= kRadius; ++dy)
            for (int64_t dx = -kRadius; dx <= kRadius; ++dx) {
                const Slope s{s0.first + dx, s0.second + dy};
                if ((dx == 0 && dy == 0) || std::abs(s.first) > kMaxSlope || std::abs(s.second) > kMaxSlope)
                    continue;
                ClassCode t = fitClass(v, s);
                const uint64_t bits = uint64_t(v.size()) * t.b + (t.b == 32 || table.index.count(s) ? 0 : 64);
                if (t.b < 32 && bits < bestBits) bestBits = bits, c = std::move(t);
            }
    }
}

} // namespace

// A chunk's plane slots (planar tree values): their plane table indices, renumbered in the order of
// first use so that a chunk's indices lie close (width: the bit width of their spread).
struct PlanarCode {
    uint32_t mask = 0, base = 0, b = 0;
    std::vector<uint32_t> k; // one index offset per plane slot, in slot order
};

Result<Sections> encodeValues(const std::vector<Val>& vals, const std::vector<DepthPlane>& planes,
                              Stats* stats) {
    using namespace dagfmt;
    Sections out;
    SlopeTable table;
    // Plane ids (1-based into `planes`) -> plane table entries, in the order the values first use them.
    std::vector<uint32_t> renumbered(planes.size(), UINT32_MAX);
    uint32_t used = 0;
    for (const Val& v : vals) {
        if (!v.plane) continue;
        if (v.plane > planes.size())
            return fail("DAG-MH: a value names plane " + std::to_string(v.plane) + " of " +
                        std::to_string(planes.size()));
        if (renumbered[v.plane - 1] != UINT32_MAX) continue;
        if (used >= kMaxPlanes) return fail("DAG-MH: plane table exceeds 2^27 entries");
        renumbered[v.plane - 1] = used++;
        const DepthPlane& q = planes[v.plane - 1];
        out.planes.push_back(uint32_t(uint64_t(q.a))), out.planes.push_back(uint32_t(q.dx));
        out.planes.push_back(uint32_t(q.dy));
    }
    const uint32_t numValues = uint32_t(vals.size());
    const uint32_t numChunks = (numValues + kChunkValues - 1) / kChunkValues;
    const uint32_t cw = chunkWords(used);
    out.chunks.assign(size_t(numChunks) * cw, 0);
    uint64_t bitPos = 0;
    auto put = [&](uint32_t k, uint32_t bits) {
        for (uint32_t bit = 0; bit < bits; ++bit, ++bitPos) {
            if ((bitPos >> 5) >= out.factors.size()) out.factors.push_back(0);
            if ((k >> bit) & 1u) out.factors[bitPos >> 5] |= 1u << (bitPos & 31);
        }
    };
    for (uint32_t c = 0; c < numChunks; ++c) {
        const uint32_t count = std::min(kChunkValues, numValues - c * kChunkValues);
        const Val* cv = &vals[size_t(c) * kChunkValues];
        // The plane slots apart; the others (compacted, in slot order) split into the two classes.
        PlanarCode pc;
        uint32_t lo = UINT32_MAX, hi = 0;
        for (uint32_t j = 0; j < count; ++j) {
            if (!cv[j].plane) continue;
            pc.mask |= 1u << j;
            const uint32_t idx = renumbered[cv[j].plane - 1];
            lo = std::min(lo, idx), hi = std::max(hi, idx);
            pc.k.push_back(idx);
        }
        // The class slots: the chunk's values as they stand, or (plane slots present) the others copied
        // out in slot order, their class bits spread back to the slots afterwards.
        std::vector<Val> rest;
        std::vector<uint32_t> slotOf;
        if (pc.mask) {
            pc.base = lo, pc.b = uint32_t(std::bit_width(hi - lo));
            for (uint32_t& k : pc.k) k -= lo;
            for (uint32_t j = 0; j < count; ++j)
                if (!cv[j].plane) rest.push_back(cv[j]), slotOf.push_back(j);
        }
        const Val* classVals = pc.mask ? rest.data() : cv;
        const uint32_t classCount = pc.mask ? uint32_t(rest.size()) : count;
        ChunkCode code;
        if (classCount) {
            code = encodeChunk(classVals, classCount, table);
            refineClasses(classVals, classCount, code, table);
        }
        if (pc.mask) {
            uint32_t classMask = 0;
            for (size_t r = 0; r < slotOf.size(); ++r)
                if ((code.mask >> r) & 1u) classMask |= 1u << slotOf[r];
            code.mask = classMask;
        }
        uint32_t entry[2];
        for (int k = 0; k < 2; ++k) {
            auto [it, added] = table.index.try_emplace(code.c[k].slope, uint32_t(table.entries.size()));
            if (added) {
                if (table.entries.size() >= kMaxSlopes)
                    return fail("DAG-MH: slope table exceeds 65536 entries");
                table.entries.push_back(code.c[k].slope);
            }
            entry[k] = it->second;
            if (!code.c[k].k.empty() && code.c[k].b != 32 && it->second != 0) table.use(it->second);
        }
        if (bitPos + uint64_t(count) * 32 > kMaxFactorBits)
            return fail("DAG-MH: factor stream exceeds 512 MiB");
        uint32_t* w = &out.chunks[size_t(c) * cw];
        w[0] = code.mask, w[1] = code.c[0].a, w[2] = code.c[1].a;
        w[3] = code.c[0].b | code.c[0].sh << 6 | code.c[1].b << 11 | code.c[1].sh << 17;
        w[4] = uint32_t(bitPos), w[5] = entry[0] | entry[1] << 16;
        if (cw == kPlanarChunkWords) w[6] = pc.mask, w[7] = pc.base | pc.b << kPlanarWidthShift;
        for (uint32_t k : pc.k) put(k, pc.b); // the plane indices first
        if (stats) stats->planarValues += pc.k.size(), stats->factorBits += uint64_t(pc.k.size()) * pc.b;
        for (int k : {1, 0}) { // class 1's factors first: a class-0 slot skips popcount(mask) of them
            for (uint32_t f : code.c[k].k) put(f, code.c[k].b);
            if (stats) {
                stats->rawClasses += code.c[k].b == 32 && !code.c[k].k.empty();
                stats->factors += code.c[k].b ? code.c[k].k.size() : 0;
                stats->factorBits += uint64_t(code.c[k].k.size()) * code.c[k].b;
            }
        }
    }
    for (const Slope& s : table.entries)
        out.slopes.push_back(uint32_t(s.first)), out.slopes.push_back(uint32_t(s.second));
    return out;
}

} // namespace ml::dagval
