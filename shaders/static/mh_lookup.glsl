// MH and MMH lookups in GLSL: mhLookup, mhLookupLevel, mmhLookup, mmhLookupLevel. One text with the C++
// decoders of shadows/static/mh.h and mmh.h: shaders/static/mh_descent.h, here reading ML_STATIC_DATA.
#ifndef ML_MH_LOOKUP_GLSL
#define ML_MH_LOOKUP_GLSL
#include "common_static.glsl"

#define ML_MH_FN
#define ML_MH_DATA_PARAM
#define ML_MH_DATA_ARG
#define ML_MH_WORD(i) ML_STATIC_DATA[i]
#include "shaders/static/mh_descent.h"

#endif
