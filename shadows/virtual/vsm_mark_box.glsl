// Page marking per cluster (GLSL, vsm_mark_cluster.comp only): the pages a world box of receivers marks
// for one light, from vsm_bounds.h's bounds; the C++ twins are markPages / boxPages in
// shadows/virtual/vsm_reference.cpp (same calls, same order). Include after vsm_common.glsl with
// VSM_MARKING defined (vsmNeedsPage, vsmWant).
#ifndef ML_VSM_MARK_BOX_GLSL
#define ML_VSM_MARK_BOX_GLSL

#include "shadows/virtual/vsm_bounds.h"

// The pages of `pages` (vsmRectPages) that need one, marked in `region` (mark), or the rectangle's size
// (count: what the threshold ML_VSM_CLUSTER_PAGES is compared with).
uint vsmMarkPages(uint map, uint mip, ivec4 pages, uint region, bool mark) {
    uint n = vsmRectPageCount(pages);
    if (!mark || n == 0u) return n;
    for (int py = pages.y; py <= pages.w; ++py)
        for (int px = pages.x; px <= pages.z; ++px) {
            uint entry = vsmEntry(VSM_CONST.sizes.x, VSM_CONST.page.z, map, mip, uint(px), uint(py));
            if (!vsmNeedsPage(map, entry)) continue;
            uint bit = 1u << (entry & 31u);
            uint word = region + (entry >> 5u);
            if ((VSM_MARKS[word] & bit) == 0u && (atomicOr(VSM_MARKS[word], bit) & bit) == 0u)
                vsmWant(map, mip, uint(px), uint(py), entry);
        }
    return n;
}

// Every page that vsmMarkReceiver marks for light L from any receiver inside the world box [lo, hi]
// whose unit normal lies in [nlo, nhi]
// (vsm_bounds.h bounds the mips, clip levels and taps; a point light's six faces each take the part of
// the box in front of them): marked (mark) or counted. Twin: boxPages in vsm_reference.cpp.
uint vsmBoxPages(GpuLight L, uint firstMap, vec3 lo, vec3 hi, vec3 nlo, vec3 nhi, bool mark) {
    uint R = VSM_CONST.options.z, shift = VSM_CONST.page.y;
    int radius = int(VSM_CONST.options.x);
    bool reserve = VSM_CONST.camera.z != 0.0;
    uint fw = VSM_CONST.options.w;
    float perMetre = vsmPerMetre(VSM_CONST.camera.x, VSM_MAPS[firstMap]); // the light's texel scale
    vec2 fp = vsmFootprintRange(frame.cameraPosition.xyz, lo, hi, perMetre);
    uint n = 0u;
    if (L.info.x == ML_LIGHT_DIRECTIONAL) {
        // A receiver takes the first level at or above its matched one that holds it: levels [a, stop],
        // stop the first at or above b (the coarsest matched) that holds the whole box.
        uint levels = VSM_MAPS[firstMap].light.z, last = levels - 1u;
        uint a = vsmPickLevel(VSM_MAPS[firstMap], fp.x, R, levels);
        uint b = vsmPickLevel(VSM_MAPS[firstMap], fp.y, R, levels);
        uint stop = last;
        for (uint l = a; l < levels; ++l) {
            GpuVsmMap map = VSM_MAPS[firstMap + l];
            VsmBox w = vsmLevelBox(VSM_MAPS[firstMap], frame.cameraPosition.xyz, lo, hi, perMetre, R, l, levels);
            if (vsmBoxEmpty(w)) continue; // no receiver matches this level or a finer one
            VsmTapRect t = vsmBoxTaps(map, R, 0u, vsmViewBox(map.view, w.lo, w.hi), vsmNormalViewBox(map.view, nlo, nhi));
            if (t.ok != 0u)
                n += vsmMarkPages(firstMap + l, 0u, vsmRectPages(t.texels, 0u, radius, R, 0u, shift), 0u, mark);
            if (l >= b && t.held != 0u) {
                stop = l;
                break;
            }
        }
        if (!reserve) return n;
        // Fallbacks: ML_VSM_FALLBACK_MIPS levels above each level taken, and the coarsest.
        uint f1 = min(stop + ML_VSM_FALLBACK_MIPS, last);
        for (uint l = min(a + ML_VSM_FALLBACK_MIPS, last); l <= f1; ++l) {
            GpuVsmMap map = VSM_MAPS[firstMap + l];
            VsmTapRect t = vsmBoxTaps(map, R, 0u, vsmViewBox(map.view, lo, hi), vsmNormalViewBox(map.view, nlo, nhi));
            if (t.ok != 0u)
                n += vsmMarkPages(firstMap + l, 0u, vsmRectPages(t.texels, 0u, radius, R, 0u, shift), fw, mark);
        }
        if (f1 != last) {
            GpuVsmMap map = VSM_MAPS[firstMap + last];
            VsmTapRect t = vsmBoxTaps(map, R, 0u, vsmViewBox(map.view, lo, hi), vsmNormalViewBox(map.view, nlo, nhi));
            if (t.ok != 0u)
                n += vsmMarkPages(firstMap + last, 0u, vsmRectPages(t.texels, 0u, radius, R, 0u, shift), fw, mark);
        }
        return n;
    }
    uint faces = L.info.x == ML_LIGHT_POINT ? 6u : 1u;
    uint mips = VSM_CONST.page.w, last = mips - 1u;
    for (uint f = 0u; f < faces; ++f) {
        uint m = firstMap + f;
        GpuVsmMap map = VSM_MAPS[m];
        VsmViewBox vb = vsmViewBox(map.view, lo, hi), nb = vsmNormalViewBox(map.view, nlo, nhi);
        uvec2 range = vsmBoxMips(map, vb, fp, R, mips);
        int wide = radius + vsmFallbackSlack(map);
        for (uint mip = range.x; mip <= range.y; ++mip) {
            // The receivers that pick this mip.
            VsmViewBox mb = vsmMipView(map, vb, lo, hi, frame.cameraPosition.xyz, fp, perMetre, R, mip, mips);
            if (!(mb.lo.x <= mb.hi.x && mb.lo.y <= mb.hi.y && mb.lo.z <= mb.hi.z)) continue;
            VsmTapRect t = vsmBoxTaps(map, R, mip, mb, nb);
            if (t.ok == 0u) continue;
            n += vsmMarkPages(m, mip, vsmRectPages(t.texels, 0u, radius, R, mip, shift), 0u, mark);
            if (!reserve) continue;
            // vsmCoarserTap: the fine taps shifted, with the wider kernel.
            uint fb = min(mip + ML_VSM_FALLBACK_MIPS, last);
            if (fb != mip)
                n += vsmMarkPages(m, fb, vsmRectPages(t.texels, fb - mip, wide, R, fb, shift), fw, mark);
            if (last != fb)
                n += vsmMarkPages(m, last, vsmRectPages(t.texels, last - mip, wide, R, last, shift), fw, mark);
        }
    }
    return n;
}

#endif
