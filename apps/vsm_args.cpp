#include "apps/vsm_args.h"

#include "shaders/shared/config.h"

#include <cstdlib>
#include <tuple>

namespace ml {

std::set<std::string> vsmSessionFlags(std::set<std::string> own) {
    for (const char* f : {"--scene", "--path", "--frames", "--size", "--lights", "--seed", "--bake",
                          "--vsm-res", "--vsm-page", "--vsm-pool", "--vsm-texels"})
        own.insert(f);
    return own;
}

Result<VsmSessionOptions> vsmSessionOptions(const cli::Args& args, const VsmArgDefaults& d,
                                            uint32_t& frames) {
    auto path = parseCameraPath(args.get("--path", "drive"));
    auto count =
        cli::parseUint("--frames", args.get("--frames", std::to_string(d.frames)), d.minFrames, 100000);
    auto size = cli::parseSize("--size", args.get("--size", d.size));
    auto lights = cli::parseUint("--lights", args.get("--lights", "256"), 1, ML_MAX_LIGHTS);
    auto seed = cli::parseUint("--seed", args.get("--seed", "1"), 0, 0xFFFFFFFFu);
    auto res = cli::parseUint("--vsm-res", args.get("--vsm-res", std::to_string(d.resolution)), 256, 16384);
    auto page = cli::parseUint("--vsm-page", args.get("--vsm-page", "64"), 32, 128);
    auto pool = cli::parseUint("--vsm-pool", args.get("--vsm-pool", "4096"), 1, 1u << 20);
    for (const std::string* e : {&path.error(), &count.error(), &size.error(), &lights.error(), &seed.error(),
                                 &res.error(), &page.error(), &pool.error()})
        if (!e->empty()) return fail(*e);
    // Texels per pixel footprint: a power of two from 1/4 to 8 (VsmSettings::texelsPerPixel).
    const std::string texels = args.get("--vsm-texels", "1");
    char* end = nullptr;
    const float texelsPerPixel = std::strtof(texels.c_str(), &end);
    if (texels.empty() || *end || !validTexelsPerPixel(texelsPerPixel))
        return fail("--vsm-texels: '" + texels + "' is not 0.25, 0.5, 1, 2, 4 or 8");
    VsmSessionOptions o;
    o.scene = args.get("--scene", "night-city");
    o.lights = lights.value();
    o.seed = seed.value();
    std::tie(o.width, o.height) = size.value();
    o.path = path.value();
    o.bake = args.get("--bake", "");
    o.module.vsm.enabled = true;
    o.module.vsm.resolution = res.value();
    o.module.vsm.pageSize = page.value();
    o.module.vsm.poolPages = pool.value();
    o.module.vsm.texelsPerPixel = texelsPerPixel;
    frames = count.value();
    return o;
}

} // namespace ml
