// Left/right counterparts of skeleton nodes by name, for the mirror helpers of attachments and
// keyposes. Recognised conventions (the first that matches wins): the suffixes ".L"/".R", "_L"/"_R",
// "-L"/"-R", " L"/" R" in either case (Blender, Maya), the prefixes "L_"/"R_" and "l_"/"r_", and
// the words "Left"/"Right", "left"/"right", "LEFT"/"RIGHT" anywhere (Mixamo's "mixamorig:LeftArm").
#pragma once

#include <cstdint>
#include <string>

#include "core/character/skeleton.h"

namespace cagewrap {

// The name with its side swapped; the name itself when it names no side ("spine").
std::string mirror_name(const std::string& name);

// The node whose name is mirror_name(node's name): the node itself when its name has no side,
// -1 when the mirrored name names no node.
int32_t mirror_node(const Skeleton& skeleton, uint32_t node);

}  // namespace cagewrap
