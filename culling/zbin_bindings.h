// Binding numbers of the Z-binning passes (zbin_mask.comp, zbin_bins.comp) and of its stats and shading
// probes (zbin_stats.comp, zbin_shade.comp), named once for the shaders (`layout(binding = ...)`) and
// for zbin.cpp, which passes each resource by its name (ML_BIND, gpu/bindings.h): the dispatch places it
// at that binding, in whatever order the list is.
#ifndef ML_ZBIN_BINDINGS_H
#define ML_ZBIN_BINDINGS_H

// zbin_mask.comp: the depth-sorted lights' tile masks.
#define ML_ZBIN_MASK_SORTED 0
#define ML_ZBIN_MASK_TILE_SLICES 1
#define ML_ZBIN_MASK_MASKS 2
#define ML_ZBIN_MASK_FRAME 3

// zbin_bins.comp: each depth bin's range of sorted lights.
#define ML_ZBIN_BINS_SORTED 0
#define ML_ZBIN_BINS_OUT 1

// zbin_stats.comp: per-pixel candidate counts.
#define ML_ZBIN_STATS_FRAME 0
#define ML_ZBIN_STATS_LIGHTS 1
#define ML_ZBIN_STATS_SORTED 2
#define ML_ZBIN_STATS_MASKS 3
#define ML_ZBIN_STATS_BINS 4
#define ML_ZBIN_STATS_DEPTH 5
#define ML_ZBIN_STATS_OUT 6
#define ML_ZBIN_STATS_WIDE 7

// zbin_shade.comp: the shading-loop probe.
#define ML_ZBIN_SHADE_FRAME 0
#define ML_ZBIN_SHADE_SLICES 1
#define ML_ZBIN_SHADE_LIGHTS 2
#define ML_ZBIN_SHADE_RANGES 3
#define ML_ZBIN_SHADE_POOL 4
#define ML_ZBIN_SHADE_SORTED 5
#define ML_ZBIN_SHADE_MASKS 6
#define ML_ZBIN_SHADE_BINS 7
#define ML_ZBIN_SHADE_WIDE 8
#define ML_ZBIN_SHADE_DEPTH 9
#define ML_ZBIN_SHADE_NORMAL 10
#define ML_ZBIN_SHADE_OUT 11

#endif
