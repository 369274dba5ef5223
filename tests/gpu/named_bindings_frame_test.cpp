// Named bindings in the module's frame: with the binding log on (gpu/bindings.h), a frame of the night
// city records what each named bind placed, and each binding of the G-buffer draw and of the culling,
// evaluation, statistics and view passes, and of every virtual shadow map pass (both raster paths), must
// hold the buffer or image meant for it, taken from the module's own state (the cluster lists, the slot's
// buffers, the VSM's pages and slot, the targets). Two buffers of one kind traded
// at a call site pass every type check, and fail here. A binding left out aborts the dispatch naming the
// program and the binding's number, one named twice naming the constant (both checked against the real
// evaluation program and a VSM program).
#include "gpu_test_util.h"
#include "vsm_test_util.h"

#include "culling/culling_bindings.h"
#include "gpu/bindings.h"
#include "lights/evaluate_bindings.h"
#include "shadows/virtual/vsm_bindings.h"

#include "evaluate.comp.spv.h"
#include "vsm_cull.comp.spv.h"
#include "vsm_mark.comp.spv.h"

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
    // The wave build where the device has subgroup arithmetic; both bind the same.
    EXPECT_EQ(checkBinds(f.log, c.waveBounds() ? "spv_cluster_bounds_wave_comp" : "spv_cluster_bounds_comp",
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
              "spv_evaluate_comp: binding 4 is not given (between ML_HOST_RANGES at 3 and "
              "ML_HOST_STATIC_WORDS at 5)");
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

namespace {

// checkBinds, and every binding `expected` names was bound at least once (a table that lists a binding
// the program does not have, or a pass that never binds one, fails).
std::string checkAllBinds(const std::vector<BoundName>& log, const std::string& program,
                          const Expected& expected) {
    std::string error = checkBinds(log, program, expected);
    if (!error.empty()) return error;
    std::set<std::string> bound;
    for (const BoundName& b : log)
        if (b.program == program) bound.insert(b.binding);
    for (const auto& [name, meant] : expected)
        if (!bound.count(name)) return program + ": " + name + " was never bound";
    return {};
}

struct LoggedVsmFrame {
    std::unique_ptr<VsmSession> session;
    std::vector<BoundName> log;
};

// The second frame of the small drive (VSM on, the probe and the VSM debug view on) with the binding
// log on. shortList: ML_VSM_ALLOC_SHORT_LIST for the session ("": the device's limit; "0": the
// multi-dispatch allocation alone, which binds vsm_list).
LoggedVsmFrame logVsmFrame(VsmRaster raster, bool clusterMarking, const char* shortList) {
    LoggedVsmFrame f;
    VsmSessionOptions o = vsmSmallDrive(raster);
    o.module.vsm.probeCapacity = 64;
    o.module.vsm.clusterMarking = clusterMarking;
    if (*shortList) setenv("ML_VSM_ALLOC_SHORT_LIST", shortList, 1);
    auto session = VsmSession::create(o);
    unsetenv("ML_VSM_ALLOC_SHORT_LIST");
    EXPECT_TRUE(session.ok()) << session.error();
    if (!session.ok()) return f;
    f.session = std::move(session.value());
    f.session->module->setView(DebugView::Vsm);
    auto first = f.session->frame(0);
    EXPECT_TRUE(first.ok()) << first.error();
    setBindingLog(&f.log);
    auto second = f.session->frame(1);
    setBindingLog(nullptr);
    EXPECT_TRUE(second.ok()) << second.error();
    return f;
}

// Every VSM program the frame bound against the resources meant for each of its bindings.
void vsmPassesBindEachResourceAtItsName(VsmRaster raster, bool clusterMarking, const char* shortList) {
    resetValidationCounters();
    LoggedVsmFrame f = logVsmFrame(raster, clusterMarking, shortList);
    ASSERT_TRUE(f.session);
    Module::Impl& m = internals(*f.session->module);
    const Module::Impl::Slot& s = m.slots[m.lastSlot];
    const VirtualShadowMaps& vsm = m.vsm;
    ASSERT_TRUE(vsm.active(m.lastSlot)) << "the frame has active maps";
    const VsmSlot& sl = vsm.slot(m.lastSlot);
    const VsmPages& pg = vsm.pages();
    const LightCulling& c = m.cull;
    const std::set<std::string> programs = programsIn(f.log);

    // Marking: per pixel, or per cluster with the receivers and tile masks.
    Expected mark = {
        {"ML_VSM_MARK_FRAME", s.frame},
        {"ML_VSM_MARK_SLICES", s.slices},
        {"ML_VSM_MARK_LIGHTS", s.lights},
        {"ML_VSM_MARK_RANGES", c.ranges},
        {"ML_VSM_MARK_LIGHT_POOL", c.pool},
        {"ML_VSM_MARK_DEPTH", m.targets.depth.view},
        {"ML_VSM_MARK_NORMAL", m.targets.normal.view},
        {"ML_VSM_MARK_CONSTANTS", sl.constants},
        {"ML_VSM_MARK_MAPS", sl.maps},
        {"ML_VSM_MARK_COVERAGE", sl.coverage},
        {"ML_VSM_MARK_MARKS", pg.marks},
        {"ML_VSM_MARK_COUNTERS", sl.counters},
        {"ML_VSM_MARK_RANK_BASE", sl.rankBase},
        {"ML_VSM_MARK_REQUESTS", pg.list[0]},
    };
    if (clusterMarking) {
        EXPECT_EQ(programs.count("spv_vsm_mark_comp"), 0u);
        mark.insert({"ML_VSM_MARK_RECEIVERS", c.receivers});
        mark.insert({"ML_VSM_MARK_TILE_MASKS", c.tileMasks});
        EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_mark_cluster_comp", mark), "");
    } else {
        EXPECT_EQ(programs.count("spv_vsm_mark_cluster_comp"), 0u);
        EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_mark_comp", mark), "");
    }

    // Closing the list: in one workgroup where the device allows it, else vsm_list.
    if (m.vsmPasses.shortListLimit() != 0) {
        EXPECT_EQ(programs.count("spv_vsm_list_comp"), 0u);
        EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_allocate_short_list_comp",
                                {{"ML_VSM_SHORT_CONSTANTS", sl.constants},
                                 {"ML_VSM_SHORT_RUNS", sl.runs},
                                 {"ML_VSM_SHORT_COUNTERS", sl.counters},
                                 {"ML_VSM_SHORT_REQUESTS", pg.list[0]},
                                 {"ML_VSM_SHORT_SORTED", pg.list[1]},
                                 {"ML_VSM_SHORT_SORT_ARGS", pg.sortArgs},
                                 {"ML_VSM_SHORT_MAPS", sl.maps},
                                 {"ML_VSM_SHORT_STALE", sl.stale},
                                 {"ML_VSM_SHORT_TABLE", pg.table},
                                 {"ML_VSM_SHORT_MARKS", pg.marks},
                                 {"ML_VSM_SHORT_OWNERS", pg.owners},
                                 {"ML_VSM_SHORT_LAST_USED", pg.lastUsed},
                                 {"ML_VSM_SHORT_AVAIL", pg.avail},
                                 {"ML_VSM_SHORT_RENDERED", pg.rendered},
                                 {"ML_VSM_SHORT_DIRTY_MIPS", pg.dirtyMips},
                                 {"ML_VSM_SHORT_DIRTY_MAPS", pg.dirtyMaps},
                                 {"ML_VSM_SHORT_HPB", pg.hpb}}),
                  "");
    } else {
        EXPECT_EQ(programs.count("spv_vsm_allocate_short_list_comp"), 0u);
        EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_list_comp",
                                {{"ML_VSM_LIST_CONSTANTS", sl.constants},
                                 {"ML_VSM_LIST_COUNTERS", sl.counters},
                                 {"ML_VSM_LIST_SORT_ARGS", pg.sortArgs},
                                 {"ML_VSM_LIST_OWNERS", pg.owners}}),
                  "");
    }

    // The sort passes alternate their buffers: pass k reads list[k % 2] and writes the other.
    uint32_t sortBinds = 0;
    for (const BoundName& b : f.log) {
        if (b.program != "spv_vsm_sort_comp") continue;
        const uint32_t pass = sortBinds++ / 3;
        const std::string name = b.binding;
        const Buffer& meant = name == "ML_VSM_SORT_COUNTERS" ? sl.counters
                              : name == "ML_VSM_SORT_SRC"    ? pg.list[pass % 2]
                                                             : pg.list[(pass + 1) % 2];
        EXPECT_TRUE(name == "ML_VSM_SORT_COUNTERS" || name == "ML_VSM_SORT_SRC" || name == "ML_VSM_SORT_DST")
            << name;
        EXPECT_EQ(b.descriptor.buffer, meant.buffer) << "sort pass " << pass << ": " << name;
    }
    EXPECT_EQ(sortBinds, 3 * (pg.mergePasses + 1));

    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_scan_comp",
                            {{"ML_VSM_SCAN_CONSTANTS", sl.constants},
                             {"ML_VSM_SCAN_RUNS", sl.runs},
                             {"ML_VSM_SCAN_COUNTERS", sl.counters},
                             {"ML_VSM_SCAN_LIST_A", pg.list[0]},
                             {"ML_VSM_SCAN_TABLE", pg.table},
                             {"ML_VSM_SCAN_MARKS", pg.marks},
                             {"ML_VSM_SCAN_LAST_USED", pg.lastUsed},
                             {"ML_VSM_SCAN_BLOCK_COUNTS", pg.blockCounts},
                             {"ML_VSM_SCAN_LIST_B", pg.list[1]},
                             {"ML_VSM_SCAN_SORT_ARGS", pg.sortArgs},
                             {"ML_VSM_SCAN_MAPS", sl.maps},
                             {"ML_VSM_SCAN_STALE", sl.stale},
                             {"ML_VSM_SCAN_OWNERS", pg.owners},
                             {"ML_VSM_SCAN_CLASS_COUNTS", pg.classCounts}}),
              "");
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_alloc_comp",
                            {{"ML_VSM_ALLOC_CONSTANTS", sl.constants},
                             {"ML_VSM_ALLOC_COUNTERS", sl.counters},
                             {"ML_VSM_ALLOC_BLOCK_COUNTS", pg.blockCounts},
                             {"ML_VSM_ALLOC_CLASS_COUNTS", pg.classCounts},
                             {"ML_VSM_ALLOC_SORT_ARGS", pg.sortArgs}}),
              "");
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_avail_comp",
                            {{"ML_VSM_AVAIL_CONSTANTS", sl.constants},
                             {"ML_VSM_AVAIL_MARKS", pg.marks},
                             {"ML_VSM_AVAIL_OWNERS", pg.owners},
                             {"ML_VSM_AVAIL_LAST_USED", pg.lastUsed},
                             {"ML_VSM_AVAIL_CLASS_BASES", pg.classCounts},
                             {"ML_VSM_AVAIL_AVAIL", pg.avail},
                             {"ML_VSM_AVAIL_COUNTERS", sl.counters}}),
              "");
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_assign_comp",
                            {{"ML_VSM_ASSIGN_CONSTANTS", sl.constants},
                             {"ML_VSM_ASSIGN_RUNS", sl.runs},
                             {"ML_VSM_ASSIGN_COUNTERS", sl.counters},
                             {"ML_VSM_ASSIGN_LIST_A", pg.list[0]},
                             {"ML_VSM_ASSIGN_TABLE", pg.table},
                             {"ML_VSM_ASSIGN_MARKS", pg.marks},
                             {"ML_VSM_ASSIGN_OWNERS", pg.owners},
                             {"ML_VSM_ASSIGN_LAST_USED", pg.lastUsed},
                             {"ML_VSM_ASSIGN_BLOCK_RANKS", pg.blockCounts},
                             {"ML_VSM_ASSIGN_AVAIL", pg.avail},
                             {"ML_VSM_ASSIGN_RENDERED", pg.rendered},
                             {"ML_VSM_ASSIGN_DIRTY_MIPS", pg.dirtyMips},
                             {"ML_VSM_ASSIGN_DIRTY_MAPS", pg.dirtyMaps},
                             {"ML_VSM_ASSIGN_LIST_B", pg.list[1]},
                             {"ML_VSM_ASSIGN_SORT_ARGS", pg.sortArgs}}),
              "");
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_hpb_comp",
                            {{"ML_VSM_HPB_CONSTANTS", sl.constants},
                             {"ML_VSM_HPB_RUNS", sl.runs},
                             {"ML_VSM_HPB_COUNTERS", sl.counters},
                             {"ML_VSM_HPB_LIST_A", pg.list[0]},
                             {"ML_VSM_HPB_TABLE", pg.table},
                             {"ML_VSM_HPB_MARKS", pg.marks},
                             {"ML_VSM_HPB_HPB", pg.hpb},
                             {"ML_VSM_HPB_LIST_B", pg.list[1]},
                             {"ML_VSM_HPB_SORT_ARGS", pg.sortArgs}}),
              "");
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_groups_comp",
                            {{"ML_VSM_GROUPS_CASTERS", sl.casters},
                             {"ML_VSM_GROUPS_ORDER", sl.casterOrder},
                             {"ML_VSM_GROUPS_GROUPS", sl.casterGroups}}),
              "");
    // Both of vsm_pairs' dispatches (the pair tests and the closing thread).
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_pairs_comp",
                            {{"ML_VSM_PAIRS_CONSTANTS", sl.constants},
                             {"ML_VSM_PAIRS_MAPS", sl.maps},
                             {"ML_VSM_PAIRS_DIRTY_MAPS", pg.dirtyMaps},
                             {"ML_VSM_PAIRS_DIRTY_MIPS", pg.dirtyMips},
                             {"ML_VSM_PAIRS_GROUPS", sl.casterGroups},
                             {"ML_VSM_PAIRS_PAIRS", sl.cullPairs},
                             {"ML_VSM_PAIRS_COUNTERS", sl.counters}}),
              "");
    EXPECT_EQ(vsm.meshPath(), raster == VsmRaster::Mesh) << "the device runs the raster path asked for";
    if (vsm.meshPath()) {
        EXPECT_EQ(programs.count("spv_vsm_cull_comp"), 0u);
        EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_expand_comp",
                                {{"ML_VSM_EXPAND_CONSTANTS", sl.constants},
                                 {"ML_VSM_EXPAND_MAPS", sl.maps},
                                 {"ML_VSM_EXPAND_PAIRS", sl.cullPairs},
                                 {"ML_VSM_EXPAND_TABLE", pg.table},
                                 {"ML_VSM_EXPAND_HPB", pg.hpb},
                                 {"ML_VSM_EXPAND_CASTERS", sl.casters},
                                 {"ML_VSM_EXPAND_DIRTY_MIPS", pg.dirtyMips},
                                 {"ML_VSM_EXPAND_MESHLET_LIST", pg.meshletList},
                                 {"ML_VSM_EXPAND_MESH_TASKS", pg.meshTasks},
                                 {"ML_VSM_EXPAND_COUNTERS", sl.counters},
                                 {"ML_VSM_EXPAND_ORDER", sl.casterOrder}}),
                  "");
        EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_draw_task",
                                {{"ML_VSM_DRAW_VERTICES", m.vertexBuffer},
                                 {"ML_VSM_DRAW_INSTANCES", s.instances},
                                 {"ML_VSM_DRAW_MESHLET_LIST", pg.meshletList},
                                 {"ML_VSM_DRAW_MAPS", sl.maps},
                                 {"ML_VSM_DRAW_CONSTANTS", sl.constants},
                                 {"ML_VSM_DRAW_TABLE", pg.table},
                                 {"ML_VSM_DRAW_PAGE_POOL", pg.pool},
                                 {"ML_VSM_DRAW_COUNTERS", sl.counters},
                                 {"ML_VSM_DRAW_MESHLET_VERTICES", m.meshletVertexBuffer},
                                 {"ML_VSM_DRAW_MESHLET_TRIANGLES", m.meshletTriangleBuffer},
                                 {"ML_VSM_DRAW_HPB", pg.hpb},
                                 {"ML_VSM_DRAW_MESH_TASKS", pg.meshTasks},
                                 {"ML_VSM_DRAW_MESHLETS", m.meshletBuffer}}),
                  "");
    } else {
        EXPECT_EQ(programs.count("spv_vsm_expand_comp"), 0u);
        EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_cull_comp",
                                {{"ML_VSM_CULL_CONSTANTS", sl.constants},
                                 {"ML_VSM_CULL_MAPS", sl.maps},
                                 {"ML_VSM_CULL_PAIRS", sl.cullPairs},
                                 {"ML_VSM_CULL_TABLE", pg.table},
                                 {"ML_VSM_CULL_HPB", pg.hpb},
                                 {"ML_VSM_CULL_CASTERS", sl.casters},
                                 {"ML_VSM_CULL_DIRTY_MIPS", pg.dirtyMips},
                                 {"ML_VSM_CULL_DRAWS", pg.draws},
                                 {"ML_VSM_CULL_DRAW_INFO", pg.drawInfo},
                                 {"ML_VSM_CULL_DRAW_COUNTS", pg.drawCounts},
                                 {"ML_VSM_CULL_COUNTERS", sl.counters},
                                 {"ML_VSM_CULL_ORDER", sl.casterOrder}}),
                  "");
        // Both draw programs (closed casters with back faces culled, then open ones).
        EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_draw_vert",
                                {{"ML_VSM_DRAW_VERTICES", m.vertexBuffer},
                                 {"ML_VSM_DRAW_INSTANCES", s.instances},
                                 {"ML_VSM_DRAW_DRAW_INFO", pg.drawInfo},
                                 {"ML_VSM_DRAW_MAPS", sl.maps},
                                 {"ML_VSM_DRAW_CONSTANTS", sl.constants},
                                 {"ML_VSM_DRAW_TABLE", pg.table},
                                 {"ML_VSM_DRAW_PAGE_POOL", pg.pool},
                                 {"ML_VSM_DRAW_COUNTERS", sl.counters}}),
                  "");
    }
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_clear_comp",
                            {{"ML_VSM_CLEAR_CONSTANTS", sl.constants},
                             {"ML_VSM_CLEAR_RENDERED", pg.rendered},
                             {"ML_VSM_CLEAR_PAGE_POOL", pg.pool}}),
              "");
    // The static layer and caching are on by default: the merge runs after the draws.
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_merge_comp",
                            {{"ML_VSM_MERGE_CONSTANTS", sl.constants},
                             {"ML_VSM_MERGE_RENDERED", pg.rendered},
                             {"ML_VSM_MERGE_PAGE_POOL", pg.pool}}),
              "");
    // After the evaluation: the probe and the debug view.
    Expected lookup = {
        {"FRAME", s.frame},
        {"SLICES", s.slices},
        {"LIGHTS", s.lights},
        {"RANGES", c.ranges},
        {"LIGHT_POOL", c.pool},
        {"DEPTH", m.targets.depth.view},
        {"NORMAL", m.targets.normal.view},
        {"CONSTANTS", sl.constants},
        {"MAPS", sl.maps},
        {"COVERAGE", sl.coverage},
        {"TABLE", pg.table},
        {"PAGE_POOL", pg.pool},
    };
    Expected probe, view;
    for (const auto& [name, meant] : lookup) {
        probe.insert({"ML_VSM_PROBE_" + name, meant});
        view.insert({"ML_VSM_VIEW_" + name, meant});
    }
    probe.insert({"ML_VSM_PROBE_PROBES", sl.probes});
    view.insert({"ML_VSM_VIEW_OUTPUT", m.output.view});
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_probe_comp", probe), "");
    EXPECT_EQ(checkAllBinds(f.log, "spv_vsm_view_comp", view), "");
    EXPECT_EQ(validationErrors(), 0u);
}

} // namespace

