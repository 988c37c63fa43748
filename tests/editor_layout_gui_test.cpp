// The editor's layout at two window sizes (issue 20): floating windows open inside the 3-D view and
// never beyond the screen, the panel sizes (splitters) are remembered between runs, and the view
// says what the View toggles hide. The figures come from the editor's own `log_layout` action.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "tests/gui_harness.h"

namespace {

namespace fs = std::filesystem;
using namespace cagewrap::test;

struct Rect {
  std::string name;
  float x = 0, y = 0, w = 0, h = 0;
};
struct Layout {
  Rect view;
  float display_w = 0, display_h = 0;
  std::vector<Rect> windows;
};

// The last `log_layout` of a run's log.
Layout parse_layout(const std::string& log) {
  Layout out;
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    Rect r;
    char name[200] = {0};
    if (std::sscanf(line.c_str(), "layout: view %f %f %f %f, display %f %f", &r.x, &r.y, &r.w, &r.h, &out.display_w, &out.display_h) == 6) {
      out.view = r;
      out.windows.clear();
    } else if (std::sscanf(line.c_str(), "layout: window '%199[^']' %f %f %f %f", name, &r.x, &r.y, &r.w, &r.h) == 5) {
      r.name = name;
      out.windows.push_back(r);
    }
  }
  return out;
}

EditorRun run_offscreen(const std::string& name, const std::string& script, int w, int h, const fs::path& config) {
  return run_editor_script(gui_test_dir(), name, script, "--offscreen --width " + std::to_string(w) + " --height " + std::to_string(h),
                           config);
}
// A window under Xvfb: unlike an offscreen run, it remembers the view settings when it closes.
EditorRun run_windowed(const std::string& name, const std::string& script, int w, int h, const fs::path& config) {
  return run_editor_script(gui_test_dir(), name, script, "--width " + std::to_string(w) + " --height " + std::to_string(h), config);
}

TEST(EditorLayoutGui, WindowsOpenInsideTheViewAtTwoSizes) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  for (auto [w, h] : {std::pair{1280, 720}, std::pair{1920, 1080}}) {
    const std::string name = "layout_" + std::to_string(w);
    const fs::path config = gui_test_dir() / (name + "_config");
    fs::remove_all(config);
    const EditorRun run = run_offscreen(name,
                                        "wait 4\nmode joints\nselect_joint 5\nexport_window\nrig_panel\nsets_panel influence\n"
                                        "sim_panel\npatch_panel\nwait 4\nlog_layout\n",
                                        w, h, config);
    ASSERT_EQ(run.status, 0) << run.log;
    const Layout l = parse_layout(run.log);
    ASSERT_EQ(l.display_w, w) << run.log;
    EXPECT_EQ(l.view.x, kDefaultLayout.left);
    EXPECT_EQ(l.view.w, w - kDefaultLayout.left - kDefaultLayout.right);
    EXPECT_EQ(l.windows.size(), 5u) << run.log;
    for (const Rect& r : l.windows) {
      EXPECT_GE(r.x, l.view.x - 0.5f) << r.name << " at " << w;
      EXPECT_GE(r.y, l.view.y - 0.5f) << r.name << " at " << w;
      EXPECT_LE(r.x + r.w, l.view.x + l.view.w + 0.5f) << r.name << " at " << w;
      EXPECT_LE(r.y + r.h, l.view.y + l.view.h + 0.5f) << r.name << " at " << w;
    }
  }
}

TEST(EditorLayoutGui, PanelSizesAreRememberedAndHiddenThingsAreSaid) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path config = gui_test_dir() / "layout_remember_config";
  fs::remove_all(config);
  EditorRun first = run_windowed("layout_remember_a", "wait 3\npanels 300 380 210\ntoggle cage\nwait 2\nlog_layout\n", 1280, 720, config);
  ASSERT_EQ(first.status, 0) << first.log;
  Layout a = parse_layout(first.log);
  EXPECT_EQ(a.view.x, 300);
  EXPECT_EQ(a.view.w, 1280 - 300 - 380);
  EXPECT_EQ(a.view.h, 720 - cagewrap::app::PanelLayout::kMenuHeight - 210);
  // the next run starts with them, and says that the cage is hidden
  EditorRun second = run_windowed("layout_remember_b", "wait 3\nlog_layout\n", 1280, 720, config);
  ASSERT_EQ(second.status, 0) << second.log;
  Layout b = parse_layout(second.log);
  EXPECT_EQ(b.view.x, 300);
  EXPECT_EQ(b.view.w, 1280 - 300 - 380);
  EXPECT_NE(second.log.find("view: the cage is hidden"), std::string::npos) << second.log;
  // an offscreen run leaves the artist's settings alone
  EditorRun off = run_offscreen("layout_remember_off", "wait 3\npanels 200 200 150\ntoggle cage\nwait 2\nlog_layout\n", 1280, 720, config);
  ASSERT_EQ(off.status, 0) << off.log;
  EXPECT_EQ(parse_layout(off.log).view.x, 200);
  EditorRun after = run_windowed("layout_remember_after", "wait 3\nlog_layout\n", 1280, 720, config);
  EXPECT_EQ(parse_layout(after.log).view.x, 300) << after.log;
  EXPECT_NE(after.log.find("view: the cage is hidden"), std::string::npos) << after.log;
  // a window too small for them: the panels give way and the view keeps its minimum
  EditorRun small = run_windowed("layout_remember_c", "wait 3\nlog_layout\n", 800, 600, config);
  ASSERT_EQ(small.status, 0) << small.log;
  EXPECT_GE(parse_layout(small.log).view.w, cagewrap::app::PanelLayout::kMinView - 0.5f);
}

}  // namespace
