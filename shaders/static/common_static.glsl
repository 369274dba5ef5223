// Shared helpers of the static shadow decoders (twin of shadows/static/format_common.h).
// Before including any *_lookup.glsl, define ML_STATIC_DATA as the name of the `uint []` array that
// holds the encoded buffers, e.g.
//   layout(std430, binding = 3) readonly buffer StaticShadows { uint staticData[]; };
//   #define ML_STATIC_DATA staticData
// Every decoder takes `base`, the word offset of one encoded buffer inside that array. Only buffers
// that passed the CPU validate() may be bound: the decoders do no bounds checks of their own.
#ifndef ML_STATIC_COMMON_GLSL
#define ML_STATIC_COMMON_GLSL

#ifndef ML_STATIC_DATA
#error "define ML_STATIC_DATA (the uint[] SSBO array) before including the static shadow decoders"
#endif

uint mlPopc(uint x) { return uint(bitCount(x)); }
uint mlLowMask(uint bits) { return bits >= 32u ? 0xFFFFFFFFu : ((1u << bits) - 1u); }

#endif
