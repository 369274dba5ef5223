// engine/limits.h on recorded limit tables (no device): lavapipe (Mesa 22, this machine's vulkaninfo)
// and a desktop GPU (24 GiB, 4 GiB storage range, 32768 image side). Each refusal is one
// line naming the setting, the value and the limit; capacities are reduced and said.
#include "engine/limits.h"
#include "gpu/program.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

DeviceLimitTable lavapipe() {
    DeviceLimitTable t;
    t.maxStorageBufferRange = 134217728; // 128 MiB
    t.maxImageDimension2D = 16384;
    t.maxImageArrayLayers = 2048;
    t.maxMemoryAllocationSize = 0x80000000ull;
    t.maxBufferSize = 0xFFFFFFFFull;
    t.deviceLocalHeap = 25275990016ull; // 23.5 GiB (the machine's memory)
    t.maxDrawIndirectCount = 0xFFFFFFFFu;
    return t;
}
DeviceLimitTable desktop() {
    DeviceLimitTable t;
    t.maxWorkGroupCount[0] = 2147483647;
    t.maxStorageBufferRange = 0xFFFFFFFFull;
    t.maxImageDimension2D = 32768;
    t.maxImageArrayLayers = 2048;
    t.maxMemoryAllocationSize = 0xFFFFFFFFull;
    t.maxBufferSize = 0xFFFFFFFFull;
    t.deviceLocalHeap = 24ull << 30;
    t.maxDrawIndirectCount = 0xFFFFFFFFu;
    return t;
}

void expectOneLine(const std::string& e, const std::string& needle) {
    EXPECT_NE(e.find(needle), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(Limits, TargetSizes) {
    EXPECT_TRUE(checkTargetLimits(lavapipe(), 1, 1, true));
    EXPECT_TRUE(checkTargetLimits(lavapipe(), 1920, 1080, true));
    EXPECT_TRUE(checkTargetLimits(lavapipe(), 2560, 1440, true));
    // 8192^2: the cluster bounds (32 B per 8x8x64 cluster, one per pixel) are 2 GiB, past 128 MiB.
    auto big = checkTargetLimits(lavapipe(), 8192, 8192, true);
    ASSERT_FALSE(big);
    expectOneLine(big.error(), "size 8192x8192: the cluster bounds need 2048 MiB");
    expectOneLine(big.error(), "maxStorageBufferRange 128 MiB");
    auto side = checkTargetLimits(lavapipe(), 16385, 8, true);
    ASSERT_FALSE(side);
    expectOneLine(side.error(), "maxImageDimension2D 16384");
    // The desktop table holds 8192^2; 16384^2's bounds are 8 GiB; 11000^2 passes them (3.9 GB) but
    // needs 20.8 GB of targets and cluster buffers, past half the 24 GiB heap.
    EXPECT_TRUE(checkTargetLimits(desktop(), 8192, 8192, true));
    auto bounds = checkTargetLimits(desktop(), 16384, 16384, true);
    ASSERT_FALSE(bounds);
    expectOneLine(bounds.error(), "cluster bounds need 8192 MiB in one storage buffer, past the device's "
                                  "maxStorageBufferRange 4096 MiB");
    auto heap = checkTargetLimits(desktop(), 11000, 11000, true);
    ASSERT_FALSE(heap);
    expectOneLine(heap.error(), "device-local memory heap (24576 MiB)");
    // A 1-D dispatch over the tiles: 65,535 groups of 64 tiles is the bound with the minimum limit.
    DeviceLimitTable wide = desktop();
    wide.maxWorkGroupCount[0] = 65535;
    wide.deviceLocalHeap = 0;
    wide.maxMemoryAllocationSize = wide.maxStorageBufferRange = uint64_t(1) << 40;
    auto groups = checkTargetLimits(wide, 32768, 32768, false);
    ASSERT_FALSE(groups);
    expectOneLine(groups.error(), "maxComputeWorkGroupCount 65535");
}

TEST(Limits, VsmCapacitiesReducedToFit) {
    std::vector<std::string> notes;
    VsmSettings s; // 4096^2, 64^2 pages, 4096 pages; the default maxMaps: as many as fit, no note
    auto dflt = fitVsmSettings(lavapipe(), s, notes);
    ASSERT_TRUE(dflt) << dflt.error();
    EXPECT_TRUE(notes.empty());
    EXPECT_EQ(dflt->maxMaps, 6144u); // 5,461 entries of 4 B a map in 128 MiB
    s.maxMaps = 512;                 // a host's own value that fits: kept
    auto same = fitVsmSettings(lavapipe(), s, notes);
    ASSERT_TRUE(same) << same.error();
    EXPECT_TRUE(notes.empty());
    EXPECT_EQ(same->maxMaps, 512u);
    // 16384^2 in 64^2 pages: 87,381 entries a map, 512 maps = 179 MB: 384 maps fit 128 MiB.
    s.resolution = 16384;
    auto maps = fitVsmSettings(lavapipe(), s, notes);
    ASSERT_TRUE(maps) << maps.error();
    EXPECT_EQ(maps->maxMaps, 384u);
    ASSERT_EQ(notes.size(), 1u);
    expectOneLine(notes[0], "vsm: map slots 512 -> 384");
    // 128^2 pages, 4096 of them: 256 MiB, 512 MiB with the static twins (VsmSettings::staticLayer): 1024
    // fit, 2048 without the twins.
    notes.clear();
    s.resolution = 4096, s.pageSize = 128;
    auto pool = fitVsmSettings(lavapipe(), s, notes);
    ASSERT_TRUE(pool) << pool.error();
    EXPECT_EQ(pool->poolPages, 1024u);
    ASSERT_EQ(notes.size(), 1u);
    expectOneLine(notes[0], "vsm: pool pages 4096 -> 1024");
    notes.clear();
    VsmSettings single = s;
    single.staticLayer = false;
    auto pool1 = fitVsmSettings(lavapipe(), single, notes);
    ASSERT_TRUE(pool1) << pool1.error();
    EXPECT_EQ(pool1->poolPages, 2048u);
    ASSERT_EQ(notes.size(), 1u);
    expectOneLine(notes[0], "vsm: pool pages 4096 -> 2048");
    notes.clear();
    EXPECT_TRUE(fitVsmSettings(desktop(), s, notes));
    EXPECT_TRUE(notes.empty());
}

TEST(Limits, VsmRefusals) {
    std::vector<std::string> notes;
    VsmSettings s;
    s.probeCapacity = 1920 * 1080 * 8; // check vsm's 8 per pixel: 759 MiB of 48 B records
    auto probes = fitVsmSettings(lavapipe(), s, notes);
    ASSERT_FALSE(probes);
    expectOneLine(probes.error(), "vsm: probe capacity 16588800 needs 760 MiB");
    s.probeCapacity = 320 * 180 * 8;
    EXPECT_TRUE(fitVsmSettings(lavapipe(), s, notes));
    DeviceLimitTable few = lavapipe(); // image array layers no longer bound the map slots (HPB of bits)
    few.maxImageArrayLayers = 256;
    EXPECT_TRUE(fitVsmSettings(few, s, notes));
    DeviceLimitTable single = lavapipe();
    single.maxDrawIndirectCount = 1; // a device without multiDrawIndirect
    auto draws = fitVsmSettings(single, s, notes);
    ASSERT_FALSE(draws);
    expectOneLine(draws.error(), "vsm: max draws per mip 16384 exceeds the device's maxDrawIndirectCount 1");
}

} // namespace
} // namespace ml
