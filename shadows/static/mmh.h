// MMH: merged multiresolution hierarchy (Scandolo, Bauszat, Eisemann 2016,
// ../shared/papers/mmh-scandolo-bauszat-eisemann-2016.txt, section 3).
//
// Starts from the MH tree (mh.h) and merges subtrees of equal topology whose intervals, taken relative
// to each subtree's base value, intersect node by node; the earlier subtree (depth-first order) is
// dropped and its parent's child offset redirected to the later one, so offsets stay positive.
//   - Values are relative: a valued node stores value - (value of its nearest valued ancestor), mod
//     2^32; the root stores its absolute value. The lookup adds them up along the path (paper Alg. 1).
//   - Subtree = the children of an inner node N and everything below (N's own value is not part of
//     it). Its base a_N = N's value, or its nearest valued ancestor's when N is empty.
//   - Topology hash per subtree (child types of every node), one hash table per subtree height, each
//     collision list in depth-first order (sec. 3.1). Heights are processed from tall to short.
//   - Local matching window (default 1000, sec. 3.2): list[i] (back to front) is tested against
//     list[i+1 .. i+window]. Early rejection by interval statistics (min/max of the lower and upper
//     bounds relative to the base); the full test walks both subtrees and compares topology exactly.
//   - Offset check: the redirected offset is bounded by the distance in the unmerged layout, which
//     must fit 24 bits (a redirect never needs a far group; the serializer may still make it far when
//     the record is version 2 and the offset passes 23 bits).
//   - Merge: every node X' of the kept subtree gets J(X') := J(X') n (J(X) - a_A + a_B), in int64.
// Why relative values stay lossless when shared: before the pass of height h, every node of height >= h
// has its final interval J (only merges of taller subtrees change it), so its value is fixed then as the
// midpoint of J. Inside a shared subtree the cumulative offset R_X = value(X) - base is the same for all
// sharers; sharer k decodes base_k + R_X, and J(X') was intersected with (I_k(X) - base_k + base_B) for
// every sharer, so base_k + R_X lies in I_k(X). The exhaustive tests check this on every texel.
//
// Serialized layout: the MH layout (mh.h) with magic 'MMH1'; values are relative; shared groups are
// written once and reached by several headers.
#pragma once
#include "shadows/static/mh.h"

namespace ml {

struct MmhOptions {
    uint32_t window = 1000; // local matching window in each collision list
    mhfmt::Layout layout;   // child group placement (mh.h); tests force far groups with it
};

struct MmhStats {
    uint64_t candidates = 0, rejectedStats = 0, rejectedOffset = 0, rejectedFull = 0, merges = 0;
    uint64_t droppedNodes = 0;
};

Result<std::vector<uint32_t>> encodeMMH(const MhTree& tree, const MmhOptions& options = {},
                                        MmhStats* stats = nullptr);
Result<std::vector<uint32_t>> encodeMMH(const DualDepthMap& map, const MmhOptions& options = {});
Result<void> validateMMH(const uint32_t* data, size_t size);
stat::ByteBreakdown breakdownMMH(const uint32_t* data, size_t size);

// The lookups: MH's descent adding relative values, one source text with the GLSL decoders
// (shaders/static/mh_descent.h, compiled by mh.h). Only valid on a buffer validateMMH accepted.
// mmhLookupLevel(data, base, x, y, steps): the map at the level `steps` below the root.
using mhtwin::mmhLookup;
using mhtwin::mmhLookupLevel;
inline uint32_t mmhLookup(const uint32_t* data, uint32_t x, uint32_t y) {
    return mmhLookup(data, 0u, x, y);
}

} // namespace ml
