// What the artist is looking at and working with, apart from the document: the camera, the
// selection and the selection tool's settings. Never undone, never saved in a project. (The clip,
// its time and the pose overrides are per-document view state kept in Scene, app/workspace/scene.h.)
#pragma once

#include <cstdint>

#include "app/workspace/camera.h"
#include "app/workspace/soft_selection.h"
#include "core/geometry/selection.h"

namespace cagewrap::app {

// What a click selects and the Select menu acts on (F5..F8).
enum class SelectMode : uint8_t { kCageVertices, kCageFaces, kSkinVertices, kJoints };
inline constexpr int kSelectModes = 4;
const char* select_mode_name(SelectMode m);  // "cage vertices", ...
// The Select menu's operations on the active mode's set.
enum class SelectOp : uint8_t { kAll, kNone, kInvert, kGrow, kShrink, kMirror };
inline constexpr int kSelectOps = 6;
const char* select_op_name(SelectOp op);  // "all", "none", ...

struct ViewState {
  Camera camera;
  Selection selection;
  SelectMode mode = SelectMode::kCageVertices;
  SoftSelectionParams soft;  // how a move spreads around the selected vertices
  MirrorParams mirror;       // X-mirror of moves (its tolerance is set from mirror_tolerance_share)
  double mirror_tolerance_share = 1e-3;  // of the skin's bounding-box diagonal
  // Moves edit the reference (rest) cage instead of adding pose offsets: the skin stays and only
  // the skin points near the moved vertices are registered again (Scene::moved_rest).
  bool move_rest = false;
};

}  // namespace cagewrap::app
