// DAG-MH value section encoder (format version 6): chunks of 32 values, each split into two classes with
// a plane each, the planes' slopes shared through a slope table; a planar tree's plane values go to a
// planar class (indices into the plane table). Layout and decoder: dagmh.h
// (dagmhValue), docs/dagmh-encoding.md. Internal to the DAG-MH encoder (dagmh.cpp).
#pragma once
#include "io/result.h"
#include "shadows/static/dual_depth.h"

#include <cstdint>
#include <vector>

namespace ml::dagval {

// One value of the MH tree in depth-first order: its node's interval [lo, hi] and the full-resolution
// texel (px, py) at the top-left corner of the node's cell (the lookup forms the same corner); `plane`
// (1-based into the tree's planes) for a planar-only node (lo > hi), whose value is that plane, else 0.
struct Val {
    uint32_t lo, hi, px, py, plane = 0;
};

struct Stats {
    uint64_t rawClasses = 0, factors = 0, factorBits = 0, planarValues = 0;
};

struct Sections {
    std::vector<uint32_t> chunks;  // chunkWords(planes) per chunk
    std::vector<uint32_t> slopes;  // kSlopeWords per entry; entry 0 is the zero slope
    std::vector<uint32_t> planes;  // kPlaneWords per entry, in the order of first use
    std::vector<uint32_t> factors; // bit stream
};

// Encodes the values; every value decodes (dagmhValue's arithmetic) into its interval, which the encoder
// checks per class before it keeps a code (raw 32-bit values otherwise); a plane value becomes its plane.
Result<Sections> encodeValues(const std::vector<Val>& vals, const std::vector<DepthPlane>& planes,
                              Stats* stats);

} // namespace ml::dagval
