// Static shadow visibility in GLSL: staticVisibility (a receiver's visibility for one light's baked
// record), staticDepthAt and staticQuantize. One text with the CPU twin of
// shadows/static/static_visibility.cpp: shaders/static/static_pcf.h (the mapping, the bias, filtering by
// level and the PCF loops; read it for how they work), here reading ML_STATIC_DATA.
#ifndef ML_STATIC_VISIBILITY_GLSL
#define ML_STATIC_VISIBILITY_GLSL

#include "shaders/shared/shadow_record.h"
#include "shaders/static/common_static.glsl"
#include "shaders/static/mh_lookup.glsl"
#include "shaders/static/mmh_lookup.glsl"
#include "shaders/static/dagmh_lookup.glsl"
#include "shaders/static/cpvs_lookup.glsl"

#define ML_SV_FN
#define ML_SV_DATA_PARAM
#define ML_SV_DATA_ARG
#define ML_SV_WORD(i) ML_STATIC_DATA[i]
#define ML_SV_INOUT(T) inout T
#include "shaders/static/static_pcf.h"

#endif
