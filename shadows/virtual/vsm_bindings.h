// Binding numbers of the virtual shadow map passes, named once for their shaders (`layout(binding = ...)`)
// and for vsm_passes.cpp, which passes each resource by its name (ML_BIND, gpu/bindings.h): the dispatch
// places it at that binding and refuses a list that names one twice, leaves one out or names one past the
// shader's. The same buffer sits at different numbers in different passes, so each pass has its own names.
// vsm_allocate_short_list.comp's are in vsm_alloc_bindings.h. The numbers are dense from 0 per program,
// as gpu/program.cpp requires (descriptors are pushed in binding order, without gaps).
#ifndef ML_VSM_BINDINGS_H
#define ML_VSM_BINDINGS_H

// vsm_mark.comp and vsm_mark_cluster.comp: receivers mark the pages their lookups will read.
#define ML_VSM_MARK_FRAME 0       // FrameConstants (uniform)
#define ML_VSM_MARK_SLICES 1      // far plane of each depth slice
#define ML_VSM_MARK_LIGHTS 2      // GpuLight per light
#define ML_VSM_MARK_RANGES 3      // each cluster's range in the light lists
#define ML_VSM_MARK_LIGHT_POOL 4  // the clusters' light lists
#define ML_VSM_MARK_DEPTH 5       // depth target (sampled)
#define ML_VSM_MARK_NORMAL 6      // normal target (sampled)
#define ML_VSM_MARK_CONSTANTS 7   // VsmConstants (uniform)
#define ML_VSM_MARK_MAPS 8        // GpuVsmMap per slot
#define ML_VSM_MARK_COVERAGE 9    // which lights have maps, per light
#define ML_VSM_MARK_MARKS 10      // lookup and fallback marks, one bit per page-table entry
#define ML_VSM_MARK_COUNTERS 11   // VsmCounters
#define ML_VSM_MARK_RANK_BASE 12  // first priority rank per (map slot, mip)
#define ML_VSM_MARK_REQUESTS 13   // the request list the first want of an entry appends to
#define ML_VSM_MARK_RECEIVERS 14  // vsm_mark_cluster only: each cluster's receiver bounds
#define ML_VSM_MARK_TILE_MASKS 15 // vsm_mark_cluster only: each tile's occupied slices

// vsm_list.comp: closes the request list and sizes the sort's dispatches.
#define ML_VSM_LIST_CONSTANTS 0 // VsmConstants (uniform)
#define ML_VSM_LIST_COUNTERS 1  // VsmCounters (the list's count)
#define ML_VSM_LIST_SORT_ARGS 2 // the sort and allocation passes' dispatch sizes
#define ML_VSM_LIST_OWNERS 3    // entry per physical page (the owned prefix's length)

// vsm_sort.comp: one block sort or merge pass from one list buffer to the other.
#define ML_VSM_SORT_COUNTERS 0 // VsmCounters (the list's count)
#define ML_VSM_SORT_SRC 1      // the runs this pass reads
#define ML_VSM_SORT_DST 2      // the runs it writes

// vsm_scan.comp: per owned physical page, invalidation and the per-block class counts; per sorted request,
// whether it needs a page, counted per block.
#define ML_VSM_SCAN_CONSTANTS 0     // VsmConstants (uniform)
#define ML_VSM_SCAN_RUNS 1          // the allocation order's runs
#define ML_VSM_SCAN_COUNTERS 2      // VsmCounters
#define ML_VSM_SCAN_LIST_A 3        // the first list buffer (list[0])
#define ML_VSM_SCAN_TABLE 4         // page table (invalidated)
#define ML_VSM_SCAN_MARKS 5         // lookup and fallback marks
#define ML_VSM_SCAN_LAST_USED 6     // frame of last use per physical page (refreshed)
#define ML_VSM_SCAN_BLOCK_COUNTS 7  // requests needing a page, per block
#define ML_VSM_SCAN_LIST_B 8        // the second list buffer (list[1])
#define ML_VSM_SCAN_SORT_ARGS 9     // which list buffer holds the sorted list, the owned pages
#define ML_VSM_SCAN_MAPS 10         // GpuVsmMap per slot (invalidation flags)
#define ML_VSM_SCAN_STALE 11        // the CPU's stale bits
#define ML_VSM_SCAN_OWNERS 12       // entry per physical page
#define ML_VSM_SCAN_CLASS_COUNTS 13 // pages per (block, class)

