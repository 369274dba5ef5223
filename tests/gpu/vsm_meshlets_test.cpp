// The VSM mesh path (vsm_expand.comp, vsm_draw.task, vsm_draw.mesh) against the vertex path, its
// reference: two sessions on the same path and frames, one per raster mode, must hold the same page
// table and, in every allocated and valid page, the same depths bit for bit (allocation does not depend
// on how pages are drawn, so the physical pages match). Also: the culling stages' counters add up, and
// meshIsClosed tells a closed box from an open one.
#include "gpu_test_util.h"
#include "vsm_test_util.h"
#include "shadows/virtual/vsm_meshlets.h"
#include "tests/common/shared_scenes.h"

#include <cstdlib>

namespace ml::test {
namespace {

VsmSessionOptions smallPath(VsmRaster raster, bool caching, bool house) {
    VsmSessionOptions o = vsmSmallDrive(raster);
    if (house) {
        // FZK-Haus: meshes of up to 2,508 triangles (many meshlets each, some closed), static spots.
        o.scene = sharedScenePath("fzk-haus.glb"); // tests/common/shared_scenes.h
        o.path = CameraPath::Orbit;
        o.lights = 12;
        o.width = 160;
        o.height = 90;
    }
    o.module.vsm.caching = caching;
    return o;
}

void comparePaths(bool caching, uint32_t frames, bool house = false) {
    resetValidationCounters();
    auto meshS = VsmSession::create(smallPath(VsmRaster::Mesh, caching, house));
    ASSERT_TRUE(meshS.ok()) << meshS.error();
    auto vertS = VsmSession::create(smallPath(VsmRaster::Vertex, caching, house));
    ASSERT_TRUE(vertS.ok()) << vertS.error();
    Module& mm = *meshS.value()->module;
    Module& vm = *vertS.value()->module;
    const VirtualShadowMaps& mv = internals(mm).vsm;
    const VirtualShadowMaps& vv = internals(vm).vsm;
    ASSERT_TRUE(mv.meshPath());
    ASSERT_FALSE(vv.meshPath());
    const uint32_t page = mv.settings().pageSize * mv.settings().pageSize;
    uint64_t pagesCompared = 0, texelsWritten = 0, total = 0, afterTask = 0, rendered = 0,
             trianglesVertex = 0, taskCulled = 0, trianglesCulled = 0;
    for (uint32_t f = 0; f < frames; ++f) {
        auto rm = meshS.value()->frame(f);
        ASSERT_TRUE(rm.ok()) << rm.error();
        auto rv = vertS.value()->frame(f);
        ASSERT_TRUE(rv.ok()) << rv.error();
        std::vector<uint32_t> tm = mv.read(deviceOf(mm), VsmState::Table),
                              tv = vv.read(deviceOf(vm), VsmState::Table);
        ASSERT_EQ(tm, tv) << "frame " << f << ": page tables differ";
        std::vector<uint32_t> pm = mv.read(deviceOf(mm), VsmState::PagePool),
                              pv = vv.read(deviceOf(vm), VsmState::PagePool);
        for (size_t e = 0; e < tm.size(); ++e) {
            const uint32_t w = tm[e];
            if (!(w & ML_VSM_ALLOCATED) || !(w & ML_VSM_VALID)) continue;
            const size_t first = size_t(w & ML_VSM_PHYS_MASK) * page;
            for (size_t t = first; t < first + page; ++t) {
                ASSERT_EQ(pm[t], pv[t])
                    << "frame " << f << ": entry " << e << " page " << (w & ML_VSM_PHYS_MASK) << " texel "
                    << (t - first) << " (mesh " << pm[t] << ", vertex " << pv[t] << ")";
                texelsWritten += pm[t] != 0xFFFFFFFFu;
            }
            ++pagesCompared;
        }
        const VsmStats& s = rm->stats.vsm;
        EXPECT_TRUE(s.meshPath);
        EXPECT_EQ(s.meshletOverflow, 0u);
        EXPECT_EQ(rv->stats.vsm.drawOverflow, 0u);
        // Every meshlet is counted once at the stage that dropped it, or survives it.
        EXPECT_EQ(s.meshletsTotal, s.meshletsCulledFrustum + s.meshletsCulledHpb + s.meshletsAfterExpansion);
        EXPECT_EQ(s.meshletsAfterExpansion,
                  s.taskCulledFrustum + s.taskCulledCone + s.taskCulledHpb + s.meshletsAfterTask);
        EXPECT_LE(s.trianglesRasterized, s.trianglesAfterTask);
        EXPECT_EQ(s.instancesDrawn, rv->stats.vsm.instancesDrawn) << "frame " << f;
        // Both paths clip each triangle to the same dirty pages (vsm_page_clip.glsl) and cull the back
        // faces of closed casters in front of the near plane (whose fragments never win the minimum): the
        // vertex path in the rasteriser, the mesh path per meshlet (cone) and per triangle, except
        // triangles under 1/16 texel^2, which it keeps. So the same fragments run, give or take those.
        const uint64_t vf = rv->stats.vsm.fragmentsDrawn, slack = vf / 1000 + 64;
        EXPECT_LE(s.fragmentsDrawn, vf + slack) << "frame " << f;
        EXPECT_GE(s.fragmentsDrawn + slack, vf) << "frame " << f;
        EXPECT_EQ(s.pageClipOverflow, 0u);
        if (f + 1 == frames)
            std::printf(
                "frame %u: meshlets total %u, culled expansion frustum %u hpb %u, after expansion %u, task "
                "frustum %u cone %u hpb %u, after task %u, triangles after task %u rasterized %u, pages "
                "rendered %u, compared %llu, non-empty texels %llu\n",
                f, s.meshletsTotal, s.meshletsCulledFrustum, s.meshletsCulledHpb, s.meshletsAfterExpansion,
                s.taskCulledFrustum, s.taskCulledCone, s.taskCulledHpb, s.meshletsAfterTask,
                s.trianglesAfterTask, s.trianglesRasterized, s.pagesRendered,
                (unsigned long long)pagesCompared, (unsigned long long)texelsWritten);
        total += s.meshletsTotal;
        taskCulled += s.taskCulledFrustum + s.taskCulledCone + s.taskCulledHpb;
        trianglesCulled += s.trianglesAfterTask - s.trianglesRasterized;
        afterTask += s.meshletsAfterTask;
        rendered += s.pagesRendered;
        trianglesVertex += s.trianglesRasterized;
    }
    // The path exercises the comparison: pages were drawn, hold casters, and the stages culled work.
    EXPECT_GT(rendered, 0u);
    EXPECT_GT(pagesCompared, 0u);
    EXPECT_GT(texelsWritten, 0u);
    EXPECT_GT(trianglesVertex, 0u);
    EXPECT_LT(afterTask, total);
    if (house) { // the task and mesh shaders' culling ran and still left the pages equal
        EXPECT_GT(taskCulled, 0u);
        EXPECT_GT(trianglesCulled, 0u);
    }
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuVsmMeshlets, MeshPathWritesTheVertexPathsPagesCached) {
    comparePaths(true, 12);
}
TEST(GpuVsmMeshlets, MeshPathWritesTheVertexPathsPagesUncached) {
    comparePaths(false, 4);
}
TEST(GpuVsmMeshlets, MeshPathWritesTheVertexPathsPagesFzkHaus) {
    ML_SKIP_WITHOUT_SHARED();
    comparePaths(true, 4, true);
}
TEST(GpuVsmMeshlets, MeshPathWritesTheVertexPathsPagesFzkHausUncached) {
    ML_SKIP_WITHOUT_SHARED();
    comparePaths(false, 3, true);
}

TEST(VsmMeshlets, ClosedMeshDetection) {
    // A unit cube with per-face vertices (welded by position) and outward counter-clockwise faces.
    std::vector<float> p;
    std::vector<uint32_t> idx;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = 0; sign < 2; ++sign) {
            glm::vec3 n(0.0f);
            n[axis] = sign ? 1.0f : -1.0f;
            glm::vec3 u(0.0f), v(0.0f);
            u[(axis + 1) % 3] = 1.0f;
            v[(axis + 2) % 3] = 1.0f;
            if (!sign) std::swap(u, v);
            const uint32_t base = uint32_t(p.size() / 3);
            for (int k = 0; k < 4; ++k) {
                glm::vec3 q = n * 0.5f + u * ((k & 1) ? 0.5f : -0.5f) + v * ((k & 2) ? 0.5f : -0.5f);
                p.insert(p.end(), {q.x, q.y, q.z});
            }
            idx.insert(idx.end(), {base, base + 1, base + 3, base, base + 3, base + 2});
        }
    const size_t n = p.size() / 3;
    EXPECT_TRUE(meshIsClosed(p.data(), 12, n, idx));
    std::vector<uint32_t> flipped = idx;
    for (size_t t = 0; t < flipped.size(); t += 3) std::swap(flipped[t + 1], flipped[t + 2]);
    EXPECT_FALSE(meshIsClosed(p.data(), 12, n, flipped)); // inward faces
    std::vector<uint32_t> open(idx.begin(), idx.end() - 6);
    EXPECT_FALSE(meshIsClosed(p.data(), 12, n, open)); // one face missing
    MeshletSet set;
    EXPECT_EQ(appendMeshlets(set, p.data(), 12, n, idx, 100), 1u);
    EXPECT_EQ(set.meshlets[0].data.w, 12u);
    EXPECT_EQ(set.meshlets[0].data.z, 24u);
    for (uint32_t v : set.vertices) EXPECT_GE(v, 100u);
}

} // namespace
} // namespace ml::test
