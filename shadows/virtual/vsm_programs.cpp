#include "shadows/virtual/vsm_programs.h"

#include "vsm_alloc.comp.spv.h"
#include "vsm_allocate_short_list.comp.spv.h"
#include "vsm_assign.comp.spv.h"
#include "vsm_avail.comp.spv.h"
#include "vsm_clear.comp.spv.h"
#include "vsm_cull.comp.spv.h"
#include "vsm_draw.frag.spv.h"
#include "vsm_draw.mesh.spv.h"
#include "vsm_draw.task.spv.h"
#include "vsm_draw.vert.spv.h"
#include "vsm_expand.comp.spv.h"
#include "vsm_groups.comp.spv.h"
#include "vsm_hpb.comp.spv.h"
#include "vsm_list.comp.spv.h"
#include "vsm_mark.comp.spv.h"
#include "vsm_mark_cluster.comp.spv.h"
#include "vsm_merge.comp.spv.h"
#include "vsm_pairs.comp.spv.h"
#include "vsm_probe.comp.spv.h"
#include "vsm_scan.comp.spv.h"
#include "vsm_sort.comp.spv.h"
#include "vsm_view.comp.spv.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ml {

namespace {
// The mark passes' profiling stage (the kStage of vsm_mark.comp and of vsm_mark_cluster.comp, whichever
// the frame runs): ML_VSM_MARK_STAGE=1..5 stops the pass early to time its parts
// (tools/vsm_mark_stages.py); those frames mark nothing. Anything but 0-5 is refused.
Result<uint32_t> markStage() {
    const char* env = std::getenv("ML_VSM_MARK_STAGE");
    if (!env || !*env) return 0u;
    if (std::strlen(env) != 1 || env[0] < '0' || env[0] > '5')
        return fail("ML_VSM_MARK_STAGE must be one digit 0-5 (vsm_mark.comp's profiling stages)");
    const uint32_t stage = uint32_t(env[0] - '0');
    if (stage != 0)
        std::fprintf(stderr,
                     "vsm_mark: profiling stage %u (ML_VSM_MARK_STAGE): no pages are marked, "
                     "shadows are wrong\n",
                     stage);
    return stage;
}

// Winding of a triangle that faces the light in the page framebuffer (the light's projection, Vulkan's
// y-down viewport): checked by `check vsm`, whose reference rasteriser draws both faces.
constexpr VkFrontFace kVsmFrontFace = VK_FRONT_FACE_CLOCKWISE;
} // namespace

Result<void> VsmPrograms::create(const Device& d, bool meshPath) {
    // Each shader is kept (shaders_, destroyed with the programs) as soon as it exists.
    auto load = [&](const uint32_t* code, size_t bytes, const char* name) -> Result<const ShaderModule*> {
        ShaderModule s;
        if (auto r = loadShader(d, s, code, bytes, name); !r) return fail(r.error());
        return &shaders_.emplace_back(std::move(s));
    };
    auto compute = [&](Program& p, Result<const ShaderModule*> s) -> Result<void> {
        if (!s) return fail(s.error());
        return createComputeProgram(d, p, *s.value());
    };
#define ML_VSM_SHADER(array) load(array, sizeof(array), #array)
    auto stage = markStage();
    if (!stage) return fail(stage.error());
    auto markShader = ML_VSM_SHADER(spv_vsm_mark_comp);
    ML_TRY(markShader);
    ML_TRY(createComputeProgram(d, mark, *markShader.value(), {{/*kStage*/ 0, stage.value()}}));
    auto markClusterShader = ML_VSM_SHADER(spv_vsm_mark_cluster_comp);
    ML_TRY(markClusterShader);
    ML_TRY(createComputeProgram(d, markCluster, *markClusterShader.value(), {{/*kStage*/ 0, stage.value()}}));
    ML_TRY(compute(list, ML_VSM_SHADER(spv_vsm_list_comp)));
    ML_TRY(compute(sort, ML_VSM_SHADER(spv_vsm_sort_comp)));
    ML_TRY(compute(allocateShortList, ML_VSM_SHADER(spv_vsm_allocate_short_list_comp)));
    ML_TRY(compute(scan, ML_VSM_SHADER(spv_vsm_scan_comp)));
    ML_TRY(compute(alloc, ML_VSM_SHADER(spv_vsm_alloc_comp)));
    ML_TRY(compute(avail, ML_VSM_SHADER(spv_vsm_avail_comp)));
    ML_TRY(compute(assign, ML_VSM_SHADER(spv_vsm_assign_comp)));
    ML_TRY(compute(hpb, ML_VSM_SHADER(spv_vsm_hpb_comp)));
    ML_TRY(compute(groups, ML_VSM_SHADER(spv_vsm_groups_comp)));
    ML_TRY(compute(pairs, ML_VSM_SHADER(spv_vsm_pairs_comp)));
    ML_TRY(compute(cull, ML_VSM_SHADER(spv_vsm_cull_comp)));
    ML_TRY(compute(clear, ML_VSM_SHADER(spv_vsm_clear_comp)));
    ML_TRY(compute(merge, ML_VSM_SHADER(spv_vsm_merge_comp)));
    ML_TRY(compute(probe, ML_VSM_SHADER(spv_vsm_probe_comp)));
    ML_TRY(compute(view, ML_VSM_SHADER(spv_vsm_view_comp)));
    GraphicsState gs; // attachment-less: depth goes to the pool with atomics
    gs.cull = VK_CULL_MODE_NONE;
    gs.depthTest = false;
    gs.depthWrite = false;
    auto frag = ML_VSM_SHADER(spv_vsm_draw_frag);
    ML_TRY(frag);
    auto vert = ML_VSM_SHADER(spv_vsm_draw_vert);
    ML_TRY(vert);
    ML_TRY(createGraphicsProgram(d, draw, {vert.value(), frag.value()}, gs));
    GraphicsState closed = gs;
    closed.cull = VK_CULL_MODE_BACK_BIT;
    closed.frontFace = kVsmFrontFace;
    ML_TRY(createGraphicsProgram(d, drawClosed, {vert.value(), frag.value()}, closed));
    if (!meshPath) return {};
    ML_TRY(compute(expand, ML_VSM_SHADER(spv_vsm_expand_comp)));
    auto task = ML_VSM_SHADER(spv_vsm_draw_task);
    ML_TRY(task);
    auto meshShader = ML_VSM_SHADER(spv_vsm_draw_mesh);
    ML_TRY(meshShader);
#undef ML_VSM_SHADER
    return createGraphicsProgram(d, mesh, {task.value(), meshShader.value(), frag.value()}, gs);
}

void VsmPrograms::destroy(const Device& d) {
    for (Program* p : {&mark,   &markCluster, &list,   &sort,       &scan,   &alloc, &avail,
                       &assign, &hpb,         &groups, &pairs,      &cull,   &clear, &merge,
                       &probe,  &view,        &draw,   &drawClosed, &expand, &mesh,  &allocateShortList})
        destroyProgram(d, *p);
    for (ShaderModule& s : shaders_) destroyShader(d, s);
    shaders_.clear();
}

} // namespace ml