// vsm_alloc.comp: the blocks' first ranks and the classes' first slots (one workgroup).
#define ML_VSM_ALLOC_CONSTANTS 0    // VsmConstants (uniform)
#define ML_VSM_ALLOC_COUNTERS 1     // VsmCounters
#define ML_VSM_ALLOC_BLOCK_COUNTS 2 // in: counts per block, out: first ranks
#define ML_VSM_ALLOC_CLASS_COUNTS 3 // in: counts per (block, class), out: first slots
#define ML_VSM_ALLOC_SORT_ARGS 4    // the owned pages (word 3); out: vsm_avail's dispatch size

// vsm_avail.comp: per physical page, its place in the available-page list.
#define ML_VSM_AVAIL_CONSTANTS 0   // VsmConstants (uniform)
#define ML_VSM_AVAIL_MARKS 1       // lookup and fallback marks
#define ML_VSM_AVAIL_OWNERS 2      // entry per physical page
#define ML_VSM_AVAIL_LAST_USED 3   // frame of last use per physical page
#define ML_VSM_AVAIL_CLASS_BASES 4 // first slot per (block, class), from vsm_alloc
#define ML_VSM_AVAIL_AVAIL 5       // the available-page list it writes
#define ML_VSM_AVAIL_COUNTERS 6    // VsmCounters: the request count, from vsm_alloc

// vsm_assign.comp: each request that needs a page takes one; dirty pages and maps are listed.
#define ML_VSM_ASSIGN_CONSTANTS 0   // VsmConstants (uniform)
#define ML_VSM_ASSIGN_RUNS 1        // the allocation order's runs
#define ML_VSM_ASSIGN_COUNTERS 2    // VsmCounters
#define ML_VSM_ASSIGN_LIST_A 3      // the first list buffer (list[0])
#define ML_VSM_ASSIGN_TABLE 4       // page table
#define ML_VSM_ASSIGN_MARKS 5       // lookup and fallback marks
#define ML_VSM_ASSIGN_OWNERS 6      // entry per physical page
#define ML_VSM_ASSIGN_LAST_USED 7   // frame of last use per physical page
#define ML_VSM_ASSIGN_BLOCK_RANKS 8 // first rank per block, from vsm_alloc
#define ML_VSM_ASSIGN_AVAIL 9       // the available-page list
#define ML_VSM_ASSIGN_RENDERED 10   // pages to clear and draw
#define ML_VSM_ASSIGN_DIRTY_MIPS 11 // dirty-mip bits per map
#define ML_VSM_ASSIGN_DIRTY_MAPS 12 // the list of maps with a dirty page
#define ML_VSM_ASSIGN_LIST_B 13     // the second list buffer (list[1])
#define ML_VSM_ASSIGN_SORT_ARGS 14  // which list buffer holds the sorted list

// vsm_hpb.comp: the hierarchical page buffer's bits of the wanted dirty entries.
#define ML_VSM_HPB_CONSTANTS 0 // VsmConstants (uniform)
#define ML_VSM_HPB_RUNS 1      // the allocation order's runs
#define ML_VSM_HPB_COUNTERS 2  // VsmCounters
#define ML_VSM_HPB_LIST_A 3    // the first list buffer (list[0])
#define ML_VSM_HPB_TABLE 4     // page table
#define ML_VSM_HPB_MARKS 5     // lookup and fallback marks
#define ML_VSM_HPB_HPB 6       // HPB bits, every level (vsm_math.h)
#define ML_VSM_HPB_LIST_B 7    // the second list buffer (list[1])
#define ML_VSM_HPB_SORT_ARGS 8 // which list buffer holds the sorted list

