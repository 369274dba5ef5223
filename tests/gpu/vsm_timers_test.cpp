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

constexpr const char* kSteps[] = {"vsm_mark",       "vsm_sort", "vsm_alloc",  "vsm_hpb",
                                  "vsm_group_cull", "vsm_cull", "vsm_expand", "vsm_draw"};

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
        for (const char* p : kSteps) {
            const std::string_view name = p;
            // The culling step is the raster path's own: vsm_cull draws lists, vsm_expand meshlet lists.
            const bool expected = name == "vsm_cull" ? !mesh : name == "vsm_expand" ? mesh : true;
            ASSERT_EQ(t.ran(p), expected) << "frame " << f << ": " << p;
            if (!t.ran(p)) continue;
            EXPECT_GE(t.ms(p), 0.0) << "frame " << f << ": " << p;
            // Fenced: the scope's own submission, timed from submit to completion (never 0 ms).
            if (timing == TimingChoice::Fenced) {
                EXPECT_GT(t.ms(p), 0.0) << "frame " << f << ": " << p << " not timed on its own";
            }
            // Every step but the page draws is bookkeeping.
            EXPECT_EQ(t.find(p)->group, name == "vsm_draw" ? "" : kVsmBookkeeping)
                << "frame " << f << ": " << p;
            if (name != "vsm_draw") bookkeeping += t.ms(p);
        }
        EXPECT_EQ(t.find("vsm_draw")->group, "") << "the page draws are not bookkeeping";
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
