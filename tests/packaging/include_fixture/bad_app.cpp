// Input of the test PublicApiIncludesCatchesInternal: an app that reaches into the module's internals.
// The check must name this file, line 4 and the header. Not compiled.
#include "manylights/manylights.h"
#include "engine/module_impl.h"
#include <vector>
