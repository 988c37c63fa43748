// The editor's panel layout: the outliner on the left, properties on the right, timeline and log
// below, the 3-D view in what they leave free. The panels' edges are splitters (drag them); the
// sizes are remembered in the preferences. The GUI tests read the default layout from here.
#pragma once

#include <algorithm>

namespace cagewrap::app {

struct ViewRect {
  float x = 0, y = 0, w = 1, h = 1;  // window pixels, top-left origin
};

struct PanelLayout {
  static constexpr float kMenuHeight = 19.0f;  // the main menu bar
  static constexpr float kMinPanel = 160.0f, kMinBottom = 100.0f;
  static constexpr float kMinView = 320.0f;    // the view never gets narrower or lower than this
  float left = 260.0f;    // the outliner's width
  float right = 340.0f;   // the properties' width
  float bottom = 170.0f;  // the timeline's and log's height
  float log_share = 0.4f; // the log's share of the bottom row

  // The sizes kept within a window of w x h: each panel at least its minimum, the view at least
  // kMinView (the panels give way, the left and right alike).
  PanelLayout fitted(float w, float h) const {
    PanelLayout p = *this;
    p.left = std::max(kMinPanel, p.left);
    p.right = std::max(kMinPanel, p.right);
    const float spare_w = w - kMinView;
    if (p.left + p.right > spare_w) {
      const float scale = std::max(0.0f, spare_w) / (p.left + p.right);
      p.left *= scale;
      p.right *= scale;
    }
    p.bottom = std::clamp(p.bottom, std::min(kMinBottom, h * 0.3f), std::max(kMinBottom, h - kMenuHeight - kMinView * 0.5f));
    p.log_share = std::clamp(p.log_share, 0.15f, 0.85f);
    return p;
  }
  // The 3-D view in a window of w x h (the layout fitted first).
  ViewRect view(float w, float h) const {
    const PanelLayout p = fitted(w, h);
    return {p.left, kMenuHeight, std::max(1.0f, w - p.left - p.right), std::max(1.0f, h - kMenuHeight - p.bottom)};
  }
};

}  // namespace cagewrap::app
