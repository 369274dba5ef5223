// Virtual shadow maps on lavapipe against their CPU references (shadows/virtual/vsm_reference.h):
// every frame of a path, the GPU's mark bits equal vsmMarkReference on the same G-buffer and cluster
// lists, and the page table, owners and last-use frames after allocation equal vsmAllocateReference run
// from the previous frame's state; the invariants hold every frame; a pool a quarter of the need counts
// fallbacks and never leaves a lookup without a page.
#include "gpu_test_util.h"

#include <array>
#include <bit>
#include "vsm_test_util.h"
#include "shadows/virtual/vsm_reference.h"

namespace ml::test {
namespace {

VsmSessionOptions smallPath(uint32_t width, uint32_t height) {
    VsmSessionOptions o = vsmSmallDrive();
    o.width = width;
    o.height = height;
    o.module.vsm.maxMaps = 512; // the CPU reference's table covers every slot: keep it small
    return o;
}

// What the allocation did over the path: the slot pool's final size and, for the pages taken from an
// owner, how many came from each LRU class (vsm_alloc_common.glsl: 1 is >= 128 frames unused, 8 is one).
struct AllocationSeen {
    uint32_t grownTo = 0;
    std::array<uint32_t, 9> evictedByClass{};
};

void marksAndAllocationEqualCpuReference(const VsmSessionOptions& options, uint32_t frames,
                                         AllocationSeen* seen = nullptr) {
    resetValidationCounters();
    auto session = VsmSession::create(options);
    ASSERT_TRUE(session.ok()) << session.error();
    VsmSession& s = *session.value();
    Module& m = *s.module;
    const VirtualShadowMaps& vsm = internals(m).vsm;
    VsmAllocState cpu;
    const size_t entries = size_t(vsm.settings().maxMaps) * vsm.layout().entriesPerMap;
    cpu.table.assign(entries, 0);
    cpu.owners.assign(vsm.settings().poolPages, ML_VSM_NO_OWNER);
    cpu.lastUsed.assign(vsm.settings().poolPages, 0);
    uint64_t marked = 0, cached = 0, rendered = 0, invalidated = 0;
    for (uint32_t f = 0; f < frames; ++f) {
        auto report = s.frame(f);
        ASSERT_TRUE(report.ok()) << report.error();
        const uint32_t slot = internals(m).lastSlot;
        // Marking.
        std::vector<uint32_t> gpuMarks = vsm.read(deviceOf(m), VsmState::Marks);
        if (f % 10 == 0 || f < 3) { // the mark reference walks every pixel: every 10th frame keeps it short
            std::vector<uint32_t> cpuMarks = options.module.vsm.clusterMarking
                                                 ? vsmMarkClusterReference(markInputs(m))
                                                 : vsmMarkReference(markInputs(m));
            size_t differ = 0;
            for (size_t w = 0; w < gpuMarks.size(); ++w) differ += gpuMarks[w] != cpuMarks[w];
            ASSERT_EQ(differ, 0u) << "frame " << f << ": mark words differ";
        }
        // Allocation from the previous frame's state, with this frame's marks.
        std::vector<uint32_t> stale = vsm.slotHost(slot).stale;
        const std::vector<uint32_t> ownersBefore = cpu.owners, lastUsedBefore = cpu.lastUsed;
        gpu::VsmCounters c = vsmAllocateReference(cpu, gpuMarks, stale, vsm.slotHost(slot).maps,
                                                  vsm.slotHost(slot).runs, vsm.lastConstants());
        std::vector<uint32_t> table = vsm.read(deviceOf(m), VsmState::Table);
        ASSERT_LE(table.size(), cpu.table.size());
        size_t differ = 0;
        for (size_t e = 0; e < table.size(); ++e) differ += table[e] != cpu.table[e];
        ASSERT_EQ(differ, 0u) << "frame " << f << ": page-table entries differ";
        ASSERT_EQ(vsm.read(deviceOf(m), VsmState::Owners), cpu.owners) << "frame " << f;
        ASSERT_EQ(vsm.read(deviceOf(m), VsmState::LastUsed), cpu.lastUsed) << "frame " << f;
        for (size_t p = 0; seen && p < cpu.owners.size(); ++p) // the class each evicted page was taken from
            if (ownersBefore[p] != ML_VSM_NO_OWNER && cpu.owners[p] != ownersBefore[p]) {
                const uint32_t age = std::max(vsm.lastConstants().sizes.w - lastUsedBefore[p], 1u);
                ++seen->evictedByClass[8 - std::min(uint32_t(std::bit_width(age) - 1), 7u)];
            }
        const VsmStats& g = report->stats.vsm;
        EXPECT_EQ(g.pagesMarked, c.pagesMarked) << "frame " << f;
        EXPECT_EQ(g.pagesCached, c.pagesCached) << "frame " << f;
        EXPECT_EQ(g.pagesRendered, c.pagesRendered) << "frame " << f;
        EXPECT_EQ(g.pagesEvicted, c.pagesEvicted) << "frame " << f;
        EXPECT_EQ(g.pagesInvalidated, c.pagesInvalidated) << "frame " << f;
        EXPECT_EQ(g.fallbacks, c.fallbacks) << "frame " << f;
        EXPECT_EQ(g.pagesAllocated, c.pagesAllocated) << "frame " << f;
        std::string bad =
            vsmCheckInvariants(cpu, gpuMarks, vsm.slotHost(slot).active, vsm.lastConstants(), c);
        ASSERT_TRUE(bad.empty()) << "frame " << f << ": " << bad;
        marked += g.pagesMarked;
        cached += g.pagesCached;
        rendered += g.pagesRendered;
        invalidated += g.pagesInvalidated;
    }
    // The path exercises what the test is about: pages were marked, rendered, kept and invalidated.
    EXPECT_GT(marked, 0u);
    EXPECT_GT(cached, 0u);
    EXPECT_GT(rendered, 0u);
    EXPECT_GT(invalidated, 0u);
    EXPECT_EQ(validationErrors(), 0u);
    if (seen) seen->grownTo = vsm.mapCapacity();
}

// Per-light bias (LightDesc::shadowDepthBias / shadowNormalBias) reaches GpuVsmMap.bias; the marks (which
// pages a lookup reads, vsmLocate) then still equal the CPU reference, and differ from the default's.
TEST(GpuVsm, PerLightBiasReachesMapsAndMarksEqualCpu) {
    resetValidationCounters();
    auto session = VsmSession::create(smallPath(192, 108));
    ASSERT_TRUE(session.ok()) << session.error();
    VsmSession& s = *session.value();
    Module& m = *s.module;
    const VirtualShadowMaps& vsm = internals(m).vsm;
    ASSERT_TRUE(s.frame(0).ok());
    const std::vector<uint32_t> defaultMarks = vsm.read(deviceOf(m), VsmState::Marks);
    for (uint32_t i = 0; i < s.scene.lights.size(); ++i) {
        if (s.scene.lights[i].dynamic) continue; // the session re-sets moving lights every frame
        LightDesc l = toLightDesc(s.scene.lights[i]);
        l.shadowDepthBias = 2.0f;
        l.shadowNormalBias = 6.0f;
        ASSERT_TRUE(m.setLight(i, l).ok());
    }
    ASSERT_TRUE(s.frame(0).ok()); // the same view and animation time
    std::vector<uint32_t> gpuMarks = vsm.read(deviceOf(m), VsmState::Marks);
    VsmMarkInputs in = markInputs(m);
    uint32_t biased = 0;
    for (const gpu::GpuVsmMap& map : in.maps) biased += map.bias.x == 2.0f && map.bias.y == 6.0f;
    EXPECT_GT(biased, 0u) << "no map carries the lights' bias";
    std::vector<uint32_t> cpuMarks = vsmMarkReference(in);
    size_t differ = 0, changed = 0;
    for (size_t w = 0; w < gpuMarks.size(); ++w) {
        differ += gpuMarks[w] != cpuMarks[w];
        changed += w < defaultMarks.size() && gpuMarks[w] != defaultMarks[w];
    }
    EXPECT_EQ(differ, 0u) << "mark words differ from the CPU reference";
    EXPECT_GT(changed, 0u) << "a six-texel normal offset moved no lookup to another page";
    EXPECT_EQ(validationErrors(), 0u);
}

// Marking covers what the evaluation looks up, and no more: a pixel that is not a shadow receiver, or a
// receiver facing away from the light (the shading is zero, evaluate.comp looks nothing up), marks no
// page (vsmFacesLight). One light with maps kept; the G-buffer normals turned towards it, then away.
size_t markedBits(const std::vector<uint32_t>& marks) {
    size_t n = 0;
    for (uint32_t w : marks) n += size_t(std::popcount(w));
    return n;
}

TEST(GpuVsm, BackFacingAndNonReceiverPixelsMarkNothing) {
    resetValidationCounters();
    auto session = VsmSession::create(smallPath(192, 108));
    ASSERT_TRUE(session.ok()) << session.error();
    VsmSession& s = *session.value();
    Module& m = *s.module;
    ASSERT_TRUE(s.frame(0).ok());
    VsmMarkInputs in = markInputs(m);
    const std::vector<uint32_t> all = vsmMarkReference(in);
    ASSERT_EQ(internals(m).vsm.read(deviceOf(m), VsmState::Marks), all);
    ASSERT_GT(markedBits(all), 0u);
    // The spot light whose pages cover most pixels keeps its maps; the others lose them.
    uint32_t keep = UINT32_MAX;
    size_t best = 0;
    for (uint32_t l = 0; l < in.lights.size(); ++l) {
        if (in.lights[l].info.y == ML_VSM_NO_MAP || in.lights[l].info.x != ML_LIGHT_SPOT) continue;
        VsmMarkInputs one = in;
        for (uint32_t k = 0; k < one.lights.size(); ++k)
            if (k != l) one.lights[k].info.y = ML_VSM_NO_MAP;
        const size_t n = markedBits(vsmMarkReference(one));
        if (n > best) best = n, keep = l;
    }
    ASSERT_NE(keep, UINT32_MAX) << "no spot light has maps on this path";
    for (uint32_t k = 0; k < in.lights.size(); ++k)
        if (k != keep) in.lights[k].info.y = ML_VSM_NO_MAP;
    const glm::vec3 lightPos(in.lights[keep].positionRange);
    auto withNormals = [&](float towards, float w) {
        VsmMarkInputs v = in;
        for (uint32_t y = 0; y < in.frame.size.y; ++y)
            for (uint32_t x = 0; x < in.frame.size.x; ++x) {
                const size_t i = size_t(y) * in.frame.size.x + x;
                if (!gpu::hasSurface(in.depth[i])) continue;
                const glm::vec3 P =
                    gpu::worldFromPixel(x, y, in.depth[i], in.frame.invViewProj, in.frame.size);
                v.normal[i] = glm::vec4(towards * glm::normalize(lightPos - P), w);
            }
        return markedBits(vsmMarkReference(v));
    };
    EXPECT_GT(withNormals(1.0f, 1.0f), 0u) << "facing the light: its receivers mark pages";
    EXPECT_EQ(withNormals(-1.0f, 1.0f), 0u) << "facing away: the evaluation reads none of these pages";
    EXPECT_EQ(withNormals(1.0f, ML_NOT_A_RECEIVER), 0u) << "not receivers: no lookup, no page";
    EXPECT_EQ(validationErrors(), 0u);
}

// Fallback reservations on demand (VsmSettings::fallbacksOnDemand): with a roomy pool, receivers stop
// reserving once a frame has completed far from pressure; with a pool near pressure, or the policy off,
// they reserve in every frame. The fallback region of the marks tells (the lookup marks are the same).
size_t fallbackBits(uint32_t poolPages, bool onDemand, uint32_t frames) {
    VsmSessionOptions o = smallPath(192, 108);
    o.module.vsm.poolPages = poolPages;
    o.module.vsm.fallbacksOnDemand = onDemand;
    auto session = VsmSession::create(o);
    EXPECT_TRUE(session.ok()) << session.error();
    if (!session.ok()) return 0;
    VsmSession& s = *session.value();
    Module& m = *s.module;
    size_t bits = 0;
    for (uint32_t f = 0; f < frames; ++f) {
        EXPECT_TRUE(s.frame(f).ok());
        const std::vector<uint32_t> marks = internals(m).vsm.read(deviceOf(m), VsmState::Marks);
        const size_t words = internals(m).vsm.layout().markWords;
        bits = 0; // the last frame's
        for (size_t w = words; w < 2 * words && w < marks.size(); ++w)
            bits += size_t(std::popcount(marks[w]));
        EXPECT_EQ(vsmMarkReference(markInputs(m)),
                  std::vector<uint32_t>(marks.begin(), marks.begin() + 2 * words))
            << "frame " << f;
    }
    return bits;
}

TEST(GpuVsm, FallbacksReservedOnlyNearPressure) {
    resetValidationCounters();
    EXPECT_EQ(fallbackBits(1024, true, 4), 0u) << "a roomy pool still reserves fallback pages";
    EXPECT_GT(fallbackBits(1024, false, 4), 0u) << "the policy off: reservations every frame";
    EXPECT_GT(fallbackBits(48, true, 4), 0u) << "a pool near pressure reserves no fallback pages";
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuVsm, MarksAndAllocationEqualCpuReferenceEveryFrame) {
    marksAndAllocationEqualCpuReference(smallPath(192, 108), 100);
}

// Marking per cluster (VsmSettings::clusterMarking): its marks equal vsmMarkClusterReference, and the
// allocation from them (the request list vsm_mark_cluster appends) equals the reference every frame.
TEST(GpuVsm, ClusterMarksAndAllocationEqualCpuReference) {
    VsmSessionOptions o = smallPath(192, 108);
    o.module.vsm.clusterMarking = true;
    marksAndAllocationEqualCpuReference(o, 40);
}

// A pool a little larger than a frame's need: once the free pages are gone, requests take cached pages
// least recently used first, from every age class (vsm_avail places them by class, then index), and
// the GPU still equals the reference every frame.
TEST(GpuVsm, EvictionFromEveryAgeClassEqualsCpuReference) {
    VsmSessionOptions o = smallPath(192, 108);
    o.module.vsm.poolPages = 192; // ~2x the path's largest frame: evicts 2-49 pages of each class 2..8
    AllocationSeen seen;
    marksAndAllocationEqualCpuReference(o, 100, &seen);
    // Class 1 (>= 128 frames unused) cannot occur on a 100-frame path; class 0 pages are free, not evicted.
    for (uint32_t cls = 2; cls < 9; ++cls)
        EXPECT_GT(seen.evictedByClass[cls], 0u) << "no page evicted from LRU class " << cls;
}

// The map-slot pool starts at 8 slots and grows (doubling) while lights come into view: the page table
// is copied at each growth, so the GPU state still equals the CPU reference bit for bit every frame.
TEST(GpuVsm, SlotPoolGrowsAndKeepsThePageTable) {
    VsmSessionOptions o = smallPath(192, 108);
    o.module.vsm.initialMaps = 8;
    AllocationSeen seen;
    marksAndAllocationEqualCpuReference(o, 30, &seen);
    EXPECT_GT(seen.grownTo, 8u);
}

// The guarantee holds while the pool keeps one page per light with receivers (each light's coarsest page
// is served first): 64 lights on the drive path need ~80 pages for ~35 such lights, so a quarter pool
// still has room for those. (256 unbaked lights give ~145 lights with pages for ~125 marked pages: a
// quarter pool cannot hold a page per light, and the lookups past it are counted as fallbacks.)
TEST(GpuVsm, QuarterPoolCountsFallbacksAndKeepsEveryShadow) {
    resetValidationCounters();
    const uint32_t frames = 8;
    uint32_t need = 0;
    VsmSessionOptions full = smallPath(320, 180);
    full.lights = 64;
    {
        auto session = VsmSession::create(full);
        ASSERT_TRUE(session.ok()) << session.error();
        for (uint32_t f = 0; f < frames; ++f) {
            auto r = session.value()->frame(f);
            ASSERT_TRUE(r.ok()) << r.error();
            EXPECT_EQ(r->stats.vsm.fallbacks, 0u);
            need = std::max(need, r->stats.vsm.pagesMarked);
        }
    }
    ASSERT_GT(need, 8u);
    VsmSessionOptions o = full;
    o.module.vsm.poolPages = need / 4;
    o.module.vsm.probeCapacity = 320 * 180 * 8;
    auto session = VsmSession::create(o);
    ASSERT_TRUE(session.ok()) << session.error();
    uint64_t fallbacks = 0, fallbackLookups = 0, lookups = 0;
    for (uint32_t f = 0; f < frames; ++f) {
        auto r = session.value()->frame(f);
        ASSERT_TRUE(r.ok()) << r.error();
        fallbacks += r->stats.vsm.fallbacks;
        uint32_t overflow = 0;
        auto probes = internals(*session.value()->module)
                          .vsm.readProbes(internals(*session.value()->module).lastSlot, &overflow);
        ASSERT_EQ(overflow, 0u);
        for (const auto& p : probes) {
            ASSERT_NE(p.info.w, ML_VSM_PROBE_MISSING)
                << "frame " << f << ": a lookup found no page at any mip (map " << p.texel.x << ", mip "
                << p.texel.y << ", kind "
                << internals(*session.value()->module).vsm.mapInfo()[p.texel.x].gpu.info.x << ", pool "
                << o.module.vsm.poolPages << ", need " << need << ", fallbacks " << r->stats.vsm.fallbacks
                << ")";
            fallbackLookups += p.info.w == ML_VSM_PROBE_FALLBACK;
            ++lookups;
        }
    }
    EXPECT_GT(fallbacks, 0u) << "a pool of " << need / 4 << " pages for a need of " << need;
    EXPECT_GT(fallbackLookups, 0u);
    EXPECT_GT(lookups, 0u);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test

namespace ml::test {
namespace {

// A directional light (moonlight) gets one map per clip level around the camera; its shadows darken
// pixels that the unshadowed frame lights, every lookup finds a page, and nothing is NaN.
TEST(GpuVsm, DirectionalClipLevelsShadowAndResolve) {
    resetValidationCounters();
    std::vector<uint8_t> images[2];
    for (int on = 0; on < 2; ++on) {
        VsmSessionOptions o = smallPath(160, 90);
        o.path = CameraPath::Orbit;
        o.lights = 8;
        o.module.vsm.enabled = on == 1;
        o.module.vsm.kinds = 4; // directional only
        o.module.vsm.probeCapacity = on ? 160 * 90 * 4 : 0;
        auto session = VsmSession::create(o);
        ASSERT_TRUE(session.ok()) << session.error();
        Module& m = *session.value()->module;
        LightDesc moon;
        moon.kind = LightKind::Directional;
        moon.direction = glm::normalize(glm::vec3(0.4f, -1.0f, 0.3f));
        moon.intensity = 2.0f;
        ASSERT_TRUE(m.addLight(moon).ok());
        for (uint32_t f = 0; f < 3; ++f) {
            auto r = session.value()->frame(f);
            ASSERT_TRUE(r.ok()) << r.error();
            if (on) {
                EXPECT_EQ(r->stats.vsm.lightsWithPages, 1u);
                EXPECT_GT(r->stats.vsm.pagesMarked, 0u);
                auto probes = internals(m).vsm.readProbes(internals(m).lastSlot);
                ASSERT_FALSE(probes.empty());
                for (const auto& p : probes) ASSERT_NE(p.info.w, ML_VSM_PROBE_MISSING);
            }
        }
        ASSERT_TRUE(m.readOutput(images[on]).ok());
        auto hdr = readImage(m, internals(m).hdr, 8, VK_IMAGE_LAYOUT_GENERAL);
        for (size_t i = 0; i < size_t(160) * 90; ++i) {
            glm::vec4 c = half4(hdr, i);
            ASSERT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) << "pixel " << i;
        }
    }
    size_t darker = 0, brighter = 0;
    for (size_t i = 0; i < images[0].size(); i += 4) {
        darker += images[1][i + 2] + 8 < images[0][i + 2];
        brighter += images[1][i + 2] > images[0][i + 2] + 8;
    }
    EXPECT_GT(darker, 100u) << "the moonlight casts shadows with virtual shadow maps on";
    EXPECT_EQ(brighter, 0u) << "shadows only remove light";
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
