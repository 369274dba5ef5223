// The culling's caster groups (vsm_groups.comp) against their CPU reference, and what they are for:
// every frame of a path, on both raster paths, the group bounds the GPU wrote equal
// vsmCasterGroupsReference over the slot's casters in the culling order bit for bit; the order is a
// permutation with static casters ahead of dynamic ones and those casting no shadow last; some
// (group, map) pairs are refused whole (vsm_pairs); and the culling's workgroups laid out in short rows
// give the same pages as the default rows. That the draws stay the same is `check vsm`'s and the mesh-
// against-vertex comparison's (vsm_meshlets_test.cpp) to show: a refused group's casters are each outside
// the frustum, so the pages match the CPU rasteriser's.
#include "gpu_test_util.h"
#include "vsm_test_util.h"
#include "shadows/virtual/vsm_reference.h"

#include <algorithm>
#include <cstring>

namespace ml::test {
namespace {

void groupsEqualReference(VsmRaster raster) {
    resetValidationCounters();
    const VsmSessionOptions o = vsmSmallDrive(raster);
    auto session = VsmSession::create(o);
    ASSERT_TRUE(session.ok()) << session.error();
    Module& m = *session.value()->module;
    const VirtualShadowMaps& vsm = internals(m).vsm;
    uint64_t tests = 0, refused = 0;
    for (uint32_t f = 0; f < 6; ++f) {
        auto r = session.value()->frame(f);
        ASSERT_TRUE(r.ok()) << r.error();
        const uint32_t slot = internals(m).lastSlot;
        const std::vector<uint32_t>& order = vsm.casterOrder();
        const std::vector<gpu::GpuCaster>& casters = vsm.slotCasters(slot);
        ASSERT_EQ(order.size(), casters.size());
        ASSERT_GT(order.size(), size_t(ML_VSM_CULL_GROUP)) << "the test scene fills more than one group";
        // A permutation: static casters, then dynamic ones, then those casting no shadow.
        std::vector<uint8_t> seen(order.size(), 0);
        uint32_t lastKind = 0;
        for (uint32_t i : order) {
            ASSERT_LT(i, order.size());
            ASSERT_EQ(seen[i], 0) << "caster " << i << " twice in the order";
            seen[i] = 1;
            const uint32_t kind = casters[i].draw.x == 0 ? 2u : casters[i].draw.w != 0 ? 1u : 0u;
            ASSERT_GE(kind, lastKind) << "caster " << i << " out of its kind's place";
            lastKind = kind;
        }
        const std::vector<gpu::GpuCasterGroup> gpuGroups = vsm.readCasterGroups(deviceOf(m), slot);
        const std::vector<gpu::GpuCasterGroup> cpuGroups = vsmCasterGroupsReference(casters, order);
        ASSERT_EQ(gpuGroups.size(), cpuGroups.size());
        for (size_t g = 0; g < cpuGroups.size(); ++g)
            ASSERT_EQ(std::memcmp(&gpuGroups[g], &cpuGroups[g], sizeof(gpu::GpuCasterGroup)), 0)
                << "frame " << f << ": group " << g << " differs (GPU casters " << gpuGroups[g].counts.x
                << ", CPU " << cpuGroups[g].counts.x << ")";
        EXPECT_LE(r->stats.vsm.groupsRefused, r->stats.vsm.groupTests);
        tests += r->stats.vsm.groupTests;
        refused += r->stats.vsm.groupsRefused;
    }
    EXPECT_GT(tests, 0u);
    EXPECT_GT(refused, 0u) << "no (caster group, map) pair refused over " << tests << " tests";
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuVsmGroups, EqualCpuReferenceVertexPath) {
    groupsEqualReference(VsmRaster::Vertex);
}

TEST(GpuVsmGroups, EqualCpuReferenceMeshPath) {
    groupsEqualReference(VsmRaster::Mesh);
}

// The culling's workgroups in rows of 3 (VsmSettings::cullRowWorkgroups) instead of 65535: the pairs span
// many rows, and every frame's page table and valid pages equal those of the default layout bit for bit.
void rowsKeepThePages(VsmRaster raster) {
    resetValidationCounters();
    VsmSessionOptions rows = vsmSmallDrive(raster);
    rows.module.vsm.cullRowWorkgroups = 3;
    auto a = VsmSession::create(vsmSmallDrive(raster));
    auto b = VsmSession::create(rows);
    ASSERT_TRUE(a.ok()) << a.error();
    ASSERT_TRUE(b.ok()) << b.error();
    uint32_t mostPairs = 0;
    for (uint32_t f = 0; f < 4; ++f) {
        auto ra = a.value()->frame(f);
        auto rb = b.value()->frame(f);
        ASSERT_TRUE(ra.ok() && rb.ok());
        const VsmStats &sa = ra->stats.vsm, &sb = rb->stats.vsm;
        mostPairs = std::max(mostPairs, sb.groupTests - sb.groupsRefused);
        EXPECT_EQ(sa.instancesDrawn, sb.instancesDrawn) << "frame " << f;
        EXPECT_EQ(sa.fragmentsDrawn, sb.fragmentsDrawn) << "frame " << f;
        EXPECT_EQ(sa.meshletsAfterExpansion, sb.meshletsAfterExpansion) << "frame " << f;
        const VirtualShadowMaps& va = internals(*a.value()->module).vsm;
        const VirtualShadowMaps& vb = internals(*b.value()->module).vsm;
        const std::vector<uint32_t> ta = va.read(deviceOf(*a.value()->module), VsmState::Table);
        ASSERT_EQ(ta, vb.read(deviceOf(*b.value()->module), VsmState::Table)) << "frame " << f;
        const std::vector<uint32_t> pa = va.read(deviceOf(*a.value()->module), VsmState::PagePool);
        const std::vector<uint32_t> pb = vb.read(deviceOf(*b.value()->module), VsmState::PagePool);
        const size_t page = size_t(va.settings().pageSize) * va.settings().pageSize;
        for (uint32_t w : ta) {
            if (!(w & ML_VSM_ALLOCATED) || !(w & ML_VSM_VALID)) continue;
            const size_t first = size_t(w & ML_VSM_PHYS_MASK) * page;
            ASSERT_TRUE(std::equal(pa.begin() + first, pa.begin() + first + page, pb.begin() + first))
                << "frame " << f << ": page " << (w & ML_VSM_PHYS_MASK) << " differs";
        }
    }
    EXPECT_GT(mostPairs, 6u) << "the pairs fit in two rows of 3: the test crosses no row";
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuVsmGroups, RowsOfThreeKeepThePagesVertexPath) {
    rowsKeepThePages(VsmRaster::Vertex);
}

TEST(GpuVsmGroups, RowsOfThreeKeepThePagesMeshPath) {
    rowsKeepThePages(VsmRaster::Mesh);
}

} // namespace
} // namespace ml::test
