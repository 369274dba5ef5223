// The enums of the public API. Their values are stored (StaticMethod in bake files) and read by the
// module's shaders, which see the same numbers as preprocessor constants: the module checks at compile
// time that the two agree, so the values here never change.
#pragma once
#include <cstdint>

namespace ml {

// A light's kind (LightDesc::kind).
enum class LightKind : uint32_t { Spot = 0, Point = 1, Directional = 2 };

// A static shadow's encoding (StaticShadowDesc::method, Module::bakeStaticShadows); None: no static shadow.
//   SM     one depth per texel (a shadow map)
//   MH     min-max quadtree of the depths, MMH its merged variant, DAGMH a deduplicated tree of it
//   CPVS   a compressed precomputed visibility set (voxel bits), no depths
enum class StaticMethod : uint32_t { None = 0, SM = 1, MH = 2, MMH = 3, DAGMH = 4, CPVS = 5 };

// How lights are assigned to the view. Clustered: each light's footprint over a 3D grid of clusters;
// ClusteredBrute: the same lists from every light against every occupied cluster (kept for comparison);
// Tiled: a 2D grid of screen tiles (one depth slice); None: every light at every pixel.
enum class CullingMode : uint32_t { Clustered = 0, Tiled = 1, None = 2, ClusteredBrute = 3 };

} // namespace ml
