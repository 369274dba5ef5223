// Binding numbers of the static lookup timer (bench_lookup.comp), named once for the shader and for
// shadows/tools/lookup_timer.cpp, which binds each buffer by its name (ML_BIND, gpu/bindings.h).
#ifndef ML_BENCH_LOOKUP_BINDINGS_H
#define ML_BENCH_LOOKUP_BINDINGS_H

#define ML_LOOKUP_ITEMS 0   // per pair: point and normal
#define ML_LOOKUP_RECORDS 1 // GpuShadowRecord per light
#define ML_LOOKUP_WORDS 2   // the bake's words
#define ML_LOOKUP_OUT 3     // per-thread sums

#endif
