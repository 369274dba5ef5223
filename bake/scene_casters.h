// A scene's static casters as the world-space triangle soup the static shadow renderers take
// (CasterTriangles, shadows/static/raster_dual.h). Here, above the static shadow library, so that the
// library needs no scene type.
#pragma once
#include "scenes/scene.h"
#include "shadows/static/raster_dual.h"

namespace ml {

// The static (non-dynamic) instances of a scene as world-space triangles. Instances whose transform
// mirrors (negative determinant) get their winding swapped so that front faces stay front faces.
CasterTriangles castersFromScene(const Scene& scene);

} // namespace ml
