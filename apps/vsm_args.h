// The options the virtual-shadow-map commands share (`check vsm`, `bench vsm`, `bench flicker --vsm`):
// scene, camera path, frames, size, lights, seed, bake and the maps' resolution, page size, pool and
// texels per pixel (--vsm-texels); the maps' group and --vsm-raster are the demo's too.
// One parser, so the commands agree on names, ranges and messages; each adds its own flags.
#pragma once
#include "apps/options.h"
#include "host/vsm_session.h"

#include <string>

namespace ml {

// --vsm-res, --vsm-page, --vsm-pool: the virtual maps' side, page side and pool of pages; --vsm-mark
// pixel|cluster: how pages are marked (VsmSettings::clusterMarking).
inline const cli::Flags kVsmMapFlags{{"--vsm-res", "--vsm-page", "--vsm-pool", "--vsm-mark"}, {}};
// The session's own flags; its commands take opts::kSceneFlags, opts::kViewFlags and kVsmMapFlags too.
inline const cli::Flags kVsmSessionFlags{{"--path", "--lights", "--bake", "--vsm-texels"}, {}};

// A VSM command's flags: the scene, view, maps' and session's groups and its own.
Result<cli::Args> parseVsmCommand(int argc, char** argv, int first, const cli::Flags& own);

struct VsmArgDefaults {
    uint32_t frames = 10, minFrames = 1;
    const char* size = "320x180";
    uint32_t resolution = 1024;
};

// Parses the maps' group into `vsm` (resolution default `resolution`); a one-line reason otherwise.
Result<void> vsmMapOptions(const cli::Args& args, uint32_t resolution, VsmSettings& vsm);
// --vsm-raster auto|mesh|vertex (default `fallback`).
Result<VsmRaster> vsmRaster(const cli::Args& args, const char* fallback = "auto");

// Parses the shared flags into session options (vsm enabled, probe pass off) and the frame count; a
// one-line reason naming the flag otherwise.
Result<VsmSessionOptions> vsmSessionOptions(const cli::Args& args, const VsmArgDefaults& defaults,
                                            uint32_t& frames);

} // namespace ml
