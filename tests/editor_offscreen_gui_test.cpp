// The editor with no window (`cagewrap --offscreen`, app/offscreen_surface.h): it runs with no X
// server at all (DISPLAY unset), draws the same picture as the windowed editor under Xvfb, and
// refuses a run that could never end.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/gui_harness.h"

namespace {

namespace fs = std::filesystem;
using namespace cagewrap::test;

// Runs `cagewrap --offscreen ARGS` with DISPLAY and WAYLAND_DISPLAY unset; the log is NAME.log.
EditorRun run_offscreen(const std::string& args, const std::string& name) {
  const fs::path dir = gui_test_dir();
  const fs::path log = dir / (name + ".log");
  const std::string cmd = "env -u DISPLAY -u WAYLAND_DISPLAY CAGEWRAP_CONFIG_DIR='" + (dir / ("config_" + name)).string() + "' " +
                          std::string(CAGEWRAP_BINARY) + " --offscreen " + args + " > '" + log.string() + "' 2>&1";
  EditorRun run;
  run.status = std::system(cmd.c_str());
  run.log = read_file(log);
  return run;
}

// Share of 4 x 4 blocks of the 3-D view whose mean colour differs by more than `tolerance` in a
// channel: edges smoothed differently (the offscreen frame always has 4 samples, Xvfb's visual may
// have none) average out, a different picture does not. The runs hide the cage and skeleton,
// whose wide lines rasterize thicker with multisampling.
double share_of_blocks_differing(const Image& a, const Image& b, int tolerance) {
  size_t diff = 0, total = 0;
  for (int y = kTop; y + 4 <= a.h - kBottom; y += 4)
    for (int x = kLeft; x + 4 <= a.w - kRight; x += 4) {
      if (kStatsOverlay.contains(x, y)) continue;
      int sum[3] = {0, 0, 0};
      for (int dy = 0; dy < 4; ++dy)
        for (int dx = 0; dx < 4; ++dx)
          for (int c = 0; c < 3; ++c) sum[c] += a.at(x + dx, y + dy)[c] - b.at(x + dx, y + dy)[c];
      ++total;
      if (std::abs(sum[0]) > 16 * tolerance || std::abs(sum[1]) > 16 * tolerance || std::abs(sum[2]) > 16 * tolerance) ++diff;
    }
  return total ? double(diff) / total : 0.0;
}

TEST(EditorOffscreen, DrawsWithNoDisplayWhatTheWindowShows) {
  if (!CAGEWRAP_TESTS_HAVE_EDITOR) GTEST_SKIP() << "cagewrap was built without the editor (CAGEWRAP_GUI=OFF)";
  const fs::path dir = gui_test_dir();
  const fs::path script = dir / "offscreen.script", png = dir / "offscreen.png";
  std::ofstream(script) << "clip arm_raise\ntime 1.2\ntoggle cage\ntoggle skeleton\nwait 2\n";
  fs::remove(png);
  // fresh preferences: a windowed run keeps its view toggles in them for the next run
  for (const char* config : {"config_offscreen", "config_offscreen_window", "config_offscreen_rest"}) fs::remove_all(dir / config);
  const EditorRun off = run_offscreen("--width 1280 --height 720 --frames 3 --cpu-deform --script " + script.string() +
                                          " --screenshot " + png.string(),
                                      "offscreen");
  if (off.log.find("no headless OpenGL") != std::string::npos || off.log.find("no EGL library") != std::string::npos)
    GTEST_SKIP() << "no headless OpenGL 4.3 context on this machine: " << off.log;
  ASSERT_EQ(off.status, 0) << off.log;
  EXPECT_NE(off.log.find("offscreen 1280 x 720: "), std::string::npos) << off.log;
  EXPECT_EQ(off.log.find("error"), std::string::npos) << off.log;
  const Image offscreen = load_png(png.string());
  ASSERT_EQ(offscreen.w, 1280);
  ASSERT_EQ(offscreen.h, 720);
  EXPECT_GT(skin_share(offscreen), 0.02);  // the character is drawn, not an empty frame

  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << "no windowed run to compare with: " << why;
  const Image window = screenshot("--frames 3 --cpu-deform --script " + script.string(), "offscreen_window");
  // the same scene, camera, pose and panels
  const double same = share_of_blocks_differing(offscreen, window, 24);
  EXPECT_LT(same, 0.004);
  // and a different pose is a different picture (the comparison can fail)
  std::ofstream(dir / "offscreen_rest.script") << "clip rest\ntoggle cage\ntoggle skeleton\nwait 2\n";
  const EditorRun rest = run_offscreen("--width 1280 --height 720 --frames 3 --cpu-deform --script " +
                                           (dir / "offscreen_rest.script").string() + " --screenshot " +
                                           (dir / "offscreen_rest.png").string(),
                                       "offscreen_rest");
  ASSERT_EQ(rest.status, 0) << rest.log;
  const double other = share_of_blocks_differing(offscreen, load_png((dir / "offscreen_rest.png").string()), 24);
  EXPECT_GT(other, 0.008);
  std::printf("4x4 blocks differing: offscreen vs window %.4f, arm_raise vs rest %.4f\n", same, other);
}

TEST(EditorOffscreen, RefusesARunWithNoScriptAndNoScreenshot) {
  if (!CAGEWRAP_TESTS_HAVE_EDITOR) GTEST_SKIP() << "cagewrap was built without the editor (CAGEWRAP_GUI=OFF)";
  const EditorRun run = run_offscreen("", "offscreen_endless");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.log.find("--offscreen has no window and no input: give --script or --screenshot"), std::string::npos) << run.log;
}

}  // namespace
