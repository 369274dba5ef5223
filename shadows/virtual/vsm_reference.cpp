// CPU twins of vsm_mark.comp (through vsm_common.glsl's choice of map, mip and kernel) and of the
// allocation passes vsm_scan / vsm_alloc / vsm_assign. Same functions of vsm_math.h, same order.
#include "shadows/virtual/vsm_reference.h"

#include "shadows/virtual/vsm_bounds.h"

#include <algorithm>
#include <bit>

namespace ml {

namespace {

using namespace gpu;

bool testBit(const std::vector<uint32_t>& bits, uint32_t i) {
    return (bits[i >> 5] >> (i & 31u)) & 1u;
}

struct Choice {
    uint32_t map = 0, mip = 0, last = 0;
    VsmTap tap{};
};

// vsm_common.glsl's vsmChoose.
Choice choose(const VsmMarkInputs& in, const GpuLight& L, uint32_t firstMap, glm::vec3 P, glm::vec3 N) {
    Choice c;
    c.map = firstMap;
    c.tap.ok = 0;
    const VsmConstants& k = in.constants;
    const uint32_t R = k.options.z;
    const float footprint =
        vsmFootprint(glm::vec3(in.frame.cameraPosition), P, vsmPerMetre(k.camera.x, in.maps[firstMap]));
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        const uint32_t levels = in.maps[firstMap].light.z;
        const uint32_t level = vsmPickLevel(in.maps[firstMap], footprint, R, levels);
        c.last = firstMap + levels - 1;
        for (uint32_t l = level; l < levels; ++l) {
            c.map = firstMap + l;
            c.tap = vsmLocate(in.maps[c.map], R, 0, P, N);
            if (c.tap.ok) break;
        }
        return c;
    }
    if (L.info.x == ML_LIGHT_POINT) c.map = firstMap + pointLightFace(P - glm::vec3(L.positionRange));
    const GpuVsmMap& map = in.maps[c.map];
    glm::vec3 vp = vsmPoint(map.view, P);
    if (!(-vp.z > map.params.y)) return c;
    const uint32_t mips = k.page.w;
    c.mip = vsmPickMip(vsmTexel0(map, vp, R), footprint, mips);
    c.last = mips - 1;
    c.tap = vsmLocate(map, R, c.mip, P, N);
    return c;
}

void markKernel(const VsmMarkInputs& in, std::vector<uint32_t>& marks, uint32_t map, uint32_t mip, VsmTap tap,
                int radius, size_t region) {
    if (!tap.ok) return;
    const VsmConstants& k = in.constants;
    const int res = int(k.options.z >> mip);
    glm::ivec2 lo = glm::clamp(tap.texel - radius, glm::ivec2(0), glm::ivec2(res - 1));
    glm::ivec2 hi = glm::clamp(tap.texel + radius, glm::ivec2(0), glm::ivec2(res - 1));
    const int shift = int(k.page.y);
    for (int py = lo.y >> shift; py <= (hi.y >> shift); ++py)
        for (int px = lo.x >> shift; px <= (hi.x >> shift); ++px) {
            uint32_t entry = vsmEntry(k.sizes.x, k.page.z, map, mip, uint32_t(px), uint32_t(py));
            bool needs = (in.maps[map].info.y & ML_VSM_MAP_DYNAMIC_ONLY) == 0 || testBit(in.coverage, entry);
            if (needs) marks[region + (entry >> 5)] |= 1u << (entry & 31u);
        }
}

// vsm_common.glsl's vsmMarkReceiver: the pages the lookup of (P, N) reads, and its fallback reservations.
void markReceiver(const VsmMarkInputs& in, std::vector<uint32_t>& marks, const GpuLight& L, glm::vec3 P,
                  glm::vec3 N) {
    const int radius = int(in.constants.options.x);
    const uint32_t R = in.constants.options.z;
    Choice c = choose(in, L, L.info.y, P, N);
    if (!c.tap.ok) return;
    markKernel(in, marks, c.map, c.mip, c.tap, radius, 0);
    if (in.constants.camera.z == 0.0f) return; // no fallback reservations this frame
    const size_t fw = in.markWords;
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        uint32_t fb = std::min(c.map + ML_VSM_FALLBACK_MIPS, c.last);
        if (fb != c.map) markKernel(in, marks, fb, 0, vsmLocate(in.maps[fb], R, 0, P, N), radius, fw);
        if (c.last != fb)
            markKernel(in, marks, c.last, 0, vsmLocate(in.maps[c.last], R, 0, P, N), radius, fw);
    } else {
        const int wide = radius + vsmFallbackSlack(in.maps[c.map]);
        uint32_t fb = std::min(c.mip + ML_VSM_FALLBACK_MIPS, c.last);
        if (fb != c.mip) markKernel(in, marks, c.map, fb, vsmCoarserTap(c.tap, fb - c.mip), wide, fw);
        if (c.last != fb)
            markKernel(in, marks, c.map, c.last, vsmCoarserTap(c.tap, c.last - c.mip), radius, fw);
    }
}

