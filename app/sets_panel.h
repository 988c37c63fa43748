// The editor's Contributing sets window (paper section 5, Figure 5): see which cage elements drive
// which skin points (a heat map of the selected cage faces' influence with a legend, set sizes,
// points with empty, edited or outside sets, what automatic separation kept apart; the members and
// weights of a selected skin point) and edit them (remove / add / only / reset the selected faces'
// elements on the selected skin points, or paint them with a brush measured along the skin), with X
// mirroring. Edits re-register only the touched points, so the skin follows at once; one undo step
// per applied edit or brush stroke.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "core/geometry/selection.h"
#include "core/document/set_editing.h"
#include "core/document/skin_brush.h"

namespace cagewrap::app {

enum class SetMap : uint8_t { kNone, kInfluence, kSize, kFlags, kSeparated };

class SetsPanel {
 public:
  bool& visible() { return visible_; }
  void draw(Scene& scene, const Selection& selection, const EditorHooks& hooks);

  // Per skin vertex colours for the current map (empty: none). Recomputed when its inputs change.
  const std::vector<glm::vec4>& colors(const Scene& scene, const Selection& selection);
  // Cage polygons to highlight: the members of the selected skin point's set.
  std::vector<uint32_t> highlighted_faces(const Scene& scene, const Selection& selection) const;
  // The same with each face's share of the point's weights (its elements' normalized weights summed).
  std::vector<std::pair<uint32_t, float>> member_face_weights(const Scene& scene, const Selection& selection) const;

  // Applies the current mode with the selected cage faces to `points` (and their mirror images when
  // mirroring), live: the document in scene.live when a stroke is under way, else one undo step.
  bool apply(Scene& scene, const Selection& selection, const IndexSet& points, const EditorHooks& hooks);
  SetEditMode& mode() { return mode_; }
  bool& mirror() { return mirror_; }
  SetMap& map() { return map_; }

  // Brush strokes (the editor feeds the mouse): painting is on while the window's Paint box is.
  bool painting() const { return visible_ && paint_; }
  // Brush radius in screen pixels instead of scene units (the editor converts at each dab's depth).
  bool screen_radius() const { return screen_radius_; }
  double radius_pixels() const { return radius_pixels_; }
  // "Select limb": the cage faces whose corners all follow the selected joints (by the attachment).
  static IndexSet limb_faces(const Scene& scene, const IndexSet& joints);
  bool take_select_limb_request() { return std::exchange(select_limb_, false); }
  double brush_radius() const { return brush_radius_; }
  void set_brush_radius(double r) { brush_radius_ = r; }
  void begin_stroke(Scene& scene);
  // A dab at the hit point on skin triangle `triangle` (positions: what the brush measures on).
  void dab(Scene& scene, const Selection& selection, uint32_t triangle, const glm::dvec3& hit, const EditorHooks& hooks);
  void end_stroke(Scene& scene);

 private:
  bool visible_ = false, paint_ = false, mirror_ = false, screen_radius_ = false, select_limb_ = false;
  double radius_pixels_ = 30.0;
  SetEditMode mode_ = SetEditMode::kRemove;
  SetMap map_ = SetMap::kInfluence;
  double brush_radius_ = 0.0;  // scene units; 0 = set from the size on first use
  bool stroking_ = false;
  SkinBrush brush_;
  std::string colors_key_;
  std::vector<glm::vec4> colors_;
  std::optional<MirrorMap> point_mirror_, face_mirror_;
  const Cage* mirror_cage_ = nullptr;
  void ensure_mirror(const Scene& scene);
};

}  // namespace cagewrap::app
