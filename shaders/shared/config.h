// Limits and workgroup sizes, shared by C++ and GLSL. Each has the reason for its value and its cost;
// the measurements behind the chosen values are on the docs page of their subject, with their commands.
#ifndef ML_CONFIG_H
#define ML_CONFIG_H

// 4096: the most lights a module holds (addLight refuses more; `--lights` up to 4096). Light indices in
// cluster lists are 32-bit, so the bound is about memory and time, not encoding.
#define ML_MAX_LIGHTS 4096

// Clustered modes: 8x8-pixel tiles, 64 exponential depth slices (ML_CLUSTER_SLICES; ML_MAX_SLICES is
// the most the 64-bit tile masks and shared arrays hold). 64 slices give a slice depth ratio
// (far/near)^(1/64) ~ 1.14 for 0.1..500 m; 8x8 = 64 threads per bounds group. Bounds are the pixels'
// own AABB per cluster. Reason: the tightest lists; coarser grids test fewer boxes in the assignment but
// every pixel then evaluates more lights, and the evaluation pass costs several times the culling.
// Cost: 921,600 clusters at 1280x720, 40 B each (32 B of bounds, 8 B of list range): 35 MiB. The grids
// compared: docs/culling.md, "Grid size".
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
// lost. Most clusters hold no pixel, so 16 per grid cluster is hundreds per occupied one (the pool's
// use on the night city: docs/culling.md, "Grid size"). Cost: 16 x 921,600 clusters (1280x720) x 4 B =
// 59 MiB at most, plus the footprint mode's hit records (a quarter of that many, 8 B each: 29 MiB). The
// tiled grid gets the same pool as the clustered one (its lists are the union of 64 slices').
#define ML_POOL_PER_CLUSTER 16

// Culling modes (FrameConstants.cluster.w; ml::CullingMode takes these values). CLUSTERED
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
// threads; 8 lanes per light assign faster (docs/culling.md, "Grid size").
#define ML_FOOTPRINT_GROUP 64
#define ML_FOOTPRINT_LANES 8
// Wide lights are the directional ones: the moon covers the whole grid (32,400 tiles at 1920x1080,
// 4,050 per lane of its 8), so it is not walked by lanes but by a pass with one thread per tile of
// its footprint. Spot and point lights with big footprints stay on their lanes: a thread per tile
// repeats the light's setup for every tile, which made their assignment slower (the wide lights'
// entry in docs/results/log.md).
// The wide pass's threads (one per tile of each wide light's footprint) run in rows of this many:
// 1024 groups of 64 per row keeps each dimension far below the 65,535-group limit (the moon alone is
// 32,400 threads at 1920x1080; 16 directional lights at 16384^2 pixels would be 1,024 rows).
#define ML_WIDE_ROW 65536
// Allocation pass of the footprint mode: one thread per tile, 64 tiles per group.
#define ML_ALLOC_GROUP 64
// Fill pass of the footprint mode: ML_FILL_GROUPS groups of 64 threads stride over the recorded hits.
#define ML_FILL_GROUP 64
#define ML_FILL_GROUPS 64
// Hits the footprint count pass records, per pool entry: the pool holds 16 entries per grid cluster
// and frames use far fewer (docs/culling.md, "Grid size"), so a quarter of the pool's entries (8 bytes
// each) is room enough; past it the frame's lists overflow (counted, never lost).
#define ML_HITS_PER_POOL_ENTRY_DIV 4
// Sorted fill of the footprint mode (light_alloc, light_fill): per tile a bitmask over the visible
// lights with a hit in the tile and its per-word prefix counts, ML_MAX_LIGHTS / 32 = 128 words each
// (512 B per tile and buffer: 1.8 MiB at 640x360's 3,600 tiles, 16.6 MiB at 1920x1080's 32,400),
// plus a tile range (8 B per tile) and a 64-bit slice mask per (tile, light) pair, at most one per
// recorded hit (hitCapacity x 8 B, as much as the hits).
#define ML_TILE_WORDS (ML_MAX_LIGHTS / 32)

// Z-binning (culling/zbin.h; Drobot 2017), measured beside the footprint clusters: ML_ZBIN_BINS bins
// linear in view depth over [near, the farthest light's far depth], each holding the (min, max)
// sorted index of the lights overlapping it (16 bits each: ML_MAX_LIGHTS = 4096 fits); per
// ML_TILE_SIZE^2 tile a bitmask over the depth-sorted lights, ML_MAX_LIGHTS / 32 = 128 words
// (512 B per tile: 16.6 MB at 1920x1080's 32,400 tiles). 1024 bins keep a bin (a few tenths of a metre
// on the night city) below the lights' depth extents (metres), so the (min, max) ranges add few
// candidates over exact per-light ranges (docs/culling.md, "Z-binning side by side").
#define ML_ZBIN_BINS 1024
#define ML_ZBIN_WORDS (ML_MAX_LIGHTS / 32)
// Mask pass: ML_ZBIN_LANES threads per sorted light over its tile rectangle (as the footprint pass);
// bin pass and stats pass: groups of ML_ZBIN_GROUP threads.
#define ML_ZBIN_LANES 8
#define ML_ZBIN_GROUP 64

// Light kinds (GpuLight.info.x): ml::LightKind takes these values (shaders/shared/enums.h).
#define ML_LIGHT_SPOT 0
#define ML_LIGHT_POINT 1
#define ML_LIGHT_DIRECTIONAL 2

// GpuLight.info.z of a light without a baked static shadow.
#define ML_NO_SHADOW 0xFFFFFFFFu

