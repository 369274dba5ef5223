// Binding numbers of vsm_allocate_short_list.comp, named once for the shader (`layout(binding = ...)`)
// and for vsm_passes.cpp, which passes each resource by its name (ML_BIND, gpu/bindings.h).
#ifndef ML_VSM_ALLOC_BINDINGS_H
#define ML_VSM_ALLOC_BINDINGS_H

#define ML_VSM_SHORT_CONSTANTS 0  // VsmConstants (uniform)
#define ML_VSM_SHORT_RUNS 1       // the allocation order's runs
#define ML_VSM_SHORT_COUNTERS 2   // VsmCounters
#define ML_VSM_SHORT_REQUESTS 3   // the request list as vsm_mark appended it (list[0])
#define ML_VSM_SHORT_SORTED 4     // the sorted list (list[1]: vsm_hpb reads it)
#define ML_VSM_SHORT_SORT_ARGS 5  // which list is sorted, and the multi-dispatch passes' dispatch sizes
#define ML_VSM_SHORT_MAPS 6       // GpuVsmMap per slot (invalidation flags)
#define ML_VSM_SHORT_STALE 7      // the CPU's stale bits
#define ML_VSM_SHORT_TABLE 8      // page table
#define ML_VSM_SHORT_MARKS 9      // lookup and fallback marks
#define ML_VSM_SHORT_OWNERS 10    // entry per physical page
#define ML_VSM_SHORT_LAST_USED 11 // frame of last use per physical page
#define ML_VSM_SHORT_AVAIL 12     // the first `requests` entries of the available-page list
#define ML_VSM_SHORT_RENDERED 13  // pages to clear and draw (the clear's dispatch)
#define ML_VSM_SHORT_DIRTY_MIPS 14
#define ML_VSM_SHORT_DIRTY_MAPS 15
#define ML_VSM_SHORT_HPB 16 // hierarchical page buffer bits (vsm_hpb's step, when recorded alone)

#endif
