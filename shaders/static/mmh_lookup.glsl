// MMH lookup: mmhLookup and mmhLookupLevel come with MH's (mh_lookup.glsl), whose descent they share
// (shaders/static/mh_descent.h: MH's layout, values relative to the nearest valued ancestor).
#ifndef ML_MMH_LOOKUP_GLSL
#define ML_MMH_LOOKUP_GLSL
#include "mh_lookup.glsl"
#endif