// The G-buffer normal's w (GpuInstance.material.z): 1 (any value >= 0) on a shadow receiver, this value on
// an instance that receives no shadows (Module::setInstanceShadowReceiving, Bevy's NotShadowReceiver): the
// evaluation lights its pixels unshadowed. A host G-buffer writes it too (HostTargets, normal).
#define ML_NOT_A_RECEIVER (-1.0)

// Static shadow methods (stored in bake files): ml::StaticMethod takes these values (shaders/shared/enums.h).
#define ML_STATIC_SM 1
#define ML_STATIC_MH 2
#define ML_STATIC_MMH 3
#define ML_STATIC_DAGMH 4
#define ML_STATIC_CPVS 5

// Largest PCF radius of the static lookups: 4 = 9x9, the widest they are specified for (81 taps at most).
#define ML_MAX_PCF_RADIUS 4

// Filtering by level (MH, MMH, DAG-MH, CPVS) reads the coarsest level whose texel is at most 1/4 of the
// receiver's pixel (shadowLevelStep). A level texel as wide as the pixel puts every shadow edge on a grid of
// pixel-sized blocks, which flips more pixels between frames than the finest level does
// (docs/filtering-by-level.md); the cost is a descent two levels deeper.
// A power of two, so the level search stays an exact doubling.
#define ML_LEVEL_TEXELS_PER_PIXEL 4.0

// Marks an overflowed cluster in ClusterRange.offset.
#define ML_CLUSTER_OVERFLOW 0xFFFFFFFFu

// Virtual shadow maps (shadows/virtual/). Page size, virtual resolution and pool size are runtime
// settings (VsmSettings in manylights/vsm_settings.h); these are the fixed limits and workgroup sizes.
// GpuLight.info.y of a light without virtual shadow maps.
#define ML_VSM_NO_MAP 0xFFFFFFFFu
// Allocation passes (vsm_scan, vsm_assign) work in blocks of 256 page-table entries, one workgroup
// each: the in-block rank is a shared-memory prefix sum, and 256 entries x 4 B fit one lavapipe
// workgroup's shared memory many times over. vsm_alloc is one workgroup of the same size.
#define ML_VSM_BLOCK 256
// One workgroup allocates request lists up to this long: 16 KiB of shared keys, 16 per thread, one core.
#define ML_VSM_ONE_GROUP_LIST 4096
// vsm_sort merges 2^ML_VSM_MERGE_WAYS_LOG2 = 8 sorted runs per pass (an entry's place: its index in its
// run plus the keys below it in the 7 sibling runs): 4 merge passes from 256-entry blocks to the default
// 2^18-entry capacity, where pairwise merges take 10, each a dispatch behind a barrier.
#define ML_VSM_MERGE_WAYS_LOG2 3u
// Marking and lookup: 8x8 pixels per workgroup, as the evaluation pass (neighbours share clusters).
#define ML_VSM_MARK_GROUP 8
// Shadow-page clear: one workgroup per rendered page, each thread clears pageSize^2 / 256 texels.
#define ML_VSM_CLEAR_GROUP 256
// Instance culling: one workgroup per (group of 64 casters, map with a dirty page) pair left by vsm_pairs,
// one thread per caster. 64: two NVIDIA warps or eight 8-lane lavapipe rows per workgroup, and one refused
// pair saves 64 caster reads (most pairs are refused: docs/virtual-shadow-maps.md; other sizes not measured).
#define ML_VSM_CULL_GROUP 64
// Meshlets of the VSM mesh path (meshoptimizer, engine/module.cpp addMesh): at most this many vertices
// and triangles each (meshoptimizer wants triangles a multiple of 4); the mesh shader's output capacity
// (VsmSettings::meshletVertices/Triangles may ask for smaller ones). Smaller meshlets cull a few more
// triangles in the task shader but cost more task and mesh workgroups: 64/124 draws fastest where drawing
// costs most (every page redrawn). Cost: every mesh workgroup reserves outputs for 64 vertices and 124
// triangles. The sizes compared: docs/vsm-page-draws.md, "Meshlet size".
#define ML_MESHLET_VERTICES 64
#define ML_MESHLET_TRIANGLES 124
// Task shader: one meshlet per invocation, 32 per workgroup (lavapipe prefers <= 64 task invocations).
#define ML_VSM_TASK_GROUP 32
// Mesh shader workgroup: one thread per output vertex (and two triangles per thread).
#define ML_VSM_MESH_GROUP 64
// Mesh path: a task workgroup launches one mesh workgroup per (surviving meshlet, dirty page under its
// bounds), each clipped to its page; the payload lists at most this many (4 bytes each: 8 KiB of the
// 16 KiB every device must give a payload). 32 meshlets x 64 pages: a meshlet of the night city's ground
// over a whole 8x8-page dirty block per survivor. A meshlet that does not fit is drawn unclipped
// (counted: VsmCounters.pageClipOverflow).
#define ML_VSM_TASK_PAGES 2048
// Each receiver also marks the page ML_VSM_FALLBACK_MIPS mips (or clip levels) coarser than the one it
// wants: allocation serves coarse mips first, so when the pool runs out the lookup still finds that
// page. 3 mips up, a fallback page covers 8x8 wanted pages, so it costs 1/64 of the marked pages (and
// draws only the casters over them), while still being a shadow at 1/8 the resolution, not none.
#define ML_VSM_FALLBACK_MIPS 3u
// Mips of a map: S_0 = resolution / page size pages per side, mips down to one page. 16384 / 32 gives
// at most 10 mips; 16 leaves room and bounds the loops.
#define ML_VSM_MAX_MIPS 16

#endif
