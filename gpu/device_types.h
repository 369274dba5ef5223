// The device API types are public (manylights/device.h); code that includes them by this path gets them
// from here.
#pragma once
#include "manylights/device.h"