// clusterLights (shaders/shared/cluster_list.glsl): the pixel's slice and its (offset, count).
uint32_t sliceOf(const VsmMarkInputs& in, float d) {
    const float z = linearDepth(d, in.frame.depth);
    uint32_t s = 0;
    while (s + 1 < in.frame.cluster.x && z >= in.sliceFar[s]) ++s;
    return s;
}

// vsm_common.glsl's vsmMarkPages.
uint32_t markPages(const VsmMarkInputs& in, std::vector<uint32_t>& marks, uint32_t map, uint32_t mip,
                   glm::ivec4 pages, size_t region, bool mark) {
    const uint32_t n = vsmRectPageCount(pages);
    if (!mark || n == 0) return n;
    const VsmConstants& k = in.constants;
    for (int py = pages.y; py <= pages.w; ++py)
        for (int px = pages.x; px <= pages.z; ++px) {
            uint32_t entry = vsmEntry(k.sizes.x, k.page.z, map, mip, uint32_t(px), uint32_t(py));
            bool needs = (in.maps[map].info.y & ML_VSM_MAP_DYNAMIC_ONLY) == 0 || testBit(in.coverage, entry);
            if (needs) marks[region + (entry >> 5)] |= 1u << (entry & 31u);
        }
    return n;
}

// vsm_common.glsl's vsmBoxPages: same calls, same order.
uint32_t boxPages(const VsmMarkInputs& in, std::vector<uint32_t>& marks, const GpuLight& L, uint32_t firstMap,
                  glm::vec3 lo, glm::vec3 hi, glm::vec3 nlo, glm::vec3 nhi, bool mark) {
    const VsmConstants& k = in.constants;
    const uint32_t R = k.options.z, shift = k.page.y;
    const int radius = int(k.options.x);
    const bool reserve = k.camera.z != 0.0f;
    const size_t fw = in.markWords;
    const float perMetre = vsmPerMetre(k.camera.x, in.maps[firstMap]); // the light's texel scale
    const glm::vec2 fp = vsmFootprintRange(glm::vec3(in.frame.cameraPosition), lo, hi, perMetre);
    uint32_t n = 0;
    auto level = [&](uint32_t l, size_t region, glm::vec3 wlo, glm::vec3 whi) {
        const GpuVsmMap& map = in.maps[firstMap + l];
        VsmTapRect t =
            vsmBoxTaps(map, R, 0, vsmViewBox(map.view, wlo, whi), vsmNormalViewBox(map.view, nlo, nhi));
        if (t.ok)
            n += markPages(in, marks, firstMap + l, 0, vsmRectPages(t.texels, 0, radius, R, 0, shift), region,
                           mark);
        return t;
    };
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        const uint32_t levels = in.maps[firstMap].light.z, last = levels - 1;
        const uint32_t a = vsmPickLevel(in.maps[firstMap], fp.x, R, levels);
        const uint32_t b = vsmPickLevel(in.maps[firstMap], fp.y, R, levels);
        uint32_t stop = last;
        const glm::vec3 camera(in.frame.cameraPosition);
        for (uint32_t l = a; l < levels; ++l) {
            const VsmBox w = vsmLevelBox(in.maps[firstMap], camera, lo, hi, perMetre, R, l, levels);
            if (vsmBoxEmpty(w)) continue; // no receiver matches this level or a finer one
            VsmTapRect t = level(l, 0, w.lo, w.hi);
            if (l >= b && t.held) {
                stop = l;
                break;
            }
        }
        if (!reserve) return n;
        const uint32_t f1 = std::min(stop + ML_VSM_FALLBACK_MIPS, last);
        for (uint32_t l = std::min(a + ML_VSM_FALLBACK_MIPS, last); l <= f1; ++l) level(l, fw, lo, hi);
        if (f1 != last) level(last, fw, lo, hi);
        return n;
    }
    const uint32_t faces = L.info.x == ML_LIGHT_POINT ? 6 : 1;
    const uint32_t mips = k.page.w, last = mips - 1;
    for (uint32_t f = 0; f < faces; ++f) {
        const uint32_t m = firstMap + f;
        const GpuVsmMap& map = in.maps[m];
        const VsmViewBox vb = vsmViewBox(map.view, lo, hi), nb = vsmNormalViewBox(map.view, nlo, nhi);
        const glm::uvec2 range = vsmBoxMips(map, vb, fp, R, mips);
        const int wide = radius + vsmFallbackSlack(map);
        for (uint32_t mip = range.x; mip <= range.y; ++mip) {
            const VsmViewBox mb =
                vsmMipView(map, vb, lo, hi, glm::vec3(in.frame.cameraPosition), fp, perMetre, R, mip, mips);
            if (!(mb.lo.x <= mb.hi.x && mb.lo.y <= mb.hi.y && mb.lo.z <= mb.hi.z)) continue;
            VsmTapRect t = vsmBoxTaps(map, R, mip, mb, nb);
            if (!t.ok) continue;
            n += markPages(in, marks, m, mip, vsmRectPages(t.texels, 0, radius, R, mip, shift), 0, mark);
            if (!reserve) continue;
            const uint32_t fb = std::min(mip + ML_VSM_FALLBACK_MIPS, last);
            if (fb != mip)
                n += markPages(in, marks, m, fb, vsmRectPages(t.texels, fb - mip, wide, R, fb, shift), fw,
                               mark);
            if (last != fb)
                n += markPages(in, marks, m, last, vsmRectPages(t.texels, last - mip, wide, R, last, shift),
                               fw, mark);
        }
    }
    return n;
}

