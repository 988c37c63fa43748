// The editor's Contributing sets window (paper section 5, Figure 5): see which cage elements drive
// which skin points (a heat map of the selected cage faces' influence with a legend, set sizes,
// points with empty, edited or outside sets, what automatic separation kept apart; the members and
// weights of a selected skin point) and edit them (remove / add / only / reset the selected faces'
// elements on the selected skin points, or paint them with a brush measured along the skin), with X
// mirroring. The edits are the workspace's (app/workspace/workspace_sets.cpp): they re-register only
// the touched points, so the skin follows at once; one undo step per applied edit or brush stroke.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "app/workspace/workspace.h"
#include "core/geometry/selection.h"
#include "core/deform/set_editing.h"
#include "core/document/skin_brush.h"

namespace cagewrap::app {

enum class SetMap : uint8_t { kNone, kInfluence, kSize, kFlags, kSeparated };

class SetsPanel {
 public:
  bool& visible() { return visible_; }
  void draw(Workspace& ws);

  // Per skin vertex colours for the current map (empty: none). Recomputed when its inputs change.
  const std::vector<glm::vec4>& colors(const Scene& scene, const Selection& selection);
  // Cage polygons to highlight: the members of the selected skin point's set.
  std::vector<uint32_t> highlighted_faces(const Scene& scene, const Selection& selection) const;
  // The same with each face's share of the point's weights (its elements' normalized weights summed).
  std::vector<std::pair<uint32_t, float>> member_face_weights(const Scene& scene, const Selection& selection) const;

  SetMap& map() { return map_; }

  // Brush strokes (the editor feeds the mouse): painting is on while the window's Paint box is.
  bool painting() const { return visible_ && paint_; }
  // Brush radius in screen pixels instead of scene units (the editor converts at each dab's depth).
  bool screen_radius() const { return screen_radius_; }
  double radius_pixels() const { return radius_pixels_; }
  // "Select limb" was pressed (the editor runs select_limb_faces).
  bool take_select_limb_request() { return std::exchange(select_limb_, false); }

 private:
  bool visible_ = false, paint_ = false, screen_radius_ = false, select_limb_ = false;
  double radius_pixels_ = 30.0;
  SetMap map_ = SetMap::kInfluence;
  std::string colors_key_;
  std::vector<glm::vec4> colors_;
};

}  // namespace cagewrap::app
