// Option groups the commands share, each parsed here once: the scene (--scene, --seed,
// --allow-outside-scene-dir), the frames and view size, the need-based resolution options, and
// comma-separated lists (numbers, static methods, culling modes). A command passes the groups it takes
// to cli::parse beside its own flags, so every command spells, bounds and words them alike.
#pragma once
#include "apps/cli.h"
#include "manylights/manylights.h"
#include "shadows/static/static_types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ml::opts {

// --scene NAME (default night-city) and --seed S (default 1; any 32-bit value).
inline const cli::Flags kSceneFlags{{"--scene", "--seed"}, {}};
// --allow-outside-scene-dir: only the commands that load a glTF through its own folder take it.
inline const cli::Flags kSceneDirFlags{{}, {"--allow-outside-scene-dir"}};
// --seed alone, for a command whose scene is fixed (bench culling).
inline const cli::Flags kSeedFlags{{"--seed"}, {}};
Result<uint32_t> seed(const cli::Args& args);
struct Scene {
    std::string name;
    uint32_t seed = 1;
    bool allowOutside = false;
};
Result<Scene> scene(const cli::Args& args);

// --frames N and --size WxH, with the command's defaults and bounds of --frames.
inline const cli::Flags kViewFlags{{"--frames", "--size"}, {}};
struct ViewDefaults {
    uint32_t frames, minFrames, maxFrames;
    const char* size;
};
struct View {
    uint32_t frames = 0, width = 0, height = 0;
};
Result<View> view(const cli::Args& args, const ViewDefaults& defaults);

// --need-size WxH, --need-min R, --need-samples N, --need-seconds S: the need-based resolution's
// region options (bake --need, bench static --need).
inline const cli::Flags kNeedFlags{{"--need-size", "--need-min", "--need-samples", "--need-seconds"}, {}};
struct Need {
    uint32_t width = 0, height = 0, minRes = 64, samples = 120, seconds = 60;
};
Result<Need> need(const cli::Args& args, const std::string& defaultSize);
// --need-min must be a power of two (the need picks powers of two between it and the cap).
Result<void> checkNeedMin(uint32_t minRes);

// --max-memory MIB: the peak memory a command may plan for (check vsm, bake). The command estimates
// its peak from its arguments before any heavy work and refuses past the limit, printing both.
// Default: half of this machine's physical memory (sysconf), so a run leaves room for the rest.
inline const cli::Flags kMemoryFlags{{"--max-memory"}, {}};
uint64_t machineMemory();                          // bytes of physical memory
Result<uint64_t> maxMemory(const cli::Args& args); // bytes
// "COMMAND: estimated peak memory X MiB (what), limit Y MiB" on stderr; past the limit a one-line error
// naming both and --max-memory.
Result<void> checkMemory(const char* command, uint64_t estimate, uint64_t limit, const std::string& what);

// Comma-separated lists: no empty item and at least one; each message names the flag.
Result<std::vector<std::string>> splitList(const std::string& flag, const std::string& text);
Result<std::vector<uint32_t>> uintList(const std::string& flag, const std::string& text, uint32_t lo,
                                       uint32_t hi);
// Static methods; "none" is refused (nothing to measure or bake).
Result<std::vector<StaticMethod>> methodList(const std::string& flag, const std::string& text);
Result<std::vector<CullingMode>> cullingList(const std::string& flag, const std::string& text);

// A number in [lo, hi]: the whole text must parse (strtod); nan and inf are refused.
Result<float> number(const std::string& flag, const std::string& text, float lo, float hi);

} // namespace ml::opts