// cluster_bounds.comp's order-preserving key: min / max on keys order -0 before +0, as the GPU does.
uint32_t toKey(float f) {
    const uint32_t u = std::bit_cast<uint32_t>(f);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}
float fromKey(uint32_t k) {
    return std::bit_cast<float>((k & 0x80000000u) ? (k & 0x7fffffffu) : ~k);
}

} // namespace

std::vector<uint32_t> vsmMarkReference(const VsmMarkInputs& in) {
    std::vector<uint32_t> marks(2 * in.markWords, 0); // lookup marks, then fallback marks
    const FrameConstants& f = in.frame;
    const uint32_t width = f.size.x, height = f.size.y;
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const float d = in.depth[size_t(y) * width + x];
            if (!gpu::hasSurface(d)) continue;
            glm::vec3 P = worldFromPixel(x, y, d, f.invViewProj, f.size);
            const glm::vec4 stored = in.normal[size_t(y) * width + x];
            if (stored.w < 0.0f) continue; // not a receiver
            glm::vec3 N = vsmNormalize(glm::vec3(stored));
            uint32_t offset = ML_CLUSTER_OVERFLOW, count = f.cluster.z;
            if (f.cluster.w != ML_CULL_NONE) {
                const uint32_t tx = x / f.cluster.y, ty = y / f.cluster.y;
                glm::uvec2 r = in.ranges[(size_t(ty) * f.size.z + tx) * f.cluster.x + sliceOf(in, d)];
                if (r.x != ML_CLUSTER_OVERFLOW) offset = r.x, count = r.y;
            }
            for (uint32_t i = 0; i < count; ++i) {
                const GpuLight& L = in.lights[offset == ML_CLUSTER_OVERFLOW ? i : in.pool[offset + i]];
                if (L.info.y == ML_VSM_NO_MAP || !lightReachesPoint(L, P) || !vsmFacesLight(L, P, N))
                    continue;
                markReceiver(in, marks, L, P, N);
            }
        }
    return marks;
}

