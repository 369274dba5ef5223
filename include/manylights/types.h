// The vectors and matrices of the public API: plain float arrays with a fixed layout, so that no compile
// definition of the host (GLM_FORCE_DEFAULT_ALIGNED_GENTYPES, GLM_FORCE_INTRINSICS, another math library's
// alignment) changes a public struct's size, its members' offsets or a function's linker name. Every type
// is standard layout and trivially copyable, aligned to 4 bytes, with no padding (sizes asserted below).
//
// They convert implicitly from any vector type with float members x, y, z (Float3) or x, y (Float2), and
// from any 4x4 float matrix of 64 bytes indexed [column][row] (Float4x4): glm::vec3 and glm::mat4 in any
// glm configuration, or a host's own types, can be handed to the API as they are. The way back to glm
// (and explicit conversions) is the optional header manylights/glm.h.
#pragma once
#include <cstddef>
#include <type_traits>

namespace ml {

// What converts implicitly (a type's own copy constructor wins over these for the type itself): a vector
// with float members x, y (Float2) or x, y, z (Float3; one with w is not narrowed without the caller
// saying so), and 64 bytes of floats indexed [column][row] (glm::mat4 aligned or not, float[4][4]; not a
// double matrix).
template <class V>
concept HasXY = requires(const V& v) {
    float(v.x) + float(v.y);
};
template <class V>
concept HasXYZ = requires(const V& v) {
    float(v.x) + float(v.y) + float(v.z);
};
template <class V>
concept HasZ = requires(const V& v) {
    v.z;
};
template <class V>
concept HasW = requires(const V& v) {
    v.w;
};
template <class V>
concept VectorXY = HasXY<V> && !HasZ<V>;
template <class V>
concept VectorXYZ = HasXYZ<V> && !HasW<V>;
template <class M>
concept Matrix4x4 = sizeof(M) == 64 && requires(const M& a) {
    float(a[3][3]);
};

struct Float2 {
    float x = 0.0f, y = 0.0f;
    constexpr Float2() = default;
    constexpr Float2(float x_, float y_) : x(x_), y(y_) {}
    template <VectorXY V> constexpr Float2(const V& v) : x(float(v.x)), y(float(v.y)) {}
};

struct Float3 {
    float x = 0.0f, y = 0.0f, z = 0.0f;
    constexpr Float3() = default;
    constexpr Float3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Float3(float s) : x(s), y(s), z(s) {}
    template <VectorXYZ V> constexpr Float3(const V& v) : x(float(v.x)), y(float(v.y)), z(float(v.z)) {}
};

// Column-major like glm and GLSL: m[c][r] is row r of column c, so m[3] holds the translation of an affine
// transform, and the 16 floats in memory are the order a GLSL mat4 (std430) reads.
struct Float4x4 {
    float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}; // identity
    constexpr Float4x4() = default;
    template <Matrix4x4 M> constexpr Float4x4(const M& a) {
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m[c][r] = float(a[c][r]);
    }
    constexpr float* operator[](int column) { return m[column]; }
    constexpr const float* operator[](int column) const { return m[column]; }
};

static_assert(sizeof(Float2) == 8 && alignof(Float2) == 4 && std::is_standard_layout_v<Float2> &&
              std::is_trivially_copyable_v<Float2>);
static_assert(sizeof(Float3) == 12 && alignof(Float3) == 4 && std::is_standard_layout_v<Float3> &&
              std::is_trivially_copyable_v<Float3>);
static_assert(offsetof(Float3, z) == 8);
static_assert(sizeof(Float4x4) == 64 && alignof(Float4x4) == 4 && std::is_standard_layout_v<Float4x4> &&
              std::is_trivially_copyable_v<Float4x4>);

} // namespace ml
