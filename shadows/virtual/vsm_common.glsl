// Virtual shadow map marking and lookup for one receiver and one light (GLSL). The C++ twins are
// vsmMarkReceiver / vsmLookupReceiver in shadows/virtual/vsm_reference.cpp: same calls, same order.
//
// Before including, declare the buffers and define their names:
//   VSM_CONST    VsmConstants           VSM_MAPS     GpuVsmMap[]
//   VSM_TABLE    uint[] page table      VSM_COVER    uint[] coverage bits (one per entry)
//   VSM_POOL     uint[] physical texels (lookup only)
//   VSM_MARKS    uint[] mark bits, coherent (marking only; define VSM_MARKING): the pages lookups read,
//                then from word VSM_CONST.options.w the fallback pages (reserved, drawn only under pressure),
//                then from word 2 * options.w the wanted bits (either of the two)
//   VSM_COUNTERS VsmCounters, VSM_RANKS uint[] first priority rank per (map slot, mip), VSM_LIST uint[]
//                the request list (marking only): the rank of every wanted entry, appended once
// Which map: a spot light has one, a point light six (face by pointLightFace), a directional light one
// per clip level. Which mip: vsm_math.h. A page "has casters" when its coverage bit is set: maps of
// lights with a static bake keep only the pages under some dynamic caster's projected bounds (the bake
// holds the rest), every other map sets all bits.
#ifndef ML_VSM_COMMON_GLSL
#define ML_VSM_COMMON_GLSL

#include "shadows/virtual/vsm_math.h"

bool vsmCovered(uint entry) { return (VSM_COVER[entry >> 5u] & (1u << (entry & 31u))) != 0u; }

// The map and mip a receiver wants, and its tap there. Directional: the first clip level at or above
// the matched one that holds the point. ok = 0: the light's maps do not hold the point (lit).
struct VsmChoice {
    uint map;
    uint mip;
    uint last; // the coarsest (map for directional, mip otherwise) the fallback chain may reach
    VsmTap tap;
};

VsmChoice vsmChoose(GpuLight L, uint firstMap, vec3 P, vec3 N) {
    VsmChoice c;
    c.map = firstMap;
    c.mip = 0u;
    c.tap.ok = 0u;
    uint R = VSM_CONST.options.z;
    float footprint = vsmFootprint(frame.cameraPosition.xyz, P, vsmPerMetre(VSM_CONST.camera.x, VSM_MAPS[firstMap]));
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        uint levels = VSM_MAPS[firstMap].light.z;
        uint level = vsmPickLevel(VSM_MAPS[firstMap], footprint, R, levels);
        c.last = firstMap + levels - 1u;
        for (uint l = level; l < levels; ++l) {
            c.map = firstMap + l;
            c.tap = vsmLocate(VSM_MAPS[c.map], R, 0u, P, N);
            if (c.tap.ok != 0u) break;
        }
        return c;
    }
    if (L.info.x == ML_LIGHT_POINT) c.map = firstMap + pointLightFace(P - L.positionRange.xyz);
    GpuVsmMap map = VSM_MAPS[c.map];
    vec3 vp = vsmPoint(map.view, P);
    if (!(-vp.z > map.params.y)) return c;
    uint mips = VSM_CONST.page.w;
    c.mip = vsmPickMip(vsmTexel0(map, vp, R), footprint, mips);
    c.last = mips - 1u;
    c.tap = vsmLocate(map, R, c.mip, P, N);
    return c;
}

// The next coarser place in the fallback chain: the next mip, or the next clip level.
bool vsmCoarser(GpuLight L, inout VsmChoice c, vec3 P, vec3 N) {
    uint R = VSM_CONST.options.z;
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        if (c.map >= c.last) return false;
        c.map += 1u;
        c.tap = vsmLocate(VSM_MAPS[c.map], R, 0u, P, N);
        return true;
    }
    if (c.mip >= c.last) return false;
    c.mip += 1u;
    c.tap = vsmLocate(VSM_MAPS[c.map], R, c.mip, P, N);
    return true;
}