// vsm_groups.comp: the bounds of each group of casters of the culling order.
#define ML_VSM_GROUPS_CASTERS 0 // GpuCaster per caster
#define ML_VSM_GROUPS_ORDER 1   // the culling order (the CPU's buildCasterOrder)
#define ML_VSM_GROUPS_GROUPS 2  // GpuCasterGroup per group, written here

// vsm_pairs.comp: the (caster group, dirty map) pairs inside the map's frustum.
#define ML_VSM_PAIRS_CONSTANTS 0  // VsmConstants (uniform)
#define ML_VSM_PAIRS_MAPS 1       // GpuVsmMap per slot
#define ML_VSM_PAIRS_DIRTY_MAPS 2 // the list of maps with a dirty page, from vsm_assign
#define ML_VSM_PAIRS_DIRTY_MIPS 3 // dirty-mip bits per map
#define ML_VSM_PAIRS_GROUPS 4     // GpuCasterGroup per group, from vsm_groups
#define ML_VSM_PAIRS_PAIRS 5      // the pair list it writes
#define ML_VSM_PAIRS_COUNTERS 6   // VsmCounters (pair count, the culling's dispatch size)

// vsm_cull.comp (vertex path): per pair, the casters' indirect draws per dirty mip.
#define ML_VSM_CULL_CONSTANTS 0   // VsmConstants (uniform)
#define ML_VSM_CULL_MAPS 1        // GpuVsmMap per slot
#define ML_VSM_CULL_PAIRS 2       // (group, map) pairs, from vsm_pairs
#define ML_VSM_CULL_TABLE 3       // page table
#define ML_VSM_CULL_HPB 4         // HPB bits, every level
#define ML_VSM_CULL_CASTERS 5     // GpuCaster per caster
#define ML_VSM_CULL_DIRTY_MIPS 6  // dirty-mip bits per map
#define ML_VSM_CULL_DRAWS 7       // VkDrawIndexedIndirectCommand per draw, per list and mip
#define ML_VSM_CULL_DRAW_INFO 8   // (instance, map, page, 0) per draw, for the vertex shader
#define ML_VSM_CULL_DRAW_COUNTS 9 // draws per list and mip
#define ML_VSM_CULL_COUNTERS 10   // VsmCounters
#define ML_VSM_CULL_ORDER 11      // the culling order (a workgroup's casters)

// vsm_expand.comp (mesh path): per pair, the meshlet-instance lists of the task shaders.
#define ML_VSM_EXPAND_CONSTANTS 0    // VsmConstants (uniform)
#define ML_VSM_EXPAND_MAPS 1         // GpuVsmMap per slot
#define ML_VSM_EXPAND_PAIRS 2        // (group, map) pairs, from vsm_pairs
#define ML_VSM_EXPAND_TABLE 3        // page table
#define ML_VSM_EXPAND_HPB 4          // HPB bits, every level
#define ML_VSM_EXPAND_CASTERS 5      // GpuCaster per caster
#define ML_VSM_EXPAND_DIRTY_MIPS 6   // dirty-mip bits per map
#define ML_VSM_EXPAND_MESHLET_LIST 7 // 3 words per meshlet instance, per mip
#define ML_VSM_EXPAND_MESH_TASKS 8   // per mip: task groups x, y, z and the count
#define ML_VSM_EXPAND_COUNTERS 9     // VsmCounters
#define ML_VSM_EXPAND_ORDER 10       // the culling order (a workgroup's casters)

// vsm_clear.comp: clears the pages rendered this frame.
#define ML_VSM_CLEAR_CONSTANTS 0 // VsmConstants (uniform)
#define ML_VSM_CLEAR_RENDERED 1  // pages to clear and draw
#define ML_VSM_CLEAR_PAGE_POOL 2 // the physical pages' depths

// vsm_merge.comp (static layer): the minimum of each rendered page and its static twin.
#define ML_VSM_MERGE_CONSTANTS 0 // VsmConstants (uniform)
#define ML_VSM_MERGE_RENDERED 1  // pages drawn this frame
#define ML_VSM_MERGE_PAGE_POOL 2 // the physical pages' depths, twins in the second half

