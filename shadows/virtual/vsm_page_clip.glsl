// Page draws clipped to one page (vsm_draw.vert and vsm_draw.mesh, the two raster paths): each draw or
// mesh workgroup carries the dirty page it renders, and four clip distances bound its triangles to that
// page's square of the mip, so the rasteriser makes fragments only inside it (fragments drawn follow
// the dirty pages' texels, not the mip's virtual resolution). The viewport stays the mip's whole
// resolution, so a triangle inside its page rasterises exactly as an unclipped draw would; page edges
// lie on integer pixel coordinates, half a pixel from every sample, so adjacent pages neither drop nor
// share a sample. Both paths clip the same triangle against the same page the same way, so their depths
// stay equal bit for bit (GpuVsmMeshlets). The includer declares `vsm` (VsmConstants).
#ifndef ML_VSM_PAGE_CLIP_GLSL
#define ML_VSM_PAGE_CLIP_GLSL

// A page as x | y << 12 (S_0 <= 16384 / 32 = 512 pages per side: 12 bits); this value: no clipping.
#define ML_VSM_PAGE_NONE 0xFFFFFFu

uint vsmPackPage(int x, int y) { return uint(x) | (uint(y) << 12u); }

// Clip distances of clip-space position p against page `page` (ML_VSM_PAGE_NONE: all inside) of `mip`.
// The page's NDC edges are exact: page size and resolution are powers of two.
vec4 vsmPageClip(vec4 p, uint page, uint mip) {
    if (page == ML_VSM_PAGE_NONE) return vec4(1.0);
    float scale = 2.0 * float(vsm.page.x) / float(vsm.options.z >> mip);
    vec2 lo = vec2(float(page & 0xFFFu), float((page >> 12u) & 0xFFFu)) * scale - 1.0;
    vec2 hi = lo + scale;
    return vec4(p.x - lo.x * p.w, hi.x * p.w - p.x, p.y - lo.y * p.w, hi.y * p.w - p.y);
}

#endif
