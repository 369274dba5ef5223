#include "apps/vsm_args.h"

#include "shaders/shared/config.h"

#include <cstdlib>

namespace ml {

Result<cli::Args> parseVsmCommand(int argc, char** argv, int first, const cli::Flags& own) {
    return cli::parse(argc, argv, first,
                      {opts::kSceneFlags, opts::kViewFlags, kVsmMapFlags, kVsmSessionFlags, own});
}

Result<void> vsmMapOptions(const cli::Args& args, uint32_t resolution, VsmSettings& vsm) {
    auto res = cli::parseUint("--vsm-res", args.get("--vsm-res", std::to_string(resolution)), 256, 16384);
    auto page = cli::parseUint("--vsm-page", args.get("--vsm-page", "64"), 32, 128);
    auto pool = cli::parseUint("--vsm-pool", args.get("--vsm-pool", "4096"), 1, 1u << 20);
    for (const std::string* e : {&res.error(), &page.error(), &pool.error()})
        if (!e->empty()) return fail(*e);
    const std::string mark = args.get("--vsm-mark", VsmSettings{}.clusterMarking ? "cluster" : "pixel");
    if (mark != "pixel" && mark != "cluster")
        return fail("--vsm-mark: '" + mark + "' is not pixel or cluster");
    vsm.clusterMarking = mark == "cluster";
    vsm.resolution = res.value();
    vsm.pageSize = page.value();
    vsm.poolPages = pool.value();
    return {};
}

Result<VsmRaster> vsmRaster(const cli::Args& args, const char* fallback) {
    VsmRaster raster = VsmRaster::Auto;
    const std::string word = args.get("--vsm-raster", fallback);
    if (!parseVsmRaster(word, raster))
        return fail("--vsm-raster: '" + word + "' is not auto, mesh or vertex");
    return raster;
}

Result<VsmSessionOptions> vsmSessionOptions(const cli::Args& args, const VsmArgDefaults& d,
                                            uint32_t& frames) {
    VsmSessionOptions o;
    auto path = parseCameraPath(args.get("--path", "drive"));
    auto view = opts::view(args, {d.frames, d.minFrames, 100000, d.size});
    auto lights = cli::parseUint("--lights", args.get("--lights", "256"), 1, ML_MAX_LIGHTS);
    auto scene = opts::scene(args);
    auto maps = vsmMapOptions(args, d.resolution, o.module.vsm);
    for (const std::string* e :
         {&path.error(), &view.error(), &lights.error(), &scene.error(), &maps.error()})
        if (!e->empty()) return fail(*e);
    // Texels per pixel footprint: a power of two from 1/4 to 8 (VsmSettings::texelsPerPixel).
    const std::string texels = args.get("--vsm-texels", "1");
    char* end = nullptr;
    const float texelsPerPixel = std::strtof(texels.c_str(), &end);
    if (texels.empty() || *end || !validTexelsPerPixel(texelsPerPixel))
        return fail("--vsm-texels: '" + texels + "' is not 0.25, 0.5, 1, 2, 4 or 8");
    o.scene = scene->name;
    o.lights = lights.value();
    o.seed = scene->seed;
    o.width = view->width;
    o.height = view->height;
    o.path = path.value();
    o.bake = args.get("--bake", "");
    o.module.vsm.enabled = true;
    o.module.vsm.texelsPerPixel = texelsPerPixel;
    frames = view->frames;
    return o;
}

} // namespace ml
