// The VSM per-step timers (manylights/pass_times.h): mark, sort, allocation, HPB, group
// culling, culling (vertex path) or expansion (mesh path) and draw are each a scope of their own, on
// both raster paths and in both timing modes. Fenced timing (lavapipe's: timestamps do not bracket
// compute on a CPU device) submits each scope on its own, so every step that ran has a positive host-
// clock time; the bookkeeping total (PassTimes::vsmBookkeepingMs, stats.json's
// vsm_bookkeeping_gpu_ms_mean) is the sum of the steps mark..expand. The stats.json / frames.csv side is
// CliVsmStepTimers (tests/cli/vsm_steps_check.py).
#include "gpu_test_util.h"
#include "vsm_test_util.h"

namespace ml::test {
namespace {

constexpr Pass kSteps[] = {Pass::VsmMark,      Pass::VsmSort, Pass::VsmAlloc,  Pass::VsmHpb,
                           Pass::VsmGroupCull, Pass::VsmCull, Pass::VsmExpand, Pass::VsmDraw};

void stepsTimedApart(VsmRaster raster, TimingChoice timing) {
    resetValidationCounters();
    VsmSessionOptions o = vsmSmallDrive(raster);
    o.module.timing = timing;
    auto session = VsmSession::create(o);
    ASSERT_TRUE(session.ok()) << session.error();
    const bool mesh = raster == VsmRaster::Mesh;
    for (uint32_t f = 0; f < 3; ++f) {
        auto r = session.value()->frame(f);
        ASSERT_TRUE(r.ok()) << r.error();
        const PassTimes& t = r->times;
        double bookkeeping = 0;
        for (Pass p : kSteps) {
            const uint32_t i = uint32_t(p);
            // The culling step is the raster path's own: vsm_cull draws lists, vsm_expand meshlet lists.
            const bool expected = p == Pass::VsmCull ? !mesh : p == Pass::VsmExpand ? mesh : true;
            ASSERT_EQ(t.ran[i], expected) << "frame " << f << ": " << passName(p);
            if (!t.ran[i]) continue;
            EXPECT_GE(t.ms[i], 0.0) << "frame " << f << ": " << passName(p);
            // Fenced: the scope's own submission, timed from submit to completion (never 0 ms).
            if (timing == TimingChoice::Fenced) {
                EXPECT_GT(t.ms[i], 0.0) << "frame " << f << ": " << passName(p) << " not timed on its own";
            }
            if (vsmBookkeeping(p)) bookkeeping += t.ms[i];
        }
        EXPECT_FALSE(vsmBookkeeping(Pass::VsmDraw)) << "the page draws are not bookkeeping";
        EXPECT_NEAR(t.vsmBookkeepingMs(), bookkeeping, 1e-9) << "frame " << f;
        EXPECT_GT(t.totalMs(), t.vsmBookkeepingMs())
            << "frame " << f << ": the frame's total holds the steps";
    }
    EXPECT_EQ(validationErrors(), 0u);
}

TEST(GpuVsmTimers, StepsTimedApartFencedVertexPath) {
    stepsTimedApart(VsmRaster::Vertex, TimingChoice::Fenced);
}
TEST(GpuVsmTimers, StepsTimedApartFencedMeshPath) {
    stepsTimedApart(VsmRaster::Mesh, TimingChoice::Fenced);
}
// Timestamps (GPUs): the same scopes between timestamp pairs in one command buffer.
TEST(GpuVsmTimers, StepsTimedApartTimestamps) {
    stepsTimedApart(VsmRaster::Vertex, TimingChoice::Timestamps);
}

} // namespace
} // namespace ml::test
