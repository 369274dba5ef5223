// The one-workgroup allocation (vsm_allocate_short_list.comp) against the multi-dispatch passes and the
// CPU reference on real frames at 320x180: the night city's drive path and the indoor level. Each frame,
// the page table, owners and last-use frames of a module that allocates short lists in one workgroup
// equal those of a module held to the multi-dispatch passes (ML_VSM_ALLOC_SHORT_LIST=0) and
// vsmAllocateReference's. Then the limit itself: a limit equal to a frame's list length takes that frame
// in one workgroup, one entry less sends it to the multi-dispatch passes, with the same pages; lists
// long enough for several of vsm_sort's merge passes; and the one workgroup recorded alone (the
// multi-dispatch passes left out after a short list), which allocates a list past its limit in the list
// buffers with the same pages.
#include "vsm_test_util.h"

#include <algorithm>
#include <cstdlib>
#include <string>

namespace ml::test {
namespace {

struct AllocFrame {
    std::vector<uint32_t> table, owners, lastUsed;
    uint32_t listLength = 0, evicted = 0, fallbacks = 0;
    uint32_t path = 0;     // vsmSortArgs word 1: 0 multi-dispatch, 1 one workgroup, 2 one in list buffers
    bool oneGroup = false; // path 1: sorted in the workgroup's shared memory
    bool alone = false;    // the multi-dispatch passes were not recorded (VsmPasses::oneWorkgroupOnly)
};

VsmSessionOptions shortAllocOptions(const char* scene) {
    VsmSessionOptions o = vsmSmallDrive();
    o.scene = scene;
    o.width = 320;
    o.height = 180;
    o.module.vsm.poolPages = 2048;
    return o;
}

// Runs `frames` frames with ML_VSM_ALLOC_SHORT_LIST=limit (empty: the default) and checks each frame's
// allocation against vsmAllocateReference on the same marks; `sequence` forces the recorded passes.
std::vector<AllocFrame> runFrames(const VsmSessionOptions& o, const char* limit, uint32_t frames,
                                  VsmPasses::Sequence sequence = VsmPasses::Sequence::Auto) {
    if (*limit)
        setenv("ML_VSM_ALLOC_SHORT_LIST", limit, 1);
    else
        unsetenv("ML_VSM_ALLOC_SHORT_LIST");
    auto session = VsmSession::create(o);
    unsetenv("ML_VSM_ALLOC_SHORT_LIST");
    EXPECT_TRUE(session.ok()) << session.error();
    std::vector<AllocFrame> out;
    if (!session.ok()) return out;
    VsmSession& s = *session.value();
    Module& m = *s.module;
    internals(m).vsmPasses.setSequence(sequence);
    const VirtualShadowMaps& vsm = internals(m).vsm;
    VsmAllocState cpu;
    cpu.table.assign(size_t(vsm.settings().maxMaps) * vsm.layout().entriesPerMap, 0);
    cpu.owners.assign(vsm.settings().poolPages, ML_VSM_NO_OWNER);
    cpu.lastUsed.assign(vsm.settings().poolPages, 0);
    for (uint32_t f = 0; f < frames; ++f) {
        auto report = s.frame(f);
        EXPECT_TRUE(report.ok()) << report.error();
        if (!report.ok()) break;
        const uint32_t slot = internals(m).lastSlot;
        const Device& d = deviceOf(m);
        vsmAllocateReference(cpu, vsm.read(d, VsmState::Marks), vsm.slotHost(slot).stale,
                             vsm.slotHost(slot).maps, vsm.slotHost(slot).runs, vsm.lastConstants());
        AllocFrame a;
        a.table = vsm.read(d, VsmState::Table);
        a.owners = vsm.read(d, VsmState::Owners);
        a.lastUsed = vsm.read(d, VsmState::LastUsed);
        const std::vector<uint32_t> words = vsm.read(d, VsmState::SortArgs);
        a.path = words[1];
        a.oneGroup = words[1] == 1u;
        a.alone = internals(m).vsmPasses.oneWorkgroupOnly(slot);
        EXPECT_TRUE(!a.alone || a.path != 0u) << "frame " << f << ": no pass allocated the list";
        a.listLength = words[2];
        a.evicted = report->stats.vsm.pagesEvicted;
        a.fallbacks = report->stats.vsm.fallbacks;
        EXPECT_TRUE(std::equal(a.table.begin(), a.table.end(), cpu.table.begin()))
            << "frame " << f << " (limit '" << limit << "'): page table differs from vsmAllocateReference";
        EXPECT_EQ(a.owners, cpu.owners) << "frame " << f;
        EXPECT_EQ(a.lastUsed, cpu.lastUsed) << "frame " << f;
        out.push_back(std::move(a));
    }
    return out;
}

void expectSame(const std::vector<AllocFrame>& a, const std::vector<AllocFrame>& b, const char* what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (size_t f = 0; f < a.size(); ++f) {
        EXPECT_EQ(a[f].listLength, b[f].listLength) << what << ", frame " << f;
        EXPECT_EQ(a[f].table, b[f].table) << what << ", frame " << f << ": page tables differ";
        EXPECT_EQ(a[f].owners, b[f].owners) << what << ", frame " << f;
        EXPECT_EQ(a[f].lastUsed, b[f].lastUsed) << what << ", frame " << f;
    }
}

// poolPages: 0 keeps shortAllocOptions' 2,048 (room for every page); a small pool evicts and falls back.
struct PoolEvents {
    size_t evicted = 0, fallbacks = 0;
};

PoolEvents oneGroupEqualsMultiDispatch(const char* scene, uint32_t frames, uint32_t poolPages = 0) {
    resetValidationCounters();
    VsmSessionOptions o = shortAllocOptions(scene);
    if (poolPages) o.module.vsm.poolPages = poolPages;
    const std::vector<AllocFrame> multi = runFrames(o, "0", frames);
    const std::vector<AllocFrame> one = runFrames(o, "", frames);
    expectSame(multi, one, scene);
    size_t oneGroupFrames = 0, marked = 0;
    PoolEvents events;
    for (size_t f = 0; f < one.size(); ++f) {
        EXPECT_FALSE(multi[f].oneGroup) << "frame " << f << ": the limit 0 took a list in one workgroup";
        EXPECT_EQ(one[f].oneGroup, one[f].listLength <= ML_VSM_ONE_GROUP_LIST) << "frame " << f;
        oneGroupFrames += one[f].oneGroup;
        // A slot's second frame on: its last list was short, so the multi-dispatch passes are left out.
        EXPECT_EQ(one[f].alone, f >= o.module.framesInFlight) << "frame " << f;
        marked += one[f].listLength;
        EXPECT_EQ(one[f].evicted, multi[f].evicted) << "frame " << f;
        EXPECT_EQ(one[f].fallbacks, multi[f].fallbacks) << "frame " << f;
        events.evicted += one[f].evicted;
        events.fallbacks += one[f].fallbacks;
    }
    EXPECT_EQ(oneGroupFrames, one.size()) << scene << ": lists at 320x180 fit one workgroup";
    EXPECT_GT(marked, 0u) << scene << ": no page wanted (nothing tested)";
    std::printf("%s: %zu frames, %zu list entries, %zu frames in one workgroup\n", scene, one.size(), marked,
                oneGroupFrames);
    EXPECT_EQ(validationErrors(), 0u);
    return events;
}

TEST(GpuVsmShortAlloc, NightCityOneWorkgroupEqualsMultiDispatchAndCpu) {
    oneGroupEqualsMultiDispatch("night-city", 6);
}

TEST(GpuVsmShortAlloc, IndoorOneWorkgroupEqualsMultiDispatchAndCpu) {
    oneGroupEqualsMultiDispatch("indoor", 4);
}

// A pool of 256 pages, under the indoor level's need: pages are evicted and requests fall back, the same
// in one workgroup as in the multi-dispatch passes.
TEST(GpuVsmShortAlloc, IndoorSmallPoolEvictsAndFallsBackTheSame) {
    const PoolEvents events = oneGroupEqualsMultiDispatch("indoor", 4, 256);
    EXPECT_GT(events.evicted, 0u) << "no page evicted (eviction untested)";
    EXPECT_GT(events.fallbacks, 0u) << "no request fell back (fallbacks untested)";
}

// Frame 1's list length n as the limit: that frame goes to one workgroup; n - 1: to the multi-dispatch
// passes (the fallback); both equal the multi-dispatch module's pages and the CPU reference.
TEST(GpuVsmShortAlloc, AtTheLimitOneWorkgroupJustOverItMultiDispatch) {
    resetValidationCounters();
    const VsmSessionOptions o = shortAllocOptions("night-city");
    const std::vector<AllocFrame> multi = runFrames(o, "0", 3);
    ASSERT_EQ(multi.size(), 3u);
    const uint32_t n = multi[1].listLength;
    ASSERT_GT(n, 1u) << "frame 1 wants no page";
    ASSERT_LE(n, uint32_t(ML_VSM_ONE_GROUP_LIST));
    const std::vector<AllocFrame> at = runFrames(o, std::to_string(n).c_str(), 3);
    const std::vector<AllocFrame> over = runFrames(o, std::to_string(n - 1).c_str(), 3);
    expectSame(multi, at, "at the limit");
    expectSame(multi, over, "just over the limit");
    ASSERT_EQ(at.size(), 3u);
    ASSERT_EQ(over.size(), 3u);
    EXPECT_TRUE(at[1].oneGroup) << "a list of exactly the limit (" << n << ") goes to one workgroup";
    EXPECT_FALSE(over[1].oneGroup) << "a list one past the limit (" << n - 1
                                   << ") goes to the multi-dispatch passes or the list buffers";
    EXPECT_NE(over[1].path, 1u);
    EXPECT_EQ(validationErrors(), 0u);
}

// Lists past one workgroup and past the first 8-way merge pass (runs of 256 -> 2,048, then 2,048 ->
// 16,384; vsm_sort.comp): the indoor level at 640x360 with 1,024 lights and twice the texels per pixel.
// The multi-dispatch passes give the pages of vsmAllocateReference every frame (runFrames checks), and
// the default module, which sends these lists to the same passes, the same pages.
TEST(GpuVsmShortAlloc, LongListsMergeAcrossPassesEqualCpu) {
    resetValidationCounters();
    VsmSessionOptions o = shortAllocOptions("indoor");
    o.width = 640;
    o.height = 360;
    o.lights = 1024;
    o.module.vsm.resolution = 4096;
    o.module.vsm.texelsPerPixel = 2.0f;
    o.module.vsm.poolPages = 8192;
    const std::vector<AllocFrame> multi = runFrames(o, "0", 2);
    const std::vector<AllocFrame> deflt = runFrames(o, "", 2);
    expectSame(multi, deflt, "long lists");
    uint32_t longest = 0;
    for (const AllocFrame& a : multi) longest = std::max(longest, a.listLength);
    std::printf("longest list %u entries\n", longest);
    EXPECT_GT(longest, uint32_t(ML_VSM_BLOCK) << ML_VSM_MERGE_WAYS_LOG2)
        << "no list reached the second merge pass";
    for (const AllocFrame& a : deflt)
        EXPECT_EQ(a.oneGroup, a.listLength <= ML_VSM_ONE_GROUP_LIST) << a.listLength << " entries";
    // The one workgroup alone: lists past its shared memory sorted in the list buffers, same pages.
    const std::vector<AllocFrame> alone = runFrames(o, "", 2, VsmPasses::Sequence::OneWorkgroup);
    expectSame(multi, alone, "long lists in one workgroup alone");
    for (const AllocFrame& a : alone) {
        EXPECT_TRUE(a.alone);
        EXPECT_EQ(a.path, a.listLength <= ML_VSM_ONE_GROUP_LIST ? 1u : 2u) << a.listLength << " entries";
    }
    EXPECT_EQ(validationErrors(), 0u);
}

// The one workgroup recorded alone (the prediction from the slot's last list) when this frame's list is
// longer than the limit, forced here by ML_VSM_ALLOC_SHORT_LIST=16 under every frame's list: each list
// is sorted in the list buffers and gives the pages of the multi-dispatch passes and of
// vsmAllocateReference (runFrames checks), on the night city and on the indoor level with a pool of 256
// pages that evicts and falls back.
TEST(GpuVsmShortAlloc, AloneListsPastTheLimitSortInTheListBuffers) {
    resetValidationCounters();
    for (const char* scene : {"night-city", "indoor"}) {
        VsmSessionOptions o = shortAllocOptions(scene);
        if (std::string(scene) == "indoor") o.module.vsm.poolPages = 256;
        const std::vector<AllocFrame> multi = runFrames(o, "0", 4);
        const std::vector<AllocFrame> alone = runFrames(o, "16", 4, VsmPasses::Sequence::OneWorkgroup);
        expectSame(multi, alone, scene);
        size_t listBufferFrames = 0;
        for (size_t f = 0; f < alone.size(); ++f) {
            EXPECT_TRUE(alone[f].alone) << scene << ", frame " << f;
            EXPECT_EQ(alone[f].path, alone[f].listLength <= 16u ? 1u : 2u) << scene << ", frame " << f;
            EXPECT_EQ(alone[f].fallbacks, multi[f].fallbacks) << scene << ", frame " << f;
            listBufferFrames += alone[f].path == 2u;
        }
        EXPECT_GT(listBufferFrames, 0u)
            << scene << ": no list past the limit (the list-buffer sort untested)";
    }
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
