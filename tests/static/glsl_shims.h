// The GLSL static-shadow decoders (shaders/static/*_lookup.glsl) compiled as C++, for the tests that pin
// their text against the C++ decoders: `uint` is uint32_t, the SSBO is the pointer glsl::gStaticData
// (set it before a call), and the GLSL built-ins the decoders use are written out below. The functions
// are glsl::mhLookup(base, x, y) and the like, as a shader calls them. Everything is in an unnamed
// namespace, so every test file that includes this header has its own copy and its own gStaticData.
#pragma once
#include <bit>
#include <cstdint>

namespace glsl {
namespace {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function" // a test calls some of the decoders, not all
using uint = uint32_t;
const uint32_t* gStaticData = nullptr;
int bitCount(uint x) {
    return std::popcount(x);
}
int findMSB(uint x) {
    return x == 0 ? -1 : 31 - std::countl_zero(x);
}
uint min(uint a, uint b) {
    return a < b ? a : b;
}
uint max(uint a, uint b) {
    return a > b ? a : b;
}
#define ML_STATIC_DATA gStaticData
#include "shaders/static/dagmh_lookup.glsl"
#include "shaders/static/mh_lookup.glsl"
#include "shaders/static/mmh_lookup.glsl"
#undef ML_STATIC_DATA
#pragma GCC diagnostic pop
} // namespace
} // namespace glsl