std::vector<uint32_t> vsmMarkClusterReference(const VsmMarkInputs& in, size_t* refinedPairs,
                                              size_t* facingAwayPairs) {
    std::vector<uint32_t> marks(2 * in.markWords, 0);
    const FrameConstants& f = in.frame;
    const uint32_t width = f.size.x, height = f.size.y, T = ML_TILE_SIZE, slices = f.cluster.x;
    struct Pixel {
        glm::vec3 P, N;
        uint32_t slice;
        bool receiver;
    };
    std::vector<Pixel> pixels;
    auto lightOf = [&](glm::uvec2 r, uint32_t i) -> const GpuLight& {
        return in.lights[r.x == ML_CLUSTER_OVERFLOW ? i : in.pool[r.x + i]];
    };
    auto countOf = [&](glm::uvec2 r) { return r.x == ML_CLUSTER_OVERFLOW ? f.cluster.z : r.y; };
    auto markPixel = [&](const Pixel& p, const GpuLight& L) {
        if (L.info.y != ML_VSM_NO_MAP && lightReachesPoint(L, p.P) && vsmFacesLight(L, p.P, p.N))
            markReceiver(in, marks, L, p.P, p.N);
    };
    for (uint32_t ty = 0; ty * T < height; ++ty)
        for (uint32_t tx = 0; tx * T < width; ++tx) {
            // cluster_bounds.comp's receiver variant: per slice the world AABB of the receivers and the
            // codes of their unit normals (keys and codes, as the GPU reduces).
            pixels.clear();
            std::vector<glm::uvec3> lo(slices, glm::uvec3(0xFFFFFFFFu)), hi(slices, glm::uvec3(0u));
            std::vector<glm::uvec3> nlo(slices, glm::uvec3(1023u)), nhi(slices, glm::uvec3(0u));
            for (uint32_t y = ty * T; y < std::min(height, ty * T + T); ++y)
                for (uint32_t x = tx * T; x < std::min(width, tx * T + T); ++x) {
                    const float d = in.depth[size_t(y) * width + x];
                    if (!gpu::hasSurface(d)) continue;
                    const glm::vec4 stored = in.normal[size_t(y) * width + x];
                    const Pixel p{worldFromPixel(x, y, d, f.invViewProj, f.size),
                                  vsmNormalize(glm::vec3(stored)), sliceOf(in, d), !(stored.w < 0.0f)};
                    pixels.push_back(p);
                    if (!p.receiver) continue;
                    const glm::vec3 u = clusterUnitNormal(glm::vec3(stored));
                    for (int c = 0; c < 3; ++c) {
                        lo[p.slice][c] = std::min(lo[p.slice][c], toKey(p.P[c]));
                        hi[p.slice][c] = std::max(hi[p.slice][c], toKey(p.P[c]));
                        nlo[p.slice][c] = std::min(nlo[p.slice][c], clusterNormalCode(u[c], false));
                        nhi[p.slice][c] = std::max(nhi[p.slice][c], clusterNormalCode(u[c], true));
                    }
                }
            const size_t tile = size_t(ty) * f.size.z + tx;
            std::vector<glm::uvec2> refine; // (slice, light index in its list)
            for (uint32_t s = 0; s < slices; ++s) {
                if (lo[s].x == 0xFFFFFFFFu) continue; // no receiver in the cluster
                const glm::vec3 blo(fromKey(lo[s].x), fromKey(lo[s].y), fromKey(lo[s].z));
                const glm::vec3 bhi(fromKey(hi[s].x), fromKey(hi[s].y), fromKey(hi[s].z));
                ClusterReceivers rb{};
                rb.normalLo = nlo[s].x | (nlo[s].y << 10) | (nlo[s].z << 20);
                rb.normalHi = nhi[s].x | (nhi[s].y << 10) | (nhi[s].z << 20) | ML_CLUSTER_HAS_RECEIVER;
                const glm::vec3 nl = vsmNormalLo(rb), nh = vsmNormalHi(rb);
                const glm::uvec2 r = in.ranges[tile * slices + s];
                for (uint32_t i = 0; i < countOf(r); ++i) {
                    const GpuLight& L = lightOf(r, i);
                    if (L.info.y == ML_VSM_NO_MAP || !lightTouchesBox(L, blo, bhi)) continue;
                    const VsmBox reach = vsmReachBox(L, blo, bhi);
                    if (vsmBoxEmpty(reach)) continue;
                    if (vsmBoxFacesAway(L, reach.lo, reach.hi, nl, nh)) {
                        if (facingAwayPairs) ++*facingAwayPairs;
                        continue;
                    }
                    // The box, or its two halves where they count fewer pages, from 4 pages on
                    // (vsm_mark_cluster.comp).
                    const uint32_t whole =
                        boxPages(in, marks, L, L.info.y, reach.lo, reach.hi, nl, nh, false);
                    const VsmBox h0 = vsmHalfBox(reach, 0), h1 = vsmHalfBox(reach, 1);
                    const bool use0 = !vsmBoxEmpty(h0) && !vsmBoxFacesAway(L, h0.lo, h0.hi, nl, nh);
                    const bool use1 = !vsmBoxEmpty(h1) && !vsmBoxFacesAway(L, h1.lo, h1.hi, nl, nh);
                    const uint32_t halves =
                        whole <= 3
                            ? whole
                            : (use0 ? boxPages(in, marks, L, L.info.y, h0.lo, h0.hi, nl, nh, false) : 0) +
                                  (use1 ? boxPages(in, marks, L, L.info.y, h1.lo, h1.hi, nl, nh, false) : 0);
                    if (std::min(whole, halves) > ML_VSM_CLUSTER_PAGES) {
                        refine.push_back({s, i});
                    } else if (halves < whole) {
                        if (use0) boxPages(in, marks, L, L.info.y, h0.lo, h0.hi, nl, nh, true);
                        if (use1) boxPages(in, marks, L, L.info.y, h1.lo, h1.hi, nl, nh, true);
                    } else {
                        boxPages(in, marks, L, L.info.y, reach.lo, reach.hi, nl, nh, true);
                    }
                }
            }
            if (refinedPairs) *refinedPairs += refine.size();
            // The refined pairs from each receiver of their slice.
            for (const Pixel& p : pixels) {
                if (!p.receiver) continue;
                const glm::uvec2 r = in.ranges[tile * slices + p.slice];
                for (const glm::uvec2& pair : refine)
                    if (pair.x == p.slice) markPixel(p, lightOf(r, pair.y));
            }
        }
    return marks;
}

