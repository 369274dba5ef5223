// The conventional entry point for a host: #include <manylights/manylights.h>. In the source tree it
// forwards to engine/manylights.h; the installed copy (cmake/install.cmake) forwards to
// <manylights/engine/manylights.h>, whose includes are rewritten to <manylights/...>.
#pragma once
#include "engine/manylights.h"
