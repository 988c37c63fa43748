// The rig may include any lower layer: the layer check accepts this file.
#pragma once
#include "core/geometry/mesh.h"