gpu::VsmCounters vsmAllocateReference(VsmAllocState& st, const std::vector<uint32_t>& marks,
                                      const std::vector<uint32_t>& stale,
                                      const std::vector<gpu::GpuVsmMap>& maps,
                                      const std::vector<glm::uvec4>& runs, const gpu::VsmConstants& k) {
    VsmCounters c{};
    const uint32_t s0 = k.page.z, mips = k.page.w, frame = k.sizes.w, pool = k.sizes.z;
    auto marked = [&](uint32_t e) { return testBit(marks, e); };
    auto wanted = [&](uint32_t e) {
        return marked(e) || ((marks[k.options.w + (e >> 5)] >> (e & 31u)) & 1u);
    };
    // Entries of the maps in use in priority order (vsm_alloc_common.glsl; inactive maps have no marks).
    struct Item {
        uint32_t entry, map, mip;
    };
    std::vector<Item> order;
    for (const glm::uvec4& run : runs)
        for (uint32_t p = 0; p < run.w; ++p)
            order.push_back({run.y * k.sizes.x + vsmMipOffset(s0, run.z) + p, run.y, run.z});
    (void)mips;
    // vsm_scan's invalidation: per physical page (the GPU walks the owned prefix: the rest have no owner),
    // its owner entry loses last frame's DIRTY bit, and VALID when stale (every owned page, whether or not
    // its map is active: inactive maps are invalidated whole when they become active again anyway). The
    // static twin (ML_VSM_STATIC_VALID) is lost only to the map flag, caching off, or the stale bits' second
    // region (static casters, from word k.options.w).
    for (uint32_t p = 0; p < pool; ++p) {
        const uint32_t e = st.owners[p];
        if (e == ML_VSM_NO_OWNER) continue;
        uint32_t pt = st.table[e] & ~(ML_VSM_DIRTY | ML_VSM_DIRTY_STATIC);
        const uint32_t map = e / k.sizes.x;
        const bool whole = k.options.y == 0 || (maps[map].info.y & ML_VSM_MAP_INVALIDATE);
        const bool staticStale = whole || testBit(stale, k.options.w * 32u + e);
        if (staticStale) pt &= ~ML_VSM_STATIC_VALID;
        if ((pt & ML_VSM_VALID) && (staticStale || testBit(stale, e))) {
            pt &= ~ML_VSM_VALID;
            ++c.pagesInvalidated;
            c.pagesInvalidatedCaster += whole ? 0 : 1;
        }
        st.table[e] = pt;
    }
    // vsm_scan over the request list (the wanted entries, in priority order).
    std::vector<uint32_t> requests;
    for (const Item& it : order) {
        if (!wanted(it.entry)) continue;
        c.pagesMarked += marked(it.entry);
        const uint32_t pt = st.table[it.entry];
        if (pt & ML_VSM_ALLOCATED)
            st.lastUsed[pt & ML_VSM_PHYS_MASK] = frame;
        else
            requests.push_back(it.entry);
    }
    // vsm_alloc: free pages, then unmarked owners from oldest to newest age bucket, by index.
    auto pageClass = [&](uint32_t p) -> uint32_t {
        const uint32_t owner = st.owners[p];
        if (owner == ML_VSM_NO_OWNER) return 0;
        if (wanted(owner)) return 9;
        const uint32_t age = std::max(frame - st.lastUsed[p], 1u);
        return 8 - std::min(uint32_t(std::bit_width(age) - 1), 7u);
    };
    // vsm_avail: only the first `requests` places are listed (the only ones vsm_assign reads); every
    // available page is still counted.
    std::vector<uint32_t> avail;
    uint32_t freePages = 0, available = 0;
    for (uint32_t cls = 0; cls < 9; ++cls)
        for (uint32_t p = 0; p < pool; ++p)
            if (pageClass(p) == cls) {
                if (avail.size() < requests.size()) avail.push_back(p);
                ++available;
                freePages += cls == 0;
            }
    c.requests = uint32_t(requests.size());
    c.available = available;
    c.pagesAllocated = (pool - freePages) + std::min(c.requests, freePages);
    c.pressure = c.requests > c.available ? 1 : 0;
    // vsm_assign.
    std::vector<uint8_t> failed(st.table.size(), 0), took(st.table.size(), 0);
    for (size_t r = 0; r < requests.size(); ++r) {
        const uint32_t e = requests[r];
        if (r < avail.size()) {
            const uint32_t p = avail[r];
            const uint32_t old = st.owners[p];
            if (old != ML_VSM_NO_OWNER) {
                st.table[old] = 0;
                ++c.pagesEvicted;
            }
            st.owners[p] = e;
            st.lastUsed[p] = frame;
            st.table[e] = ML_VSM_ALLOCATED | p;
            took[e] = 1;
        } else {
            ++c.fallbacks;
            failed[e] = 1;
        }
    }
    for (const Item& it : order) {
        if (!wanted(it.entry) || failed[it.entry]) continue;
        uint32_t& pt = st.table[it.entry];
        if (!(pt & ML_VSM_VALID) && (marked(it.entry) || c.pressure)) {
            const bool fromStatic = (pt & ML_VSM_STATIC_VALID) != 0;
            pt |= ML_VSM_VALID | ML_VSM_DIRTY;
            if (k.camera.w != 0.0f && !fromStatic) pt |= ML_VSM_STATIC_VALID | ML_VSM_DIRTY_STATIC;
            ++c.pagesRendered;
            ++c.dispatchX;
            c.pagesNew += took[it.entry];
            c.pagesRenderedDynamic += fromStatic ? 1 : 0;
        } else if (marked(it.entry) && (pt & ML_VSM_VALID)) {
            ++c.pagesCached;
        }
    }
    return c;
}

