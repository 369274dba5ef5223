// Optional: conversions between the API's plain types (manylights/types.h) and glm, for a host that does
// its math in glm. The API itself never includes glm, so a host's GLM_FORCE_* definitions cannot change
// it. Handing glm values to the API needs nothing (Float2, Float3 and Float4x4 convert from them
// implicitly); reading the API's values back as glm is toGlm here.
//
// The functions are templates over glm's qualifier (defaulted to the includer's glm::defaultp): a host
// built with GLM_FORCE_DEFAULT_ALIGNED_GENTYPES and the module built without get differently named
// instantiations, so the linker never merges a 16-byte vec3 with a 12-byte one.
#pragma once
#include "manylights/types.h"

#include <glm/glm.hpp>

namespace ml {

template <glm::qualifier Q = glm::defaultp> glm::vec<2, float, Q> toGlm(Float2 v) {
    return {v.x, v.y};
}
template <glm::qualifier Q = glm::defaultp> glm::vec<3, float, Q> toGlm(Float3 v) {
    return {v.x, v.y, v.z};
}
template <glm::qualifier Q = glm::defaultp> glm::mat<4, 4, float, Q> toGlm(const Float4x4& a) {
    glm::mat<4, 4, float, Q> out;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) out[c][r] = a.m[c][r];
    return out;
}

template <glm::qualifier Q> Float2 fromGlm(const glm::vec<2, float, Q>& v) {
    return {v.x, v.y};
}
template <glm::qualifier Q> Float3 fromGlm(const glm::vec<3, float, Q>& v) {
    return {v.x, v.y, v.z};
}
template <glm::qualifier Q> Float4x4 fromGlm(const glm::mat<4, 4, float, Q>& a) {
    return Float4x4(a);
}

} // namespace ml
