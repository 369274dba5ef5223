// Fixture of LayerCheckCatchesCycle: a feature header that includes the facade above it.
#pragma once
#include "engine/facade.h"
