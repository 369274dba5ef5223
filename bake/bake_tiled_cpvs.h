// Out-of-core CPVS bakes and verifies of one record (shadows/static/cpvs_tiled.h): the dual depth map is
// never held whole, so CPVS bakes past kBakeWholeMapMax up to kCpvsMaxResolution. Strips are rendered by
// the CPU rasteriser (DualRasterizer::renderRect) on every hardware thread, as the MH family's tiles
// (bake_tiled.h); the words equal the whole-map bake's of the same rasteriser's map.
#pragma once
#include "bake/bake_tiled.h"

namespace ml {

// The CPVS words of one map, built region by region. options.maxNodes (0: none) bounds the sub-DAGs alive
// at once to the bytes of as many MH tree nodes held twice (the bound bakeTilesOf derives from
// --max-memory); progress gets 0..1 over the regions.
Result<std::vector<uint32_t>> bakeCpvsRecordTiled(const CasterTriangles& casters, const LightFrustum& frustum,
                                                  uint32_t resolution, const TiledBakeOptions& options,
                                                  LightBakeStats& stats);

// Every voxel of a CPVS record against the re-rendered tiles (tile x tile texels, each column walked
// through the DAG against its voxelisation; undefined voxels counted apart), in bounded memory.
Result<void> verifyCpvsRecordTiled(const BakeRecord& record, const CasterTriangles& casters, uint32_t tile,
                                   const std::function<void(double)>& progress, VerifyLight& out,
                                   std::vector<std::string>& examples, size_t maxExamples);

} // namespace ml
