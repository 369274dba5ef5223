#include "shadows/virtual/vsm_programs.h"

#include "vsm_alloc.comp.spv.h"
#include "vsm_assign.comp.spv.h"
#include "vsm_avail.comp.spv.h"
#include "vsm_clear.comp.spv.h"
#include "vsm_cull.comp.spv.h"
#include "vsm_draw.frag.spv.h"
#include "vsm_draw.mesh.spv.h"
#include "vsm_draw.task.spv.h"
#include "vsm_draw.vert.spv.h"
#include "vsm_expand.comp.spv.h"
#include "vsm_hpb.comp.spv.h"
#include "vsm_invalidate.comp.spv.h"
#include "vsm_list.comp.spv.h"
#include "vsm_mark.comp.spv.h"
#include "vsm_probe.comp.spv.h"
#include "vsm_scan.comp.spv.h"
#include "vsm_sort.comp.spv.h"
#include "vsm_view.comp.spv.h"

namespace ml {

void VsmPrograms::create(const Device& d, bool meshPath) {
    auto keep = [&](ShaderModule s) -> const ShaderModule& { return shaders_.emplace_back(std::move(s)); };
    auto compute = [&](ShaderModule s) { return createComputeProgram(d, keep(std::move(s))); };
    mark = compute(ML_SHADER(d, spv_vsm_mark_comp));
    list = compute(ML_SHADER(d, spv_vsm_list_comp));
    sort = compute(ML_SHADER(d, spv_vsm_sort_comp));
    invalidate = compute(ML_SHADER(d, spv_vsm_invalidate_comp));
    scan = compute(ML_SHADER(d, spv_vsm_scan_comp));
    alloc = compute(ML_SHADER(d, spv_vsm_alloc_comp));
    avail = compute(ML_SHADER(d, spv_vsm_avail_comp));
    assign = compute(ML_SHADER(d, spv_vsm_assign_comp));
    hpb = compute(ML_SHADER(d, spv_vsm_hpb_comp));
    cull = compute(ML_SHADER(d, spv_vsm_cull_comp));
    clear = compute(ML_SHADER(d, spv_vsm_clear_comp));
    probe = compute(ML_SHADER(d, spv_vsm_probe_comp));
    view = compute(ML_SHADER(d, spv_vsm_view_comp));
    GraphicsState gs; // attachment-less: depth goes to the pool with atomics
    gs.cull = VK_CULL_MODE_NONE;
    gs.depthTest = false;
    gs.depthWrite = false;
    const ShaderModule& frag = keep(ML_SHADER(d, spv_vsm_draw_frag));
    draw = createGraphicsProgram(d, {&keep(ML_SHADER(d, spv_vsm_draw_vert)), &frag}, gs);
    if (!meshPath) return;
    expand = compute(ML_SHADER(d, spv_vsm_expand_comp));
    const ShaderModule& task = keep(ML_SHADER(d, spv_vsm_draw_task));
    const ShaderModule& meshShader = keep(ML_SHADER(d, spv_vsm_draw_mesh));
    mesh = createGraphicsProgram(d, {&task, &meshShader, &frag}, gs);
}

void VsmPrograms::destroy(const Device& d) {
    for (Program* p : {&mark, &list, &sort, &invalidate, &scan, &alloc, &avail, &assign, &hpb, &cull, &clear,
                       &probe, &view, &draw, &expand, &mesh})
        destroyProgram(d, *p);
    for (ShaderModule& s : shaders_) destroyShader(d, s);
    shaders_.clear();
}

} // namespace ml
