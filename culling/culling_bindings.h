// Binding numbers of the culling passes, named once for their shaders (`layout(binding = ...)`) and for
// culling/culling.cpp, which passes each resource by its name (ML_BIND, gpu/bindings.h): the dispatch
// places it at that binding and refuses a list that names one twice, leaves one out or names one past
// the shader's. Several passes read the same buffer at different numbers, so each pass has its own names.
#ifndef ML_CULLING_BINDINGS_H
#define ML_CULLING_BINDINGS_H

// cluster_bounds.comp: the world AABB of each (tile, slice) from the depth buffer.
#define ML_BOUNDS_FRAME 0
#define ML_BOUNDS_SLICES 1
#define ML_BOUNDS_DEPTH 2
#define ML_BOUNDS_OUT 3
#define ML_BOUNDS_COUNTERS 4
#define ML_BOUNDS_TILE_MASKS 5
#define ML_BOUNDS_NORMAL 6
#define ML_BOUNDS_RECEIVERS 7 // the receiver variant's output (the plain one binds ML_BOUNDS_OUT's buffer)

// light_footprint.comp (both variants): count and record each light's hits.
#define ML_FOOTPRINT_FRAME 0
#define ML_FOOTPRINT_SLICES 1
#define ML_FOOTPRINT_LIGHTS 2
#define ML_FOOTPRINT_BOUNDS 3
#define ML_FOOTPRINT_TILE_MASKS 4
#define ML_FOOTPRINT_COUNTS 5
#define ML_FOOTPRINT_HITS 6
#define ML_FOOTPRINT_WORK 7
#define ML_FOOTPRINT_WIDE 8
#define ML_FOOTPRINT_TILE_BITS 9

// light_alloc.comp: each tile's clusters get their ranges in the pool.
#define ML_ALLOC_FRAME 0
#define ML_ALLOC_TILE_MASKS 1
#define ML_ALLOC_COUNTS 2
#define ML_ALLOC_RANGES 3
#define ML_ALLOC_COUNTERS 4
#define ML_ALLOC_WORK 5
#define ML_ALLOC_TILE_BITS 6
#define ML_ALLOC_TILE_PREFIX 7
#define ML_ALLOC_TILE_RANGES 8
#define ML_ALLOC_TILE_SLICES 9

// light_fill.comp (mark and append): the recorded hits into sorted lists.
#define ML_FILL_FRAME 0
#define ML_FILL_HITS 1
#define ML_FILL_RANGES 2
#define ML_FILL_POOL 3
#define ML_FILL_WORK 4
#define ML_FILL_TILE_BITS 5
#define ML_FILL_TILE_PREFIX 6
#define ML_FILL_TILE_RANGES 7
#define ML_FILL_TILE_SLICES 8

// light_assign.comp (clustered-brute, tiled): every visible light against each occupied cluster.
#define ML_ASSIGN_FRAME 0
#define ML_ASSIGN_LIGHTS 1
#define ML_ASSIGN_BOUNDS 2
#define ML_ASSIGN_RANGES 3
#define ML_ASSIGN_POOL 4
#define ML_ASSIGN_COUNTERS 5
#define ML_ASSIGN_WORK 6

// lights/view_lights.comp (recorded by LightCulling::recordView): the light-complexity views.
#define ML_VIEW_FRAME 0
#define ML_VIEW_SLICES 1
#define ML_VIEW_LIGHTS 2
#define ML_VIEW_RANGES 3
#define ML_VIEW_DEPTH 4
#define ML_VIEW_OUTPUT 5
#define ML_VIEW_COUNTS 6

#endif