std::string vsmCheckInvariants(const VsmAllocState& st, const std::vector<uint32_t>& marks,
                               const std::vector<uint32_t>& active, const gpu::VsmConstants& k,
                               const gpu::VsmCounters& counters) {
    const uint32_t pool = k.sizes.z;
    std::vector<uint32_t> seen(pool, ML_VSM_NO_OWNER);
    for (uint32_t e = 0; e < st.table.size(); ++e) {
        const uint32_t pt = st.table[e];
        if (!(pt & ML_VSM_ALLOCATED)) {
            if (pt & (ML_VSM_VALID | ML_VSM_DIRTY))
                return "entry " + std::to_string(e) + " is valid or dirty without a physical page";
            continue;
        }
        const uint32_t p = pt & ML_VSM_PHYS_MASK;
        if (p >= pool) return "entry " + std::to_string(e) + " points past the pool";
        if (seen[p] != ML_VSM_NO_OWNER)
            return "physical page " + std::to_string(p) + " backs entries " + std::to_string(seen[p]) +
                   " and " + std::to_string(e);
        seen[p] = e;
        if (st.owners[p] != e)
            return "physical page " + std::to_string(p) + " is owned by " + std::to_string(st.owners[p]) +
                   " but entry " + std::to_string(e) + " points to it";
    }
    for (uint32_t p = 0; p < pool; ++p)
        if (st.owners[p] != ML_VSM_NO_OWNER && seen[p] != st.owners[p])
            return "physical page " + std::to_string(p) + " has an owner whose entry does not point to it";
    // Requests take free pages first, by index, and no page is ever freed: the owned pages are a prefix
    // of the pool, which the GPU passes walk alone (vsmOwnedPages in vsm_alloc_common.glsl).
    for (uint32_t p = 1; p < pool; ++p)
        if (st.owners[p] != ML_VSM_NO_OWNER && st.owners[p - 1] == ML_VSM_NO_OWNER)
            return "physical page " + std::to_string(p) + " is owned after free page " +
                   std::to_string(p - 1) + ": the owned pages are not a prefix of the pool";
    // Every wanted (marked or reserved) entry of an active map has a page, or is counted as a fallback.
    uint32_t unbacked = 0;
    const uint32_t s0 = k.page.z;
    for (uint32_t map : active)
        for (uint32_t i = 0; i < vsmMipOffset(s0, k.page.w); ++i) {
            const uint32_t e = map * k.sizes.x + i;
            const bool wanted = testBit(marks, e) || ((marks[k.options.w + (e >> 5)] >> (e & 31u)) & 1u);
            if (wanted && !(st.table[e] & ML_VSM_ALLOCATED)) ++unbacked;
        }
    if (unbacked != counters.fallbacks)
        return std::to_string(unbacked) + " marked entries without a page, " +
               std::to_string(counters.fallbacks) + " fallbacks counted";
    return {};
}

