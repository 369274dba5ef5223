// The hierarchical page buffer (vsm_hpb.comp, a mipped array image: layer per map, mip per level) read
// back level by level through the staging path and compared with a CPU build from the page table's
// DIRTY bits (the bits the HPB was built from: scan clears them only at the next frame's start), for
// every active map of every frame of a drive path, including the zero texels outside every mip's cells.
#include "gpu_test_util.h"
#include "host/vsm_session.h"
#include "shadows/virtual/vsm_math.h"

namespace ml::test {
namespace {

// CPU twin: level l of one map as the whole image mip (width S_0 >> (l - 1), height S_0 >> l).
std::vector<std::vector<uint32_t>> hpbReference(const std::vector<uint32_t>& table, uint32_t map, uint32_t s0,
                                                uint32_t mips, uint32_t entriesPerMap) {
    std::vector<std::vector<uint32_t>> levels;
    for (uint32_t level = 1; (s0 >> level) != 0; ++level) {
        const uint32_t width = s0 >> (level - 1), height = s0 >> level;
        std::vector<uint32_t> img(size_t(width) * height, 0);
        for (uint32_t mip = 0; mip < mips; ++mip) {
            const uint32_t side = (s0 >> mip) >> level, first = gpu::vsmHpbColumn(s0, mip) >> level;
            for (uint32_t y = 0; y < side; ++y)
                for (uint32_t x = 0; x < side; ++x) {
                    // Straight from the pages under the cell (no use of the level below).
                    uint32_t any = 0;
                    for (uint32_t py = y << level; py < (y + 1) << level; ++py)
                        for (uint32_t px = x << level; px < (x + 1) << level; ++px)
                            any |= table[gpu::vsmEntry(entriesPerMap, s0, map, mip, px, py)] & ML_VSM_DIRTY;
                    img[size_t(y) * width + first + x] = any ? 1u : 0u;
                }
        }
        levels.push_back(std::move(img));
    }
    return levels;
}

TEST(GpuVsmHpb, EveryLevelOfEveryActiveMapEqualsCpuBuild) {
    resetValidationCounters();
    VsmSessionOptions o;
    o.width = 160;
    o.height = 90;
    o.path = CameraPath::Drive;
    o.module.device.validation = true;
    o.module.vsm.resolution = 1024; // 16 pages of 64: levels 1..4
    o.module.vsm.poolPages = 1024;
    auto session = VsmSession::create(o);
    ASSERT_TRUE(session.ok()) << session.error();
    VsmSession& s = *session.value();
    Module& m = *s.module;
    const VirtualShadowMaps& vsm = internals(m).vsm;
    ASSERT_EQ(vsm.layout().hpbLevels, 4u);
    uint64_t maps = 0, ones = 0, zeros = 0;
    for (uint32_t f = 0; f < 6; ++f) {
        auto report = s.frame(f);
        ASSERT_TRUE(report.ok()) << report.error();
        const uint32_t slot = internals(m).lastSlot;
        std::vector<uint32_t> table = vsm.read(deviceOf(m), VsmState::Table);
        table.resize(size_t(vsm.settings().maxMaps) * vsm.layout().entriesPerMap, 0);
        for (uint32_t map : vsm.slotHost(slot).active) {
            auto ref = hpbReference(table, map, vsm.layout().pagesPerSide, vsm.layout().mips,
                                    vsm.layout().entriesPerMap);
            for (uint32_t level = 1; level <= vsm.layout().hpbLevels; ++level) {
                std::vector<uint32_t> gpu = vsm.readHpb(deviceOf(m), map, level);
                ASSERT_EQ(gpu, ref[level - 1]) << "frame " << f << " map " << map << " level " << level;
                for (uint32_t v : gpu) (v ? ones : zeros)++;
            }
            ++maps;
        }
    }
    std::printf("%llu map builds compared, %llu set and %llu clear HPB cells\n", (unsigned long long)maps,
                (unsigned long long)ones, (unsigned long long)zeros);
    EXPECT_GT(maps, 0u);
    EXPECT_GT(ones, 0u); // both answers occur
    EXPECT_GT(zeros, 0u);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml::test