uint vsmEntryOf(uint map, uint mip, ivec2 texel) {
    uint shift = VSM_CONST.page.y;
    return vsmEntry(VSM_CONST.sizes.x, VSM_CONST.page.z, map, mip, uint(texel.x) >> shift, uint(texel.y) >> shift);
}

bool vsmNeedsPage(uint map, uint entry) {
    return (VSM_MAPS[map].info.y & ML_VSM_MAP_DYNAMIC_ONLY) == 0u || vsmCovered(entry);
}

#ifdef VSM_MARKING
// Stream compaction of the marks: the first want of an entry this frame (lookup or fallback mark) appends
// its priority rank (vsm_alloc_common.glsl) to the request list, so the allocation passes walk the wanted
// entries only. Ranks are unique per entry; the list's order is the atomics' and vsm_sort makes it
// deterministic. Past the capacity an entry is counted in listOverflow by vsm_list (never silent).
void vsmWant(uint map, uint mip, uint px, uint py, uint entry) {
    uint bit = 1u << (entry & 31u);
    uint word = 2u * VSM_CONST.options.w + (entry >> 5u);
    if ((VSM_MARKS[word] & bit) != 0u || (atomicOr(VSM_MARKS[word], bit) & bit) != 0u) return;
    uint slot = atomicAdd(VSM_COUNTERS.listCount, 1u);
    if (slot < VSM_CONST.order.z)
        VSM_LIST[slot] = VSM_RANKS[map * VSM_CONST.page.w + mip] + py * (VSM_CONST.page.z >> mip) + px;
}

void vsmMarkKernel(uint map, uint mip, VsmTap tap, int radius, uint region) {
    if (tap.ok == 0u) return;
    int res = int(VSM_CONST.options.z >> mip);
    ivec2 lo = clamp(tap.texel - radius, ivec2(0), ivec2(res - 1));
    ivec2 hi = clamp(tap.texel + radius, ivec2(0), ivec2(res - 1));
    int shift = int(VSM_CONST.page.y);
    for (int py = lo.y >> shift; py <= (hi.y >> shift); ++py)
        for (int px = lo.x >> shift; px <= (hi.x >> shift); ++px) {
            uint entry = vsmEntry(VSM_CONST.sizes.x, VSM_CONST.page.z, map, mip, uint(px), uint(py));
            if (!vsmNeedsPage(map, entry)) continue;
            uint bit = 1u << (entry & 31u);
            uint word = region + (entry >> 5u);
            if ((VSM_MARKS[word] & bit) == 0u && (atomicOr(VSM_MARKS[word], bit) & bit) == 0u)
                vsmWant(map, mip, uint(px), uint(py), entry);
        }
}

// Marks the pages the lookup of (P, N) will read and, in frames that reserve them (VsmConstants.camera.z:
// near pool pressure, VsmSettings::fallbacksOnDemand), reserves its fallback pages ML_VSM_FALLBACK_MIPS
// mips (or clip levels) coarser and at the coarsest, so that a full pool still leaves a coarser shadow:
// allocation serves coarse mips first, so a fallback page gets memory before the pages it stands in for.
// A fallback page is drawn only in a frame where some request found no page ("pressure"); otherwise it
// costs memory only.
void vsmMarkReceiver(GpuLight L, uint firstMap, vec3 P, vec3 N) {
    VsmChoice c = vsmChoose(L, firstMap, P, N);
    if (c.tap.ok == 0u) return;
    int radius = int(VSM_CONST.options.x);
    vsmMarkKernel(c.map, c.mip, c.tap, radius, 0u);
    if (VSM_CONST.camera.z == 0.0) return; // no reservations this frame (VsmSettings::fallbacksOnDemand)
    uint fallbackWords = VSM_CONST.options.w;
    uint R = VSM_CONST.options.z;
    // Two fallback pages: a few mips up (the shadow a small pool keeps), and the coarsest place (one page
    // per map: what even a pool of one page per active map still holds). Perspective maps take the fine
    // tap shifted (vsmCoarserTap: no second projection); clip levels are separate maps and project again.
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        uint f = min(c.map + ML_VSM_FALLBACK_MIPS, c.last);
        if (f != c.map) vsmMarkKernel(f, 0u, vsmLocate(VSM_MAPS[f], R, 0u, P, N), radius, fallbackWords);
        if (c.last != f) vsmMarkKernel(c.last, 0u, vsmLocate(VSM_MAPS[c.last], R, 0u, P, N), radius, fallbackWords);
    } else {
        // The coarser lookup's own normal offset moves its tap up to bias.y texels of that mip from the
        // shifted one: the reservation's kernel is that much (and a texel of rounding) wider.
        int wide = radius + vsmFallbackSlack(VSM_MAPS[c.map]);
        uint f = min(c.mip + ML_VSM_FALLBACK_MIPS, c.last);
        if (f != c.mip) vsmMarkKernel(c.map, f, vsmCoarserTap(c.tap, f - c.mip), wide, fallbackWords);
        if (c.last != f) vsmMarkKernel(c.map, c.last, vsmCoarserTap(c.tap, c.last - c.mip), wide, fallbackWords);
    }
}
#endif

