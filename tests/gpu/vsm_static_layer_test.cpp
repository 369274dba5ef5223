// The static layer (VsmSettings::staticLayer; vsm_scan, vsm_assign, vsm_clear, vsm_draw.frag): a
// page invalidated only by a moving dynamic caster is redrawn from its static twin plus the dynamic
// casters. On the indoor level's drive (four carts on loops, the camera following one), three sessions
// run the same frames: cached with the layer, cached without it (every caster redrawn into such a page,
// the behaviour before) and uncached (every marked page redrawn from nothing). Every page valid in two
// of them must hold the same depths bit for bit (the atomic minimum is order-independent and the static
// casters' depths do not change), some pages must be redrawn from their twin, and the cached frames
// with the layer must draw fewer fragments than without it. The allocation counters' breakdown
// (pagesNew, pagesInvalidatedCaster) must add up.
#include "gpu_test_util.h"
#include "host/vsm_session.h"

#include <cstdio>

namespace ml::test {
namespace {

VsmSessionOptions indoorDrive(bool caching, bool staticLayer) {
    VsmSessionOptions o;
    o.scene = "indoor";
    o.width = 256;
    o.height = 144;
    o.path = CameraPath::Drive;
    o.module.device.validation = true;
    o.module.vsm.resolution = 1024;
    o.module.vsm.poolPages = 2048;
    o.module.vsm.maxMaps = 512;
    o.module.vsm.caching = caching;
    o.module.vsm.staticLayer = staticLayer;
    o.module.vsm.raster = VsmRaster::Vertex;
    o.module.vsm.kinds = 1; // spot lights; the carts' headlights move every frame and redraw anyway
    o.module.vsm.movingLights = false;
    return o;
}

// Texels of every page valid in both sessions that differ; `pages` counts the pages compared.
size_t differingTexels(Module& a, Module& b, size_t& pages) {
    const VirtualShadowMaps& va = internals(a).vsm;
    const VirtualShadowMaps& vb = internals(b).vsm;
    const std::vector<uint32_t> ta = va.read(deviceOf(a), VsmState::Table),
                                tb = vb.read(deviceOf(b), VsmState::Table);
    const std::vector<uint32_t> pa = va.read(deviceOf(a), VsmState::PagePool),
                                pb = vb.read(deviceOf(b), VsmState::PagePool);
    const size_t texels = size_t(va.settings().pageSize) * va.settings().pageSize;
    size_t differ = 0;
    for (size_t e = 0; e < std::min(ta.size(), tb.size()); ++e) {
        if (!(ta[e] & ML_VSM_VALID) || !(tb[e] & ML_VSM_VALID)) continue;
        const size_t fa = size_t(ta[e] & ML_VSM_PHYS_MASK) * texels,
                     fb = size_t(tb[e] & ML_VSM_PHYS_MASK) * texels;
        for (size_t t = 0; t < texels; ++t) differ += pa[fa + t] != pb[fb + t];
        ++pages;
    }
    return differ;
}

TEST(GpuVsmStaticLayer, DynamicOnlyRedrawsEqualFullRedrawsWithFewerFragments) {
    resetValidationCounters();
    auto layered = VsmSession::create(indoorDrive(true, true));
    auto plain = VsmSession::create(indoorDrive(true, false));
    auto uncached = VsmSession::create(indoorDrive(false, true));
    ASSERT_TRUE(layered.ok() && plain.ok() && uncached.ok());
    uint64_t fragmentsLayered = 0, fragmentsPlain = 0, fromTwin = 0, invalidatedByCasters = 0;
    size_t compared = 0;
    const uint32_t frames = 6;
    for (uint32_t f = 0; f < frames; ++f) {
        auto rl = layered.value()->frame(f);
        auto rp = plain.value()->frame(f);
        auto ru = uncached.value()->frame(f);
        ASSERT_TRUE(rl.ok() && rp.ok() && ru.ok());
        const VsmStats &l = rl->stats.vsm, &p = rp->stats.vsm, &u = ru->stats.vsm;
        // The same camera and casters: the same pages marked, rendered and invalidated with or without
        // the layer; the layer changes only what is drawn into them.
        EXPECT_EQ(l.pagesMarked, u.pagesMarked) << "frame " << f;
        EXPECT_EQ(l.pagesRendered, p.pagesRendered) << "frame " << f;
        EXPECT_EQ(l.pagesNew, p.pagesNew) << "frame " << f;
        EXPECT_EQ(l.pagesInvalidatedCaster, p.pagesInvalidatedCaster) << "frame " << f;
        EXPECT_EQ(p.pagesRenderedDynamic, 0u) << "frame " << f;
        EXPECT_LE(l.pagesRenderedDynamic + l.pagesNew, l.pagesRendered) << "frame " << f;
        EXPECT_LE(l.pagesInvalidatedCaster, l.pagesInvalidated) << "frame " << f;
        // Uncached: every owned page is invalidated as a whole (none by casters alone), nothing from a twin.
        EXPECT_EQ(u.pagesInvalidatedCaster, 0u) << "frame " << f;
        EXPECT_EQ(u.pagesRenderedDynamic, 0u) << "frame " << f;
        EXPECT_EQ(u.pagesRendered, u.pagesMarked) << "frame " << f;
        size_t pages = 0;
        EXPECT_EQ(differingTexels(*layered.value()->module, *uncached.value()->module, pages), 0u)
            << "frame " << f << ": layered cached pages differ from a full redraw";
        EXPECT_EQ(differingTexels(*plain.value()->module, *uncached.value()->module, pages), 0u)
            << "frame " << f << ": cached pages without the layer differ from a full redraw";
        compared += pages;
        if (f == 0) continue; // every page new
        fragmentsLayered += l.fragmentsDrawn;
        fragmentsPlain += p.fragmentsDrawn;
        fromTwin += l.pagesRenderedDynamic;
        invalidatedByCasters += l.pagesInvalidatedCaster;
    }
    std::printf("pages compared %zu; cached frames: %llu pages from their twin, %llu invalidated by casters; "
                "fragments %llu with the layer, %llu without\n",
                compared, (unsigned long long)fromTwin, (unsigned long long)invalidatedByCasters,
                (unsigned long long)fragmentsLayered, (unsigned long long)fragmentsPlain);
    EXPECT_GT(compared, 0u);
    EXPECT_GT(fromTwin, 0u) << "no page was redrawn from its static twin: the path exercises nothing";
    EXPECT_LT(fragmentsLayered, fragmentsPlain);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
