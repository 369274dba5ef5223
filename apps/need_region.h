// The camera region of `bake --need` and `bench static --need`: where the camera can be, as camera
// samples for the need estimator (bake/need.h).
//   path:static|drive|orbit  the named camera path (scenes/camera_path.h) sampled at `samples` times
//                            evenly over [0, seconds): position, view direction and field of view;
//   box:X0,Y0,Z0,X1,Y1,Z1    a grid of k^3 positions in the box (k = the cube root of `samples`,
//                            rounded, at least 1), looking anywhere.
#pragma once
#include "manylights/result.h"
#include "scenes/scene.h"
#include "bake/need.h"

#include <string>
#include <vector>

namespace ml {

struct NeedRegion {
    std::string text;                // stored in the bake file: "path:drive, 120 samples over 60 s"
    std::vector<NeedCamera> cameras; // the estimator's samples
    std::vector<Camera> views;       // paths: the camera of each sample (bench static --need renders them)
};

Result<NeedRegion> makeNeedRegion(const Scene& scene, const std::string& spec, uint32_t samples,
                                  double seconds, uint32_t width, uint32_t height);

// estimateNeed with occlusion from Embree rays (static geometry), over the lights of `lights` that
// bakeScene would bake (the others are left out: bake lists them as skipped).
Result<std::vector<LightNeed>> estimateNeedWithRays(const Scene& scene, const std::vector<uint32_t>& lights,
                                                    const NeedRegion& region, const NeedOptions& options);

} // namespace ml
