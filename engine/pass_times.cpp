#include "manylights/pass_times.h"

namespace ml {

const char* passName(Pass pass) {
    switch (pass) {
    case Pass::GBuffer:
        return "gbuffer";
    case Pass::ClusterBounds:
        return "cluster_bounds";
    case Pass::LightAssign:
        return "light_assign";
    case Pass::VsmMark:
        return "vsm_mark";
    case Pass::VsmSort:
        return "vsm_sort";
    case Pass::VsmAlloc:
        return "vsm_alloc";
    case Pass::VsmHpb:
        return "vsm_hpb";
    case Pass::VsmGroupCull:
        return "vsm_group_cull";
    case Pass::VsmCull:
        return "vsm_cull";
    case Pass::VsmExpand:
        return "vsm_expand";
    case Pass::VsmDraw:
        return "vsm_draw";
    case Pass::Evaluate:
        return "evaluate";
    case Pass::Statistics:
        return "statistics";
    case Pass::Count:
        break;
    }
    return "?";
}

double PassTimes::totalMs() const {
    double t = 0;
    for (uint32_t i = 0; i < kPassCount; ++i)
        if (ran[i]) t += ms[i];
    return t;
}

double PassTimes::vsmBookkeepingMs() const {
    double t = 0;
    for (uint32_t i = 0; i < kPassCount; ++i)
        if (ran[i] && vsmBookkeeping(Pass(i))) t += ms[i];
    return t;
}

} // namespace ml
