// The depth slice every per-pixel pass finds (shaders/shared/cluster_slice.glsl): its text compiled as
// C++ must give what culling.cpp's linear walk gives for every depth, whether or not the logarithm's
// estimate is right: at each slice end, one float either side of it, below the near plane and past the
// far one, and over tables that are not exponential at all (where the estimate is off by many slices and
// only the walks find the answer). The GPU run of the same text is checked on real frames by the
// culling, evaluation and statistics tests, which rebuild each pixel's list with sliceOf.
#include "culling/culling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace glsl {
using uint = uint32_t;
struct FrameSlices {
    glm::uvec4 cluster; // x slices
    glm::vec4 depth;    // x near, y far
};
static FrameSlices frame;
static const float* sliceFar = nullptr;
inline float log(float x) {
    return std::log(x);
}
inline float max(float a, float b) {
    return a > b ? a : b;
}
inline float clamp(float x, float lo, float hi) {
    return x < lo ? lo : (x > hi ? hi : x);
}
#include "shaders/shared/cluster_slice.glsl"
} // namespace glsl

namespace ml::test {
namespace {

// Depths around every slice end of `table` and outside [near, far]; the twin must equal sliceOf.
uint64_t mismatches(const std::vector<float>& table, float nearPlane, float farPlane, std::mt19937& rng) {
    const auto slices = uint32_t(table.size());
    glsl::frame.cluster = glm::uvec4(slices, 8, 0, 0);
    glsl::frame.depth = glm::vec4(nearPlane, farPlane, nearPlane * farPlane, farPlane - nearPlane);
    glsl::sliceFar = table.data();
    std::vector<float> depths = {0.0f, nearPlane * 0.5f, nearPlane, farPlane, farPlane * 2.0f, 3.0e38f};
    for (float end : table)
        for (float z :
             {std::nextafter(end, 0.0f), end, std::nextafter(end, std::numeric_limits<float>::infinity())})
            depths.push_back(z);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) depths.push_back(nearPlane + (farPlane - nearPlane) * u(rng));
    uint64_t bad = 0;
    for (float z : depths) bad += glsl::clusterSlice(z) != sliceOf(z, table, slices);
    return bad;
}

TEST(ClusterSlice, GlslTextEqualsTheLinearWalk) {
    std::mt19937 rng(5);
    for (float nearPlane : {0.05f, 0.1f, 1.0f})
        for (float farPlane : {50.0f, 500.0f, 5000.0f}) {
            SCOPED_TRACE(testing::Message() << "near " << nearPlane << " far " << farPlane);
            // The module's own exponential table, at the slice counts the shared arrays allow.
            for (uint32_t slices : {1u, 2u, 16u, 63u, uint32_t(ML_CLUSTER_SLICES)})
                EXPECT_EQ(mismatches(sliceBoundaries(nearPlane, farPlane, slices), nearPlane, farPlane, rng),
                          0u);
            // Linear slices and random increasing ends: the estimate misses, the walks must not.
            std::vector<float> linear(ML_CLUSTER_SLICES), random(ML_CLUSTER_SLICES);
            float t = nearPlane;
            for (uint32_t s = 0; s < ML_CLUSTER_SLICES; ++s) {
                linear[s] = nearPlane + (farPlane - nearPlane) * float(s + 1) / ML_CLUSTER_SLICES;
                t += (farPlane - nearPlane) / ML_CLUSTER_SLICES *
                     std::uniform_real_distribution<float>(0.0f, 2.0f)(rng);
                random[s] = t;
            }
            EXPECT_EQ(mismatches(linear, nearPlane, farPlane, rng), 0u);
            EXPECT_EQ(mismatches(random, nearPlane, farPlane, rng), 0u);
        }
}

} // namespace
} // namespace ml::test
