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

// Culling modes (specialization constant kSpecCullingMode and FrameConstants.cluster.w).
#define ML_CULL_CLUSTERED 0
#define ML_CULL_TILED 1
#define ML_CULL_NONE 2

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

// Virtual shadow maps (shadows/virtual/). Page size, virtual resolution and pool size are runtime
// settings (VsmSettings in engine/manylights.h); these are the fixed limits and workgroup sizes.
// GpuLight.info.y of a light without virtual shadow maps.
#define ML_VSM_NO_MAP 0xFFFFFFFFu
// Allocation passes (vsm_scan, vsm_assign) work in blocks of 256 page-table entries, one workgroup
// each: the in-block rank is a shared-memory prefix sum, and 256 entries x 4 B fit one lavapipe
// workgroup's shared memory many times over. vsm_alloc is one workgroup of the same size.
#define ML_VSM_BLOCK 256
// Marking and lookup: 8x8 pixels per workgroup, as the evaluation pass (neighbours share clusters).
#define ML_VSM_MARK_GROUP 8
// Shadow-page clear: one workgroup per rendered page, each thread clears pageSize^2 / 256 texels.
#define ML_VSM_CLEAR_GROUP 256
// Instance culling: one thread per (active map, caster).
#define ML_VSM_CULL_GROUP 64
// Meshlets of the VSM mesh path (meshoptimizer, engine/module.cpp addMesh): at most this many vertices
// and triangles each (meshoptimizer wants triangles a multiple of 4); the mesh shader's output capacity
// (VsmSettings::meshletVertices/Triangles may ask for smaller ones). Measured on lavapipe, FZK-Haus
// (32,588 triangles, 200 meshes), orbit, 320x180, 245 static spots, mesh path, page-draw ms per frame
// uncached / cached (`manylights bench vsm --scene ../shared/scenes/fzk-haus.glb --path orbit --frames 5
// --size 320x180 --kinds static-spot --vsm-raster mesh --meshlet VxT`, best of the runs, the machine shared):
//   16x32: 6607 meshlets, 6362 / 58.4 ms;  32x64: 3356 meshlets, 3588 / 28.3 ms;
//   64x124: 1637 meshlets, 2266 / 34.2 ms (triangles rasterized 0.96M vs 1.05M per frame at 32x64 vs 64x124).
// Smaller meshlets cull a few more triangles in the task shader but cost more task and mesh workgroups:
// 64/124 is fastest where drawing costs most (every page redrawn) and within noise when cached. The night
// city's meshes are small (16 meshlets for 11 meshes at 64/124), so the size hardly matters there.
#define ML_MESHLET_VERTICES 64
#define ML_MESHLET_TRIANGLES 124
// Task shader: one meshlet per invocation, 32 per workgroup (lavapipe prefers <= 64 task invocations).
#define ML_VSM_TASK_GROUP 32
// Mesh shader workgroup: one thread per output vertex (and two triangles per thread).
#define ML_VSM_MESH_GROUP 64
// Each receiver also marks the page ML_VSM_FALLBACK_MIPS mips (or clip levels) coarser than the one it
// wants: allocation serves coarse mips first, so when the pool runs out the lookup still finds that
// page. 3 mips up, a fallback page covers 8x8 wanted pages, so it costs 1/64 of the marked pages (and
// draws only the casters over them), while still being a shadow at 1/8 the resolution, not none.
#define ML_VSM_FALLBACK_MIPS 3u
// Mips of a map: S_0 = resolution / page size pages per side, mips down to one page. 16384 / 32 gives
// at most 10 mips; 16 leaves room and bounds the loops.
#define ML_VSM_MAX_MIPS 16

#endif