std::vector<gpu::GpuCasterGroup> vsmCasterGroupsReference(const std::vector<gpu::GpuCaster>& casters,
                                                          const std::vector<uint32_t>& order) {
    std::vector<gpu::GpuCasterGroup> groups((order.size() + ML_VSM_CULL_GROUP - 1) / ML_VSM_CULL_GROUP);
    for (size_t g = 0; g < groups.size(); ++g) {
        gpu::GpuCasterGroup& b = groups[g];
        b.lo = glm::vec4(1e30f, 1e30f, 1e30f, 0.0f);
        b.hi = glm::vec4(-1e30f, -1e30f, -1e30f, 0.0f);
        b.dynamicLo = b.lo;
        b.dynamicHi = b.hi;
        b.counts = glm::uvec4(0);
        for (size_t i = g * ML_VSM_CULL_GROUP; i < std::min(order.size(), (g + 1) * ML_VSM_CULL_GROUP); ++i) {
            const gpu::GpuCaster& c = casters[order[i]];
            if (c.draw.x == 0) continue;
            b.lo = glm::vec4(glm::min(glm::vec3(b.lo), glm::vec3(c.lo)), 0.0f);
            b.hi = glm::vec4(glm::max(glm::vec3(b.hi), glm::vec3(c.hi)), 0.0f);
            b.counts += glm::uvec4(1, c.meshlets.y, 0, 0);
            if (c.draw.w == 0) continue;
            b.dynamicLo = glm::vec4(glm::min(glm::vec3(b.dynamicLo), glm::vec3(c.lo)), 0.0f);
            b.dynamicHi = glm::vec4(glm::max(glm::vec3(b.dynamicHi), glm::vec3(c.hi)), 0.0f);
            b.counts += glm::uvec4(0, 0, 1, c.meshlets.y);
        }
    }
    return groups;
}

} // namespace ml
