// Named bindings in the module's frame: with the binding log on (gpu/bindings.h), a frame of the night
// city records what each named bind placed, and each binding of the G-buffer draw and of the culling,
// evaluation, statistics and view passes must hold the buffer or image meant for it, taken from the
// module's own state (the cluster lists, the slot's buffers, the targets). Two buffers of one kind traded
// at a call site pass every type check, and fail here. A binding left out aborts the dispatch naming the
// program and the binding's number, one named twice naming the constant (both checked against the real
// evaluation program).
#include "gpu_test_util.h"

#include "culling/culling_bindings.h"
#include "gpu/bindings.h"
#include "lights/evaluate_bindings.h"

#include "evaluate.comp.spv.h"

#include <map>
#include <set>

namespace ml::test {
namespace {

// What a binding must hold: a buffer or an image view.
struct Meant {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    Meant(const Buffer& b) : buffer(b.buffer) {}
    Meant(VkImageView v) : view(v) {}
};
using Expected = std::map<std::string, Meant>; // binding constant's name -> resource

// The first binding of `program`'s binds in `log` that does not hold what `expected` names, or that
// `expected` does not list; "" when every bind of it matches. Fails when the program was never bound.
std::string checkBinds(const std::vector<BoundName>& log, const std::string& program,
                       const Expected& expected) {
    size_t binds = 0;
    for (const BoundName& b : log) {
        if (b.program != program) continue;
        ++binds;
        auto it = expected.find(b.binding);
        if (it == expected.end()) return program + ": " + b.binding + " is not in the test's table";
        const Meant& m = it->second;
        if (m.buffer ? b.descriptor.buffer != m.buffer : b.descriptor.view != m.view)
            return program + ": " + b.binding + " holds another resource";
    }
    if (!binds) return program + ": never bound";
    return {};
}

// The programs bound in the log, by name.
std::set<std::string> programsIn(const std::vector<BoundName>& log) {
    std::set<std::string> names;
    for (const BoundName& b : log) names.insert(b.program);
    return names;
}

struct LoggedFrame {
    std::unique_ptr<Module> module;
    std::vector<BoundName> log;
};

// One 160x90 frame of the night city (24 lights) with the binding log on.
LoggedFrame logFrame(CullingMode mode, DebugView view = DebugView::Shaded) {
    LoggedFrame f;
    f.module = makeModule(mode);
    auto scene = loadScene("night-city", 24, 7);
    EXPECT_TRUE(scene.ok()) << scene.error();
    auto bound = bindScene(*f.module, scene.value());
    EXPECT_TRUE(bound.ok()) << bound.error();
    f.module->setView(view);
    EXPECT_TRUE(f.module->createTargets(160, 90).ok());
    setBindingLog(&f.log);
    renderFrame(*f.module);
    setBindingLog(nullptr);
    return f;
}

// The evaluation's program name: the wave build where the device has subgroup arithmetic.
std::string evaluateProgram(const std::vector<BoundName>& log) {
    const auto names = programsIn(log);
    return names.count("spv_evaluate_wave_comp") ? "spv_evaluate_wave_comp" : "spv_evaluate_comp";
}

} // namespace

TEST(NamedBindings, EvaluationAndStatisticsBindEachInputAtItsName) {
    LoggedFrame f = logFrame(CullingMode::Clustered);
    Module::Impl& m = internals(*f.module);
    const Module::Impl::Slot& s = m.slots[m.lastSlot];
    const Expected evaluate = {
        {"ML_HOST_FRAME", s.frame},
        {"ML_HOST_SLICES", s.slices},
        {"ML_HOST_LIGHTS", s.lights},
        {"ML_HOST_RANGES", m.cull.ranges},
        {"ML_HOST_POOL", m.cull.pool},
        {"ML_HOST_STATIC_WORDS", m.staticWords},
        {"ML_HOST_SHADOW_RECORDS", s.shadowRecords},
        // VSM off: the frame constants and the static words fill its bindings (never read).
        {"ML_HOST_VSM_CONST", s.frame},
        {"ML_HOST_VSM_MAPS", m.staticWords},
        {"ML_HOST_VSM_COVERAGE", m.staticWords},
        {"ML_HOST_VSM_TABLE", m.staticWords},
        {"ML_HOST_VSM_POOL", m.staticWords},
        {"ML_EVAL_DEPTH", m.targets.depth.view},
        {"ML_EVAL_NORMAL", m.targets.normal.view},
        {"ML_EVAL_ALBEDO", m.targets.albedo.view},
        {"ML_EVAL_HDR", m.hdr.view},
        {"ML_EVAL_OUTPUT", m.output.view},
        {"ML_EVAL_MATERIAL", m.targets.albedo.view}, // no material target: the albedo fills it
    };
    EXPECT_EQ(checkBinds(f.log, evaluateProgram(f.log), evaluate), "");
    const Expected statistics = {
        {"ML_STATS_FRAME", s.frame},       {"ML_STATS_SLICES", s.slices},
        {"ML_STATS_LIGHTS", s.lights},     {"ML_STATS_RANGES", m.cull.ranges},
        {"ML_STATS_POOL", m.cull.pool},    {"ML_STATS_DEPTH", m.targets.depth.view},
        {"ML_STATS_COUNTERS", s.counters},
    };
    EXPECT_EQ(checkBinds(f.log, "spv_statistics_comp", statistics), "");

    // The check itself: the ranges and the pool (both storage buffers of uints) traded in the log, as a
    // swapped call site would bind them, are caught, and so is a binding the table does not know.
    std::vector<BoundName> swapped = f.log;
    for (BoundName& b : swapped) {
        if (b.program != evaluateProgram(f.log)) continue;
        if (b.binding == std::string("ML_HOST_RANGES"))
            b.descriptor = Descriptor(m.cull.pool);
        else if (b.binding == std::string("ML_HOST_POOL"))
            b.descriptor = Descriptor(m.cull.ranges);
    }
    EXPECT_EQ(checkBinds(swapped, evaluateProgram(f.log), evaluate),
              evaluateProgram(f.log) + ": ML_HOST_RANGES holds another resource");
    Expected missing = statistics;
    missing.erase("ML_STATS_POOL");
    EXPECT_EQ(checkBinds(f.log, "spv_statistics_comp", missing),
              "spv_statistics_comp: ML_STATS_POOL is not in the test's table");
}

TEST(NamedBindings, ClusteredCullingBindsEachBufferAtItsName) {
    LoggedFrame f = logFrame(CullingMode::Clustered);
    Module::Impl& m = internals(*f.module);
    const Module::Impl::Slot& s = m.slots[m.lastSlot];
    const LightCulling& c = m.cull;
    EXPECT_EQ(checkBinds(f.log, "spv_cluster_bounds_comp",
                         {{"ML_BOUNDS_FRAME", s.frame},
                          {"ML_BOUNDS_SLICES", s.slices},
                          {"ML_BOUNDS_DEPTH", m.targets.depth.view},
                          {"ML_BOUNDS_OUT", c.bounds},
                          {"ML_BOUNDS_COUNTERS", s.counters},
                          {"ML_BOUNDS_TILE_MASKS", c.tileMasks},
                          {"ML_BOUNDS_NORMAL", m.targets.normal.view},
                          {"ML_BOUNDS_RECEIVERS", c.bounds}}), // no receivers wanted: the bounds fill it
              "");
    // The G-buffer draw (a graphics program, bound by name as well) before them.
    EXPECT_EQ(checkBinds(f.log, "spv_gbuffer_vert",
                         {{"ML_GBUFFER_FRAME", s.frame},
                          {"ML_GBUFFER_VERTICES", m.vertexBuffer},
                          {"ML_GBUFFER_INSTANCES", s.instances}}),
              "");
    // Both variants (lanes, and the moon's wide pass) bind the same.
    EXPECT_EQ(checkBinds(f.log, "spv_light_footprint_comp",
                         {{"ML_FOOTPRINT_FRAME", s.frame},
                          {"ML_FOOTPRINT_SLICES", s.slices},
                          {"ML_FOOTPRINT_LIGHTS", s.lights},
                          {"ML_FOOTPRINT_BOUNDS", c.bounds},
                          {"ML_FOOTPRINT_TILE_MASKS", c.tileMasks},
                          {"ML_FOOTPRINT_COUNTS", c.counts},
                          {"ML_FOOTPRINT_HITS", c.hits},
                          {"ML_FOOTPRINT_WORK", c.work},
                          {"ML_FOOTPRINT_WIDE", s.wide},
                          {"ML_FOOTPRINT_TILE_BITS", c.tileBits}}),
              "");
    EXPECT_EQ(checkBinds(f.log, "spv_light_alloc_comp",
                         {{"ML_ALLOC_FRAME", s.frame},
                          {"ML_ALLOC_TILE_MASKS", c.tileMasks},
                          {"ML_ALLOC_COUNTS", c.counts},
                          {"ML_ALLOC_RANGES", c.ranges},
                          {"ML_ALLOC_COUNTERS", s.counters},
                          {"ML_ALLOC_WORK", c.work},
                          {"ML_ALLOC_TILE_BITS", c.tileBits},
                          {"ML_ALLOC_TILE_PREFIX", c.tilePrefix},
                          {"ML_ALLOC_TILE_RANGES", c.tileRanges},
                          {"ML_ALLOC_TILE_SLICES", c.tileSlices}}),
              "");
    // Mark and append: one shader, the same buffers.
    EXPECT_EQ(checkBinds(f.log, "spv_light_fill_comp",
                         {{"ML_FILL_FRAME", s.frame},
                          {"ML_FILL_HITS", c.hits},
                          {"ML_FILL_RANGES", c.ranges},
                          {"ML_FILL_POOL", c.pool},
                          {"ML_FILL_WORK", c.work},
                          {"ML_FILL_TILE_BITS", c.tileBits},
                          {"ML_FILL_TILE_PREFIX", c.tilePrefix},
                          {"ML_FILL_TILE_RANGES", c.tileRanges},
                          {"ML_FILL_TILE_SLICES", c.tileSlices}}),
              "");
}

TEST(NamedBindings, TiledAssignmentAndViewBindEachBufferAtItsName) {
    LoggedFrame f = logFrame(CullingMode::Tiled, DebugView::LightsEvaluated);
    Module::Impl& m = internals(*f.module);
    const Module::Impl::Slot& s = m.slots[m.lastSlot];
    const LightCulling& c = m.cull;
    EXPECT_EQ(checkBinds(f.log, "spv_light_assign_comp",
                         {{"ML_ASSIGN_FRAME", s.frame},
                          {"ML_ASSIGN_LIGHTS", s.lights},
                          {"ML_ASSIGN_BOUNDS", c.bounds},
                          {"ML_ASSIGN_RANGES", c.ranges},
                          {"ML_ASSIGN_POOL", c.pool},
                          {"ML_ASSIGN_COUNTERS", s.counters},
                          {"ML_ASSIGN_WORK", c.work}}),
              "");
    EXPECT_EQ(checkBinds(f.log, "spv_view_lights_comp",
                         {{"ML_VIEW_FRAME", s.frame},
                          {"ML_VIEW_SLICES", s.slices},
                          {"ML_VIEW_LIGHTS", s.lights},
                          {"ML_VIEW_RANGES", c.ranges},
                          {"ML_VIEW_DEPTH", m.targets.depth.view},
                          {"ML_VIEW_OUTPUT", m.output.view},
                          {"ML_VIEW_COUNTS", c.viewCounts}}),
              "");
    // The footprint passes are clustered mode's only.
    EXPECT_EQ(programsIn(f.log).count("spv_light_footprint_comp"), 0u);
}

// The evaluation's constants against its real program (bindings reflected from the SPIR-V): the full
// list places, one left out or named twice is refused with the program's and the binding's names.
TEST(NamedBindings, EvaluationProgramRefusesAMissingOrTwiceNamedBinding) {
    auto module = makeModule();
    Device& d = deviceOf(*module);
    ShaderModule shader = ML_SHADER(d, spv_evaluate_comp);
    Program p = createComputeProgram(d, shader);
    Buffer b = createBuffer(d, 64, kStorageBufferUsage, "test_buffer");
    const Descriptor* ordered[32];
    const VkImageView v = VK_NULL_HANDLE;
#define ML_TEST_EVAL_BUFFERS                                                                                 \
    ML_BIND(ML_HOST_FRAME, b), ML_BIND(ML_HOST_SLICES, b), ML_BIND(ML_HOST_LIGHTS, b),                       \
        ML_BIND(ML_HOST_RANGES, b), ML_BIND(ML_HOST_STATIC_WORDS, b), ML_BIND(ML_HOST_SHADOW_RECORDS, b),    \
        ML_BIND(ML_HOST_VSM_CONST, b), ML_BIND(ML_HOST_VSM_MAPS, b), ML_BIND(ML_HOST_VSM_COVERAGE, b),       \
        ML_BIND(ML_HOST_VSM_TABLE, b), ML_BIND(ML_HOST_VSM_POOL, b), ML_BIND(ML_EVAL_DEPTH, v),              \
        ML_BIND(ML_EVAL_NORMAL, v), ML_BIND(ML_EVAL_ALBEDO, v), ML_BIND(ML_EVAL_HDR, v),                     \
        ML_BIND(ML_EVAL_OUTPUT, v)
    EXPECT_EQ(orderNamedDescriptors(
                  p, {ML_TEST_EVAL_BUFFERS, ML_BIND(ML_HOST_POOL, b), ML_BIND(ML_EVAL_MATERIAL, v)}, ordered),
              "");
    EXPECT_EQ(orderNamedDescriptors(p, {ML_TEST_EVAL_BUFFERS, ML_BIND(ML_EVAL_MATERIAL, v)}, ordered),
              "spv_evaluate_comp: binding 4 is not given");
    EXPECT_EQ(orderNamedDescriptors(p,
                                    {ML_TEST_EVAL_BUFFERS, ML_BIND(ML_HOST_POOL, b),
                                     ML_BIND(ML_EVAL_MATERIAL, v), ML_BIND(ML_HOST_RANGES, b)},
                                    ordered),
              "spv_evaluate_comp: ML_HOST_RANGES (binding 3) is given twice");
#undef ML_TEST_EVAL_BUFFERS
    destroyBuffer(d, b);
    destroyProgram(d, p);
    destroyShader(d, shader);
}

} // namespace ml::test
