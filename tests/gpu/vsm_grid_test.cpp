// 16384^2 maps of 64^2 pages at 256 lights: once ~86,000 allocation blocks of 256 entries,
// past 65,535 workgroups in one dimension (it aborted in dispatchThreads); now the allocation walks the
// request list of the marked pages. The page table, owners and last-use frames after
// allocation equal the CPU reference (vsmAllocateReference) on the same marks, two frames (the first
// allocates, the second keeps what it can).
#include "gpu_test_util.h"
#include "host/vsm_session.h"
#include "shadows/virtual/vsm_reference.h"

namespace ml::test {
namespace {

TEST(GpuVsm, AllocationPastOneDimensionOfWorkgroupsEqualsCpuReference) {
    resetValidationCounters();
    VsmSessionOptions o;
    o.width = 160; // the demo's view (static camera): 88,235 blocks
    o.height = 90;
    o.path = CameraPath::Static;
    o.module.device.validation = true;
    o.module.vsm.resolution = 16384;
    o.module.vsm.pageSize = 64;
    auto session = VsmSession::create(o);
    ASSERT_TRUE(session.ok()) << session.error();
    VsmSession& s = *session.value();
    Module& m = *s.module;
    const VirtualShadowMaps& vsm = internals(m).vsm;
    VsmAllocState cpu;
    cpu.table.assign(size_t(vsm.settings().maxMaps) * vsm.layout().entriesPerMap, 0);
    cpu.owners.assign(vsm.settings().poolPages, ML_VSM_NO_OWNER);
    cpu.lastUsed.assign(vsm.settings().poolPages, 0);
    const uint32_t maxGroups = deviceOf(m).properties.limits.maxComputeWorkGroupCount[0];
    for (uint32_t f = 0; f < 2; ++f) {
        auto report = s.frame(f);
        ASSERT_TRUE(report.ok()) << report.error();
        const uint32_t slot = internals(m).lastSlot;
        const uint64_t blocks = (uint64_t(vsm.slot(slot).orderEntries) + ML_VSM_BLOCK - 1) / ML_VSM_BLOCK;
        ASSERT_GT(blocks, maxGroups) << "frame " << f << ": the grid must need a second row";
        std::vector<uint32_t> marks = vsm.read(deviceOf(m), VsmState::Marks);
        gpu::VsmCounters c =
            vsmAllocateReference(cpu, marks, vsm.slotHost(slot).stale, vsm.slotHost(slot).maps,
                                 vsm.slotHost(slot).runs, vsm.lastConstants());
        std::vector<uint32_t> table = vsm.read(deviceOf(m), VsmState::Table);
        ASSERT_LE(table.size(), cpu.table.size());
        size_t differ = 0;
        for (size_t e = 0; e < table.size(); ++e) differ += table[e] != cpu.table[e];
        EXPECT_EQ(differ, 0u) << "frame " << f << ": page-table entries differ";
        EXPECT_EQ(vsm.read(deviceOf(m), VsmState::Owners), cpu.owners) << "frame " << f;
        EXPECT_EQ(vsm.read(deviceOf(m), VsmState::LastUsed), cpu.lastUsed) << "frame " << f;
        EXPECT_EQ(report->stats.vsm.pagesAllocated, c.pagesAllocated) << "frame " << f;
        EXPECT_EQ(report->stats.vsm.pagesMarked, c.pagesMarked) << "frame " << f;
        EXPECT_GT(c.pagesMarked, 0u) << "frame " << f;
    }
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
