// One entry point for every static shadow method: name parsing, encoding from a dual depth map,
// validation, byte breakdown, and the CPU lookup twins. The bake file, `inspect`, `verify`, the bench and
// the module all go through here, so adding a method means adding it in one place.
//
// Depth methods (SM, MH, MMH, DAG-MH) return a light-space depth per texel (a receiver behind it is in
// shadow). CPVS returns binary visibility per voxel (shadows/static/cpvs.h).
#pragma once
#include "io/result.h"
#include "shadows/static/static_types.h"
#include "shadows/static/cpvs.h"
#include "shadows/static/dagmh.h"
#include "shadows/static/dual_depth.h"
#include "shadows/static/mh.h"
#include "shadows/static/mmh.h"
#include "shadows/static/sm.h"

#include <string>
#include <vector>

namespace ml {

struct StaticEncodeOptions {
    float nearPlane = 0.05f, farPlane = 10.0f; // the light frustum's (CPVS voxel space needs them)
    std::function<void(float)> progress;       // CPVS only
    CpvsStats* cpvsStats = nullptr;            // CPVS only: receives the bake's timings and counts
};

Result<std::vector<uint32_t>> encodeStatic(StaticMethod method, const DualDepthMap& map,
                                           const StaticEncodeOptions& options = {});
Result<void> validateStatic(StaticMethod method, const uint32_t* data, size_t words);
// Bytes per part: header, skip list, nodes, treelets, values, factors (CPVS: grid -> skipList,
// thresholds -> header, inner nodes -> nodes, leaf masks -> values).
stat::ByteBreakdown breakdownStatic(StaticMethod method, const uint32_t* data, size_t words);
uint32_t staticResolution(StaticMethod method, const uint32_t* data); // data must be valid

// Depth methods: the decoded depth of texel (x, y). Data must be valid.
uint32_t lookupStaticDepth(StaticMethod method, const uint32_t* data, uint32_t base, uint32_t x, uint32_t y);

} // namespace ml
