// Binding numbers of the evaluation and statistics passes (evaluate.comp, statistics.comp), named once
// for the shaders (`layout(binding = ...)`) and for lights/evaluate_pass.cpp, which passes each resource
// by its name (ML_BIND, gpu/bindings.h). The evaluation's first 12 bindings are the host include's
// (manylights/host_bindings.h, ML_HOST_*: lights/manylights_lights.glsl declares them at offset 0), so
// a host's own shaders and the evaluation read the same buffers at the same numbers; its images follow.
#ifndef ML_EVALUATE_BINDINGS_H
#define ML_EVALUATE_BINDINGS_H

#include "manylights/host_bindings.h"

// evaluate.comp, after ML_HOST_FRAME..ML_HOST_VSM_POOL.
#define ML_EVAL_DEPTH (ML_HOST_BINDING_COUNT + 0)
#define ML_EVAL_NORMAL (ML_HOST_BINDING_COUNT + 1)
#define ML_EVAL_ALBEDO (ML_HOST_BINDING_COUNT + 2)
#define ML_EVAL_HDR (ML_HOST_BINDING_COUNT + 3)
#define ML_EVAL_OUTPUT (ML_HOST_BINDING_COUNT + 4)
#define ML_EVAL_MATERIAL (ML_HOST_BINDING_COUNT + 5) // read by the GGX variant (kSpecPbr) only

// statistics.comp: per-pixel light counts.
#define ML_STATS_FRAME 0
#define ML_STATS_SLICES 1
#define ML_STATS_LIGHTS 2
#define ML_STATS_RANGES 3
#define ML_STATS_POOL 4
#define ML_STATS_DEPTH 5
#define ML_STATS_COUNTERS 6

#endif
