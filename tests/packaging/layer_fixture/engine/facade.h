// Fixture of LayerCheckCatchesCycle: the facade includes the feature (the edge that is allowed).
#pragma once
#include "shadows/feature.h"
