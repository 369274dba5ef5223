// The options the virtual-shadow-map commands share (`check vsm`, `bench vsm`, `bench flicker --vsm`):
// scene, camera path, frames, size, lights, seed, bake and the maps' resolution, page size, pool and
// texels per pixel (--vsm-texels).
// One parser, so the commands agree on names, ranges and messages; each adds its own flags.
#pragma once
#include "apps/cli.h"
#include "host/vsm_session.h"

#include <set>
#include <string>

namespace ml {

// The shared valued flags, to merge into a command's own for cli::parse.
std::set<std::string> vsmSessionFlags(std::set<std::string> own);

struct VsmArgDefaults {
    uint32_t frames = 10, minFrames = 1;
    const char* size = "320x180";
    uint32_t resolution = 1024;
};

// Parses the shared flags into session options (vsm enabled, probe pass off) and the frame count; a
// one-line reason naming the flag otherwise.
Result<VsmSessionOptions> vsmSessionOptions(const cli::Args& args, const VsmArgDefaults& defaults,
                                            uint32_t& frames);

} // namespace ml
