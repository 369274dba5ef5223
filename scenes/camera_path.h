// Deterministic named camera paths for the demo, the benchmarks and the tests: the camera at time t is a
// pure function of the scene and t, so every run of a path sees the same frames.
//   static  the scene's own camera;
//   drive   behind and above a car (the one whose loop passes closest to the scene camera's target),
//           looking ahead along its heading (night city: its headlights and the lamps it passes);
//   orbit   a circle around the scene's centre, one turn per minute, looking at the centre.
#pragma once
#include "scenes/scene.h"

#include <string>

namespace ml {

enum class CameraPath : uint32_t { Static, Drive, Orbit };
Result<CameraPath> parseCameraPath(const std::string& name); // one-line error naming the choices
const char* cameraPathName(CameraPath path);

// The camera of `path` at `seconds` (after animateScene(scene, seconds) placed the cars). Drive needs a
// car: an error names the scene when it has none.
Result<Camera> cameraOnPath(const Scene& scene, CameraPath path, double seconds);

} // namespace ml
