// Page draws clipped to their dirty page (VsmSettings::pageClip; vsm_cull.comp, vsm_draw.task,
// vsm_page_clip.glsl) against unclipped draws over each mip's whole virtual resolution whose fragments
// outside dirty pages are discarded (the layout before page clipping): on the night city's drive, both
// raster paths, two sessions per path must hold the same page table and, in every allocated and valid
// page, the same covered texels (but for a few on triangle edges through a sample: clipping moves a
// vertex by rounding) with depths within float interpolation error (clipping gives a triangle new
// vertices, so depths differ in their low bits: measured up to 1.3e-3 of the range where a ground
// triangle far larger than the map is clipped; `check vsm` holds both paths to the double-precision CPU
// reference); and the clipped draws' fragments must follow the dirty pages' texels (at most 4x them: the
// casters' depth complexity there) where the unclipped ones do not. Mesh against vertex path, bit for
// bit, with clipping: GpuVsmMeshlets.
#include "gpu_test_util.h"
#include "vsm_test_util.h"

#include <algorithm>
#include <cstdio>

namespace ml::test {
namespace {

VsmSessionOptions drivePath(VsmRaster raster, bool pageClip) {
    VsmSessionOptions o = vsmSmallDrive(raster);
    o.module.vsm.caching = false; // every marked page drawn every frame: the most draws
    o.module.vsm.pageClip = pageClip;
    return o;
}

struct Totals {
    uint64_t fragments = 0, dirtyTexels = 0, pagesCompared = 0, texelsWritten = 0;
};

Totals compareClipped(VsmRaster raster, uint32_t frames) {
    Totals clipped, whole;
    auto onS = VsmSession::create(drivePath(raster, true));
    auto offS = VsmSession::create(drivePath(raster, false));
    EXPECT_TRUE(onS.ok() && offS.ok());
    if (!onS.ok() || !offS.ok()) return clipped;
    Module& on = *onS.value()->module;
    Module& off = *offS.value()->module;
    const VirtualShadowMaps& von = internals(on).vsm;
    const VirtualShadowMaps& voff = internals(off).vsm;
    EXPECT_EQ(von.meshPath(), raster == VsmRaster::Mesh);
    const uint32_t page = von.settings().pageSize * von.settings().pageSize;
    for (uint32_t f = 0; f < frames; ++f) {
        auto ron = onS.value()->frame(f);
        auto roff = offS.value()->frame(f);
        EXPECT_TRUE(ron.ok() && roff.ok());
        if (!ron.ok() || !roff.ok()) return clipped;
        const std::vector<uint32_t> table = von.read(deviceOf(on), VsmState::Table);
        EXPECT_EQ(table, voff.read(deviceOf(off), VsmState::Table)) << "frame " << f;
        const std::vector<uint32_t> pon = von.read(deviceOf(on), VsmState::PagePool),
                                    poff = voff.read(deviceOf(off), VsmState::PagePool);
        size_t differing = 0, firstDiff = 0, coverage = 0;
        uint32_t maxDiff = 0;
        for (uint32_t w : table) {
            if (!(w & ML_VSM_ALLOCATED) || !(w & ML_VSM_VALID)) continue;
            const size_t first = size_t(w & ML_VSM_PHYS_MASK) * page;
            for (size_t t = first; t < first + page; ++t) {
                if (pon[t] != poff[t] && differing++ == 0) firstDiff = t;
                if ((pon[t] == 0xFFFFFFFFu) != (poff[t] == 0xFFFFFFFFu))
                    ++coverage;
                else if (pon[t] != 0xFFFFFFFFu)
                    maxDiff = std::max(maxDiff, pon[t] > poff[t] ? pon[t] - poff[t] : poff[t] - pon[t]);
                clipped.texelsWritten += pon[t] != 0xFFFFFFFFu;
            }
            ++clipped.pagesCompared;
        }
        std::printf(
            "frame %u: %zu texels differ, %zu in coverage; largest depth difference %.2e of the range\n", f,
            differing, coverage, maxDiff / 4294967040.0);
        EXPECT_LE(coverage, 4u) << "frame " << f;
        EXPECT_LE(maxDiff, uint32_t(2e-3 * 4294967040.0))
            << "frame " << f << ": first differing texel " << firstDiff << " (clipped " << pon[firstDiff]
            << ", whole mip " << poff[firstDiff] << ")";
        const VsmStats& s = ron->stats.vsm;
        EXPECT_EQ(s.drawOverflow + s.meshletOverflow + s.pageClipOverflow, 0u);
        EXPECT_EQ(s.dirtyPageTexels, roff->stats.vsm.dirtyPageTexels);
        clipped.fragments += s.fragmentsDrawn;
        clipped.dirtyTexels += s.dirtyPageTexels;
        whole.fragments += roff->stats.vsm.fragmentsDrawn;
    }
    std::printf("%s: dirty-page texels %llu, fragments clipped %llu, whole mip %llu; pages compared %llu\n",
                raster == VsmRaster::Mesh ? "mesh" : "vertex", (unsigned long long)clipped.dirtyTexels,
                (unsigned long long)clipped.fragments, (unsigned long long)whole.fragments,
                (unsigned long long)clipped.pagesCompared);
    EXPECT_GT(clipped.pagesCompared, 0u);
    EXPECT_GT(clipped.texelsWritten, 0u);
    EXPECT_GT(clipped.fragments, 0u);
    EXPECT_LE(clipped.fragments, 4 * clipped.dirtyTexels);
    EXPECT_GT(whole.fragments, 4 * clipped.dirtyTexels); // the bound fails without page clipping
    return clipped;
}

TEST(GpuVsmPageClip, VertexPathSamePagesFewerFragments) {
    resetValidationCounters();
    compareClipped(VsmRaster::Vertex, 4);
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuVsmPageClip, MeshPathSamePagesFewerFragments) {
    resetValidationCounters();
    compareClipped(VsmRaster::Mesh, 4);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
