// Demo and benchmark outputs: Chrome trace (profile.json), per-pass CSV (frames.csv), stats.json.
#pragma once
#include "manylights/manylights.h"

#include <string>
#include <vector>

namespace ml {

struct RunInfo {
    std::string scene, culling, device;
    uint32_t width = 0, height = 0, frames = 0, seed = 0;
    std::string memoryPlacement; // DeviceInfo::memoryPlacement
};

Result<void> writeProfile(const std::string& path, const std::vector<FrameReport>& reports);
Result<void> writeFramesCsv(const std::string& path, const std::vector<FrameReport>& reports);
Result<void> writeStats(const std::string& path, const RunInfo& info,
                        const std::vector<FrameReport>& reports);

} // namespace ml
