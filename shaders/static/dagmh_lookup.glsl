// DAG-MH lookups in GLSL: dagmhLookup, dagmhLookupLevel (a level above the finest, for filtering by
// level), the bounds tests and the steps a PCF kernel shares (dagmhPcfPrefix, dagmhLevelStart). One text
// with the C++ decoder of shadows/static/dagmh.h: shaders/static/dagmh_decode.h, here reading
// ML_STATIC_DATA (layout in shadows/static/dagmh.h and docs/dagmh-encoding.md).
#ifndef ML_DAGMH_LOOKUP_GLSL
#define ML_DAGMH_LOOKUP_GLSL
#include "common_static.glsl"

#define ML_DAG_FN
#define ML_DAG_DATA_PARAM
#define ML_DAG_DATA_ARG
#define ML_DAG_WORD(i) ML_STATIC_DATA[i]
#include "shaders/static/dagmh_decode.h"

#endif
