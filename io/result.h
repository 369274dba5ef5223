// Result<T> is a public API type (manylights/result.h); the io library and the code below the module that
// includes it by this path (the static shadow library, the bake driver) get it from here.
#pragma once
#include "manylights/result.h"
