// The consistency check of a binding's tables, for one read from a file or built by hand.
#pragma once

#include "core/base/result.h"
#include "core/deform/binding.h"

namespace cagewrap {

// Checks a binding's tables against each other (kParse) and every index against its table
// (kIndexOutOfRange): element corners against the cage vertices, stencil ids against the elements
// (basic, clamped) or the cage vertices (extended), fallback points against the skin points and
// fallback elements against the elements. Messages name the entry, the bad index and the table size.
// load_binding and Deformer::create both call it.
Status validate_binding(const Binding& binding);

}  // namespace cagewrap
