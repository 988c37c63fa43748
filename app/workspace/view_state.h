// What the artist is looking at and working with, apart from the document: the camera, the
// selection and the selection tool's settings, the clip playing, its time and the joints posed on top
// of it. Never undone, never saved in a project.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "app/workspace/camera.h"
#include "app/workspace/soft_selection.h"
#include "core/deform/set_editing.h"
#include "core/geometry/selection.h"
#include "core/rig/fidelity.h"
#include "core/character/animation.h"

namespace cagewrap::app {

// What a click selects and the Select menu acts on (F5..F8).
enum class SelectMode : uint8_t { kCageVertices, kCageFaces, kSkinVertices, kJoints };
inline constexpr int kSelectModes = 4;
const char* select_mode_name(SelectMode m);  // "cage vertices", ...
// The Select menu's operations on the active mode's set.
enum class SelectOp : uint8_t { kAll, kNone, kInvert, kGrow, kShrink, kMirror };
inline constexpr int kSelectOps = 6;
const char* select_op_name(SelectOp op);  // "all", "none", ...

// What plays and the artist's posing on top of it, for the open document (Workspace::set_scene starts
// it on the document's first clip). Scene::update_pose poses the skeleton, the cage and the skin from it.
struct Playback {
  int32_t clip = -1;  // the character's clip; -1: the bind pose
  ClipPlayer player;
  // The artist's posing on top of the clip: per node, a local rotation applied after the clip's
  // (local = clip * override); empty or identity = none.
  std::vector<glm::quat> pose_override;
  bool show_file_skinning = false;  // compare: show the file's own linear blend skinning instead (L)
  // The first of `clips` (paused at 0), or the bind pose when there is none.
  static Playback first_of(const std::vector<Clip>& clips) {
    Playback p;
    if (!clips.empty()) p.clip = 0, p.player = ClipPlayer(clips.front().duration);
    return p;
  }
};

struct ViewState {
  Playback playback;
  Camera camera;
  Selection selection;
  SelectMode mode = SelectMode::kCageVertices;
  SoftSelectionParams soft;  // how a move spreads around the selected vertices
  MirrorParams mirror;       // X-mirror of moves (its tolerance is set from mirror_tolerance_share)
  double mirror_tolerance_share = 1e-3;  // of the skin's bounding-box diagonal
  // Moves edit the reference (rest) cage instead of adding pose offsets: the skin stays and only
  // the skin points near the moved vertices are registered again (Scene::moved_rest).
  bool move_rest = false;
  size_t keypose_set = 0;  // the keypose set Key, mirror and the Rig window act on (index in the document's)
  // The contributing-set edit tool (the Sets window, `set_edit`, brush strokes)
  struct SetEditTool {
    SetEditMode mode = SetEditMode::kRemove;
    bool mirror = false;        // the mirror images of the points, with the mirror faces, too
    double brush_radius = 0.0;  // scene units; 0: 3 % of the skin's size at the first dab
  } sets;
  // The mask brush (app/workspace/workspace_mask.cpp; the Deformers list's Paint, actions mask_*): paints the
  // skin mask of the active deformer layer, or of parametric driver `driver` (>= 0). Each dab moves the
  // weights within `radius` toward `value` by `strength` at the centre, less toward the rim.
  struct MaskTool {
    bool painting = false;
    int driver = -1;          // >= 0: that parametric driver's mask; -1: the active layer's
    float value = 1.0f;       // 1 paints the deformer in, 0 paints it out
    float strength = 0.5f;    // in (0, 1]
    double radius = 0.0;      // scene units; 0: 3 % of the skin's size at the first dab
  } mask;
  // The parametric driver's window: while it is open (`editing`) clicks pick control points and the
  // move gizmo moves `point` (-1: none).
  // With `samples` on, clicks pick the first driver's samples instead (its contributing-set elements,
  // core/deform/patch_binding.h) into `picked`, which the driver's set edits act on with the selected
  // skin vertices (app/workspace/workspace_driver_sets.cpp).
  struct PatchTool {
    bool editing = false;
    int point = -1;
    bool samples = false;
    IndexSet picked;
  } patch;
  // Fidelity to the file's skinning: the heat map on the skin, and the thresholds the warning and
  // the check of every clip judge by.
  struct FidelityView {
    bool heat_map = false;
    FidelityThresholds thresholds;
  } fidelity;
};

}  // namespace cagewrap::app
