// The virtual shadow map passes' programs (vsm.h lists the passes, vsm_passes.cpp records them): one per
// pass shader, created once for the raster path the settings chose; the mesh path's expand and
// task/mesh programs only when it is taken. The shader modules live as long as the programs.
#pragma once
#include "gpu/program.h"

#include <deque>

namespace ml {

struct VsmPrograms {
    Program mark;        // vsm_mark.comp: per receiver pixel
    Program markCluster; // vsm_mark_cluster.comp: per cluster-light pair (VsmSettings::clusterMarking)
    Program list, sort, scan, alloc, avail, assign, hpb, groups, pairs, cull, clear, merge, probe, view;
    Program allocateShortList; // vsm_allocate_short_list.comp: list to assignment in one workgroup
    Program draw;              // raster path: vsm_draw.vert + vsm_draw.frag (open casters: no culling)
    Program drawClosed;        // the same with back faces culled (closed casters)
    Program expand;            // mesh path: vsm_expand.comp
    Program mesh;              // mesh path: vsm_draw.task + vsm_draw.mesh + vsm_draw.frag
    Result<void> create(const Device& device, bool meshPath);
    void destroy(const Device& device);

  private:
    std::deque<ShaderModule> shaders_; // stable addresses: a graphics program takes several
};

} // namespace ml
