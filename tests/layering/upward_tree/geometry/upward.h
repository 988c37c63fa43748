// A geometry header that reaches up to the rig: the layer check must refuse it.
#pragma once
#include "core/rig/rig.h"
#include "core/base/result.h"