#ifdef VSM_POOL
// Lit taps of the kernel at c, or -1 when a tap's page is not resident (allocated and valid): the
// caller then moves the whole kernel to the next coarser place.
int vsmKernelLit(VsmChoice c, int radius, out uint centreDepth) {
    centreDepth = 0xFFFFFFFFu;
    int res = int(VSM_CONST.options.z >> c.mip);
    uint size = VSM_CONST.page.x;
    int lit = 0;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            ivec2 t = c.tap.texel + ivec2(dx, dy);
            if (t.x < 0 || t.y < 0 || t.x >= res || t.y >= res) { lit += 1; continue; }
            uint entry = vsmEntryOf(c.map, c.mip, t);
            if (!vsmNeedsPage(c.map, entry)) { lit += 1; continue; }
            uint pt = VSM_TABLE[entry];
            if ((pt & (ML_VSM_ALLOCATED | ML_VSM_VALID)) != (ML_VSM_ALLOCATED | ML_VSM_VALID)) return -1;
            uint texel = (pt & ML_VSM_PHYS_MASK) * size * size + (uint(t.y) & (size - 1u)) * size + (uint(t.x) & (size - 1u));
            uint d = VSM_POOL[texel];
            if (dx == 0 && dy == 0) centreDepth = d;
            if (c.tap.depth <= d) lit += 1;
        }
    return lit;
}

// Dynamic visibility of light L at P in [0, 1]; status receives ML_VSM_PROBE_*.
float vsmVisibility(GpuLight L, uint firstMap, vec3 P, vec3 Nraw, out VsmChoice c, out uint status,
                    out uint centreDepth) {
    vec3 N = vsmNormalize(Nraw);
    c = vsmChoose(L, firstMap, P, N);
    status = ML_VSM_PROBE_NO_CASTER;
    centreDepth = 0xFFFFFFFFu;
    if (c.tap.ok == 0u) return 1.0;
    int radius = int(VSM_CONST.options.x);
    float taps = float((2 * radius + 1) * (2 * radius + 1));
    bool fallback = false;
    for (;;) {
        if (c.tap.ok == 0u) return 1.0;
        int lit = vsmKernelLit(c, radius, centreDepth);
        if (lit >= 0) {
            uint entry = vsmEntryOf(c.map, c.mip, c.tap.texel);
            status = !vsmNeedsPage(c.map, entry) ? ML_VSM_PROBE_NO_CASTER
                     : fallback                   ? ML_VSM_PROBE_FALLBACK
                                                  : ML_VSM_PROBE_PAGE;
            return float(lit) / taps;
        }
        fallback = true;
        if (!vsmCoarser(L, c, P, N)) break;
    }
    status = ML_VSM_PROBE_MISSING;
    return 1.0;
}
#endif

#endif
