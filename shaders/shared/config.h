// Limits and workgroup sizes, shared by C++ and GLSL. Each has the reason for its value.
#ifndef ML_CONFIG_H
#define ML_CONFIG_H

// 4096: the mission's upper bound for lights in one scene (`--lights` up to 4096). Light indices in
// cluster lists are 32-bit, so the bound is about memory and time, not encoding.
#define ML_MAX_LIGHTS 4096

// Clustered mode: 8x8-pixel tiles, 64 exponential depth slices. Measured on the night city at 320x180
// (manylights demo, culling_tightness = evaluated / reaching lights per pixel): 16 px / 32 slices
// gave 4.4, 8 px / 32 slices 2.6 (with the cone's bounding-sphere test only), 8 px / 64 slices with
// the pyramid test 1.75. 64 slices give a slice depth ratio (far/near)^(1/64) ~ 1.14 for 0.1..500 m;
// 8x8 = 64 threads per bounds group. Bounds are then tightened to the pixels in each cluster.
#define ML_TILE_SIZE 8
#define ML_MAX_SLICES 64
#define ML_CLUSTER_SLICES 64

// Light-assignment workgroup: one thread per light in chunks of 64 (one subgroup or two on most
// GPUs; lavapipe runs 8-wide SIMD, 64 keeps per-group overhead low for up to 4096 lights).
#define ML_ASSIGN_GROUP 64

// Evaluation pass: 8x8 pixels per workgroup (64 threads) keeps neighbouring pixels, which mostly share
// a cluster, in one group.
#define ML_EVAL_GROUP 8

// The light-index pool holds this many entries per cluster of the grid before clusters overflow; an
// overflowing cluster is counted and its pixels fall back to testing every visible light, so no light is
// lost. Most clusters are empty (no pixels: 2% occupied on the night city), so 16 per grid cluster is
// ~700 per occupied one: 16 x 921,600 clusters (1280x720) x 4 B = 59 MiB at most.
#define ML_POOL_PER_CLUSTER 16

// Culling modes (specialization constant kSpecCullingMode and FrameConstants.cluster.w). CLUSTERED
// assigns per light over its footprint (light_footprint.comp); CLUSTERED_BRUTE is the same grid and
// lists from every light against every occupied cluster of each tile (light_assign.comp); TILED is
// the brute force with one slice. All three write the same ranges + pool layout.
#define ML_CULL_CLUSTERED 0
#define ML_CULL_TILED 1
#define ML_CULL_NONE 2
#define ML_CULL_CLUSTERED_BRUTE 3

// Footprint assignment: ML_FOOTPRINT_LANES threads per visible light stride over the tiles of the
// light's screen rectangle and test the occupied slices (a 64-bit mask per tile) inside its depth
// range; ML_FOOTPRINT_GROUP / LANES lights per workgroup. Most lights cover a few tiles, so a whole
// 64-thread group per light left lavapipe (8-wide SIMD, a fixed cost per group) paying for idle
// threads: at 4096 lights, 640x360, one group per light took 76 ms of assignment for 70k box tests.
#define ML_FOOTPRINT_GROUP 64
#define ML_FOOTPRINT_LANES 8
// Allocation pass of the footprint mode: one thread per tile, 64 tiles per group.
#define ML_ALLOC_GROUP 64
// Fill pass of the footprint mode: ML_FILL_GROUPS groups of 64 threads stride over the recorded hits.
#define ML_FILL_GROUP 64
#define ML_FILL_GROUPS 64
// Hits the footprint count pass records, per pool entry: the pool holds 16 entries per grid cluster
// and frames use far fewer (0.3 M of 3.7 M at 4096 lights, 640x360), so a quarter of the pool's
// entries (8 bytes each) is room enough; past it the frame's lists overflow (counted, never lost).
#define ML_HITS_PER_POOL_ENTRY_DIV 4

// Light types (GpuLight.info.x); same values as ml::LightType.
#define ML_LIGHT_SPOT 0
#define ML_LIGHT_POINT 1
#define ML_LIGHT_DIRECTIONAL 2

// GpuLight.info.z of a light without a baked static shadow.
#define ML_NO_SHADOW 0xFFFFFFFFu

// Static shadow methods (StaticMethod in shadows/static/static_method.h; stored in bake files).
#define ML_STATIC_SM 1
#define ML_STATIC_MH 2
#define ML_STATIC_MMH 3
#define ML_STATIC_DAGMH 4
#define ML_STATIC_CPVS 5

// Largest PCF radius of the static lookups: 4 = 9x9 (the CPVS issue's maximum).
#define ML_MAX_PCF_RADIUS 4

// Marks an overflowed cluster in ClusterRange.offset.
#define ML_CLUSTER_OVERFLOW 0xFFFFFFFFu

#endif
