// Comma-separated lists of unsigned numbers for bench options (`--res 4096,8192`, `--regions 1,2,3`), each
// item range-checked with the flag named in the error.
#pragma once
#include "apps/cli.h"

#include <sstream>

namespace ml::cli {

inline Result<std::vector<uint32_t>> parseUintList(const std::string& flag, const std::string& text,
                                                   uint32_t lo, uint32_t hi) {
    std::vector<uint32_t> out;
    std::stringstream ss(text);
    for (std::string item; std::getline(ss, item, ',');) {
        auto v = parseUint(flag, item, lo, hi);
        if (!v) return fail(v.error());
        out.push_back(v.value());
    }
    if (out.empty()) return fail(flag + ": empty list");
    return out;
}

} // namespace ml::cli