// vsm_draw.{vert,frag} (vertex path) and vsm_draw.{task,mesh,frag} (mesh path): the dirty pages' draws.
// Binding 2 is the draw info on the vertex path and the meshlet-instance lists on the mesh path.
#define ML_VSM_DRAW_VERTICES 0          // GpuVertex, pulled by index
#define ML_VSM_DRAW_INSTANCES 1         // GpuInstance per instance
#define ML_VSM_DRAW_DRAW_INFO 2         // vertex path: (instance, map, page, 0) per draw, from vsm_cull
#define ML_VSM_DRAW_MESHLET_LIST 2      // mesh path: meshlet instances per mip, from vsm_expand
#define ML_VSM_DRAW_MAPS 3              // GpuVsmMap per slot
#define ML_VSM_DRAW_CONSTANTS 4         // VsmConstants (uniform)
#define ML_VSM_DRAW_TABLE 5             // page table
#define ML_VSM_DRAW_PAGE_POOL 6         // the physical pages' depths (atomic minimum)
#define ML_VSM_DRAW_COUNTERS 7          // VsmCounters (fragments drawn)
#define ML_VSM_DRAW_MESHLET_VERTICES 8  // mesh path: vertex indices of each meshlet
#define ML_VSM_DRAW_MESHLET_TRIANGLES 9 // mesh path: packed triangles of each meshlet
#define ML_VSM_DRAW_HPB 10              // mesh path: HPB bits, every level
#define ML_VSM_DRAW_MESH_TASKS 11       // mesh path: per mip task counts, from vsm_expand
#define ML_VSM_DRAW_MESHLETS 12         // mesh path: GpuMeshlet per meshlet

// vsm_probe.comp: the lookups of the probe points after the evaluation (tests).
#define ML_VSM_PROBE_FRAME 0      // FrameConstants (uniform)
#define ML_VSM_PROBE_SLICES 1     // far plane of each depth slice
#define ML_VSM_PROBE_LIGHTS 2     // GpuLight per light
#define ML_VSM_PROBE_RANGES 3     // each cluster's range in the light lists
#define ML_VSM_PROBE_LIGHT_POOL 4 // the clusters' light lists
#define ML_VSM_PROBE_DEPTH 5      // depth target (sampled)
#define ML_VSM_PROBE_NORMAL 6     // normal target (sampled)
#define ML_VSM_PROBE_CONSTANTS 7  // VsmConstants (uniform)
#define ML_VSM_PROBE_MAPS 8       // GpuVsmMap per slot
#define ML_VSM_PROBE_COVERAGE 9   // which lights have maps, per light
#define ML_VSM_PROBE_TABLE 10     // page table
#define ML_VSM_PROBE_PAGE_POOL 11 // the physical pages' depths
#define ML_VSM_PROBE_PROBES 12    // the probe records it appends

// vsm_view.comp (demo --view vsm): colours each pixel by the page its lookup reads.
#define ML_VSM_VIEW_FRAME 0      // FrameConstants (uniform)
#define ML_VSM_VIEW_SLICES 1     // far plane of each depth slice
#define ML_VSM_VIEW_LIGHTS 2     // GpuLight per light
#define ML_VSM_VIEW_RANGES 3     // each cluster's range in the light lists
#define ML_VSM_VIEW_LIGHT_POOL 4 // the clusters' light lists
#define ML_VSM_VIEW_DEPTH 5      // depth target (sampled)
#define ML_VSM_VIEW_NORMAL 6     // normal target (sampled)
#define ML_VSM_VIEW_CONSTANTS 7  // VsmConstants (uniform)
#define ML_VSM_VIEW_MAPS 8       // GpuVsmMap per slot
#define ML_VSM_VIEW_COVERAGE 9   // which lights have maps, per light
#define ML_VSM_VIEW_TABLE 10     // page table
#define ML_VSM_VIEW_PAGE_POOL 11 // the physical pages' depths
#define ML_VSM_VIEW_OUTPUT 12    // the RGBA8 output (storage image)

#endif
