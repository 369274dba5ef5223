// Shared pieces of the static shadow formats (SM, MH, MMH, DAG-MH): the checksum every buffer carries,
// the per-part byte breakdown, and the bit helpers the GLSL-portable decoders use.
//
// Every format is one flat std::vector<uint32_t> (an SSBO `uint data[]` on the GPU) that starts with a
// small header of 32-bit words. Word 0 is a magic number naming the format, word 1 the version, and one
// header word holds a checksum over all other words of the buffer: validate() recomputes it, so any
// single flipped bit anywhere is rejected, and then walks every offset and count so that a forged
// checksum still cannot make a lookup read outside the buffer.
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>

namespace ml::stat {

// Word-wise FNV-1a. Each step (h ^ w) * prime is a bijection of h for a fixed w and of w for a fixed h,
// so changing any single word (any number of its bits) always changes the result.
inline uint32_t checksumWords(const uint32_t* data, size_t size, size_t skipIndex) {
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < size; ++i) h = (h ^ (i == skipIndex ? 0u : data[i])) * 16777619u;
    return h;
}

// Bytes per part of an encoded buffer. `values` is every stored depth value (MH/MMH node values, SM
// texels, DAG-MH chunk infos); `factors` is the DAG-MH bit-packed factor stream.
struct ByteBreakdown {
    uint64_t header = 0, skipList = 0, bounds = 0, nodes = 0, treelets = 0, values = 0, factors = 0;
    uint64_t total() const { return header + skipList + bounds + nodes + treelets + values + factors; }
};

// GLSL twins: bitCount(x), and reading a `bits`-wide field (0..32) at a bit position of a word array.
inline uint32_t popc(uint32_t x) {
    return uint32_t(std::popcount(x));
}
inline uint32_t lowMask(uint32_t bits) {
    return bits >= 32u ? 0xFFFFFFFFu : ((1u << bits) - 1u);
}

// Midpoint of [lo, hi] without overflow, rounded down.
inline uint32_t midpoint(uint32_t lo, uint32_t hi) {
    return lo + (hi - lo) / 2u;
}

constexpr uint32_t fourcc(char a, char b, char c, char d) {
    return uint32_t(uint8_t(a)) | uint32_t(uint8_t(b)) << 8 | uint32_t(uint8_t(c)) << 16 |
           uint32_t(uint8_t(d)) << 24;
}

} // namespace ml::stat