TEST(NamedBindings, VsmVertexPathBindsEachResourceAtItsName) {
    vsmPassesBindEachResourceAtItsName(VsmRaster::Vertex, false, "");
}

// The mesh path, marking per cluster, and the multi-dispatch allocation (vsm_list) alone.
TEST(NamedBindings, VsmMeshPathClusterMarkingBindsEachResourceAtItsName) {
    vsmPassesBindEachResourceAtItsName(VsmRaster::Mesh, true, "0");
}

// A VSM program's real bindings (reflected from its SPIR-V): its full list places, one left out is
// refused naming the constants on either side, one named twice naming the constant, and the cluster
// variant's bindings are past the per-pixel mark's.
TEST(NamedBindings, VsmProgramsRefuseAMissingTwiceOrPastBinding) {
    auto module = makeModule();
    Device& d = deviceOf(*module);
    ShaderModule cullShader = ML_SHADER(d, spv_vsm_cull_comp);
    ShaderModule markShader = ML_SHADER(d, spv_vsm_mark_comp);
    Program cull = createComputeProgram(d, cullShader);
    Program mark = createComputeProgram(d, markShader);
    Buffer b = createBuffer(d, 64, kStorageBufferUsage, "test_buffer");
    const Descriptor* ordered[32];
#define ML_TEST_CULL_BUFFERS                                                                                 \
    ML_BIND(ML_VSM_CULL_CONSTANTS, b), ML_BIND(ML_VSM_CULL_MAPS, b), ML_BIND(ML_VSM_CULL_PAIRS, b),          \
        ML_BIND(ML_VSM_CULL_TABLE, b), ML_BIND(ML_VSM_CULL_HPB, b), ML_BIND(ML_VSM_CULL_CASTERS, b),         \
        ML_BIND(ML_VSM_CULL_DIRTY_MIPS, b), ML_BIND(ML_VSM_CULL_DRAWS, b),                                   \
        ML_BIND(ML_VSM_CULL_DRAW_COUNTS, b), ML_BIND(ML_VSM_CULL_COUNTERS, b), ML_BIND(ML_VSM_CULL_ORDER, b)
    EXPECT_EQ(orderNamedDescriptors(cull, {ML_TEST_CULL_BUFFERS, ML_BIND(ML_VSM_CULL_DRAW_INFO, b)}, ordered),
              "");
    EXPECT_EQ(orderNamedDescriptors(cull, {ML_TEST_CULL_BUFFERS}, ordered),
              "spv_vsm_cull_comp: binding 8 is not given (between ML_VSM_CULL_DRAWS at 7 and "
              "ML_VSM_CULL_DRAW_COUNTS at 9)");
    EXPECT_EQ(orderNamedDescriptors(cull, {ML_TEST_CULL_BUFFERS, ML_BIND(ML_VSM_CULL_DRAWS, b)}, ordered),
              "spv_vsm_cull_comp: ML_VSM_CULL_DRAWS (binding 7) is given twice");
#undef ML_TEST_CULL_BUFFERS
    EXPECT_EQ(orderNamedDescriptors(mark, {ML_BIND(ML_VSM_MARK_TILE_MASKS, b)}, ordered),
              "spv_vsm_mark_comp: ML_VSM_MARK_TILE_MASKS (binding 15) is past the shader's 14 bindings");
    destroyBuffer(d, b);
    destroyProgram(d, mark);
    destroyProgram(d, cull);
    destroyShader(d, markShader);
    destroyShader(d, cullShader);
}

} // namespace ml::test
