// Memory placement by role (gpu/memory.h) over recorded VkPhysicalDeviceMemoryProperties tables: a
// discrete GPU with a device-local heap and a host heap, the same with a small 256 MiB host-visible
// device-local heap (ReBAR off) and with ReBAR on, an integrated GPU and lavapipe. The tables follow what
// vulkaninfo reports on such devices (type order as drivers list them); lavapipe's is checked against
// the device this test runs on. Then the module on lavapipe: bytes per kind counted and released.
#include "gpu/memory.h"
#include "gpu_test_util.h"

#include <gtest/gtest.h>

namespace ml {
namespace {

constexpr VkMemoryPropertyFlags DL = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
constexpr VkMemoryPropertyFlags HV = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
constexpr VkMemoryPropertyFlags HC = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkMemoryPropertyFlags CACHED = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
constexpr VkDeviceSize MiB = 1 << 20, GiB = VkDeviceSize(1) << 30;

struct TypeRow {
    VkMemoryPropertyFlags flags;
    uint32_t heap;
};
VkPhysicalDeviceMemoryProperties table(std::initializer_list<std::pair<VkDeviceSize, bool>> heaps,
                                       std::initializer_list<TypeRow> types) {
    VkPhysicalDeviceMemoryProperties p{};
    for (auto [size, deviceLocal] : heaps)
        p.memoryHeaps[p.memoryHeapCount++] = {
            size, deviceLocal ? VkMemoryHeapFlags(VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) : 0u};
    for (const TypeRow& t : types) p.memoryTypes[p.memoryTypeCount++] = {t.flags, t.heap};
    return p;
}

// Discrete, no BAR exposed: VRAM and system memory only (an older driver or a BAR the OS hides).
VkPhysicalDeviceMemoryProperties discrete() {
    return table({{8 * GiB, true}, {16 * GiB, false}}, {{DL, 0}, {HV | HC, 1}, {HV | HC | CACHED, 1}});
}
// Discrete with ReBAR off: a 256 MiB host-visible window into VRAM (NVIDIA lists it last).
VkPhysicalDeviceMemoryProperties discreteSmallBar() {
    return table({{8 * GiB, true}, {16 * GiB, false}, {256 * MiB, true}},
                 {{DL, 0}, {HV | HC, 1}, {HV | HC | CACHED, 1}, {DL | HV | HC, 2}});
}
// Discrete with ReBAR on: all of VRAM host-visible; AMD also lists device-coherent types (avoided).
VkPhysicalDeviceMemoryProperties discreteReBar() {
    constexpr VkMemoryPropertyFlags amd =
        VK_MEMORY_PROPERTY_DEVICE_COHERENT_BIT_AMD | VK_MEMORY_PROPERTY_DEVICE_UNCACHED_BIT_AMD;
    return table({{16 * GiB, true}, {32 * GiB, false}},
                 {{DL | HV | HC | amd, 0}, {DL, 0}, {HV | HC, 1}, {DL | HV | HC, 0}, {HV | HC | CACHED, 1}});
}
// Integrated (one heap of shared memory, Intel-like types).
VkPhysicalDeviceMemoryProperties integrated() {
    return table({{16 * GiB, true}}, {{DL, 0}, {DL | HV | HC, 0}, {DL | HV | HC | CACHED, 0}});
}
// lavapipe (Mesa 25): one heap, one type with every host flag.
VkPhysicalDeviceMemoryProperties lavapipe() {
    return table({{24 * GiB, true}}, {{DL | HV | HC | CACHED, 0}});
}

struct Landing {
    uint32_t type;
    MemoryKind kind;
};
void expectLands(const VkPhysicalDeviceMemoryProperties& p, MemoryRole role, VkDeviceSize size, Landing want,
                 uint32_t typeBits = ~0u) {
    const MemoryChoice c = selectMemoryType(p, typeBits, role, size);
    EXPECT_EQ(c.type, want.type) << memoryRoleName(role) << " of " << size << " bytes";
    EXPECT_EQ(c.kind, want.kind) << memoryRoleName(role) << " of " << size << " bytes";
    if (c.type != ~0u && roleIsMapped(role)) { // mapped roles are always coherent (no flushes in the module)
        EXPECT_TRUE(p.memoryTypes[c.type].propertyFlags & HC);
    }
}

TEST(MemoryPlacement, DiscreteWithoutBar) {
    const auto p = discrete();
    expectLands(p, MemoryRole::GpuOnly, 64 * MiB, {0, MemoryKind::DeviceLocal});
    expectLands(p, MemoryRole::Upload, 64 * 1024, {1, MemoryKind::Host}); // uncached: write-combined
    expectLands(p, MemoryRole::Readback, 64 * 1024, {2, MemoryKind::HostCached});
    expectLands(p, MemoryRole::Staging, 64 * MiB, {1, MemoryKind::Host});
}

TEST(MemoryPlacement, DiscreteSmallBarTakesOnlySmallUploads) {
    const auto p = discreteSmallBar();
    expectLands(p, MemoryRole::GpuOnly, 64 * MiB, {0, MemoryKind::DeviceLocal}); // not the BAR
    // 256 MiB / kBarUploadFraction = 8 MiB: a frame's constants and lights go to the BAR, larger to host.
    expectLands(p, MemoryRole::Upload, 64 * 1024, {3, MemoryKind::DeviceMappable});
    expectLands(p, MemoryRole::Upload, 256 * MiB / kBarUploadFraction, {3, MemoryKind::DeviceMappable});
    expectLands(p, MemoryRole::Upload, 256 * MiB / kBarUploadFraction + 4, {1, MemoryKind::Host});
    expectLands(p, MemoryRole::Readback, 64 * 1024, {2, MemoryKind::HostCached});
    expectLands(p, MemoryRole::Staging, 64 * 1024, {1, MemoryKind::Host}); // the BAR stays for uploads
}

TEST(MemoryPlacement, DiscreteReBarAvoidsDeviceCoherentTypes) {
    const auto p = discreteReBar();
    expectLands(p, MemoryRole::GpuOnly, 64 * MiB, {1, MemoryKind::DeviceLocal});
    expectLands(p, MemoryRole::Upload, 512 * MiB, {3, MemoryKind::DeviceMappable}); // the heap is all VRAM
    expectLands(p, MemoryRole::Readback, 64 * 1024, {4, MemoryKind::HostCached});
    expectLands(p, MemoryRole::Staging, 64 * 1024, {2, MemoryKind::Host});
}

TEST(MemoryPlacement, Integrated) {
    const auto p = integrated();
    expectLands(p, MemoryRole::GpuOnly, 64 * MiB, {0, MemoryKind::DeviceLocal});
    expectLands(p, MemoryRole::Upload, 64 * MiB, {1, MemoryKind::DeviceMappable});
    expectLands(p, MemoryRole::Readback, 64 * 1024, {2, MemoryKind::DeviceMappable});
    expectLands(p, MemoryRole::Staging, 64 * 1024, {1, MemoryKind::DeviceMappable});
}

TEST(MemoryPlacement, LavapipeEverythingInItsOneType) {
    const auto p = lavapipe();
    for (uint32_t r = 0; r < kMemoryRoleCount; ++r)
        expectLands(p, MemoryRole(r), 64 * MiB, {0, MemoryKind::DeviceMappable});
}

TEST(MemoryPlacement, AllowedTypesRestrictTheChoice) {
    // A resource that cannot live in VRAM (memoryTypeBits without type 0) falls back for GPU-only use;
    // one with no host-visible type allowed cannot be mapped: no choice (an error at allocation).
    const auto p = discrete();
    expectLands(p, MemoryRole::GpuOnly, 1024, {1, MemoryKind::Host}, 0b110);
    expectLands(p, MemoryRole::Readback, 1024, {1, MemoryKind::Host}, 0b011); // no cached type allowed
    EXPECT_EQ(selectMemoryType(p, 0b001, MemoryRole::Upload, 1024).type, ~0u);
}

TEST(MemoryPlacement, DescribesEveryRole) {
    const std::string line = describePlacement(discreteSmallBar());
    EXPECT_EQ(line, "gpu-only -> type 0 (device_local, heap 0 8192 MiB); upload -> type 3 (device_mappable, "
                    "heap 2 256 MiB); readback -> type 2 (host_cached, heap 1 16384 MiB); staging -> type 1 "
                    "(host, heap 1 16384 MiB)");
}

// The recorded lavapipe table is this machine's device (flags and heap of its types), and the module's
// buffers and images are counted by kind while they live.
TEST(MemoryPlacement, ModuleCountsBytesPerKind) {
    auto m = test::makeModule();
    ASSERT_TRUE(m);
    Device& d = deviceOf(*m);
    const auto rec = lavapipe();
    ASSERT_EQ(d.memoryProperties.memoryTypeCount, rec.memoryTypeCount) << d.name;
    EXPECT_EQ(d.memoryProperties.memoryTypes[0].propertyFlags, rec.memoryTypes[0].propertyFlags);
    EXPECT_NE(m->deviceInfo().memoryPlacement.find("gpu-only -> type 0 (device_mappable"), std::string::npos)
        << m->deviceInfo().memoryPlacement;
    const uint64_t before = d.memoryUsage().bytes[uint32_t(MemoryKind::DeviceMappable)];
    EXPECT_GT(before, 0u); // slot buffers, profiler-independent
    ASSERT_TRUE(m->createTargets(64, 32).ok());
    const uint64_t withTargets = d.memoryUsage().bytes[uint32_t(MemoryKind::DeviceMappable)];
    // Three G-buffer images, HDR and output of 64x32: at least 64*32*(4+8+4+8+4) bytes more.
    EXPECT_GE(withTargets, before + 64 * 32 * 28);
    for (uint32_t k = 0; k < kMemoryKindCount; ++k)
        if (MemoryKind(k) != MemoryKind::DeviceMappable) {
            EXPECT_EQ(d.memoryUsage().bytes[k], 0u);
        }
    // By role: slot uploads, counters (readback), cluster-independent GPU-only images; kinds and roles
    // count the same allocations.
    const MemoryUsage u = d.memoryUsage();
    uint64_t byKind = 0, byRole = 0;
    for (uint64_t b : u.bytes) byKind += b;
    for (uint64_t b : u.roleBytes) byRole += b;
    EXPECT_EQ(byKind, byRole);
    EXPECT_GE(u.roleBytes[uint32_t(MemoryRole::GpuOnly)], 64u * 32 * 28);
    EXPECT_GT(u.roleBytes[uint32_t(MemoryRole::Upload)], 0u);
    EXPECT_GT(u.roleBytes[uint32_t(MemoryRole::Readback)], 0u);
    EXPECT_EQ(u.roleBytes[uint32_t(MemoryRole::Staging)], 0u); // staging lives only during a copy
    // Recreated before any frame: nothing can be in flight, so the old images are freed (and uncounted)
    // at once rather than retired.
    ASSERT_TRUE(m->createTargets(64, 32).ok());
    EXPECT_EQ(d.memoryUsage().bytes[uint32_t(MemoryKind::DeviceMappable)], withTargets);
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace
} // namespace ml
