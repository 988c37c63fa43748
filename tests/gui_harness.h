// Running the real editor under Xvfb for GUI tests: availability check, a run that returns the
// screenshot, PNG loading and image comparisons over the 3-D view (the fixed panels excluded).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <stb_image.h>

#include "app/workspace/panel_layout.h"

namespace cagewrap::test {

struct Image {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;  // w x h x 3
  const unsigned char* at(int x, int y) const { return &rgb[(static_cast<size_t>(y) * w + x) * 3]; }
};

inline Image load_png(const std::string& path) {
  Image img;
  int n = 0;
  unsigned char* d = stbi_load(path.c_str(), &img.w, &img.h, &n, 3);
  if (d) {
    img.rgb.assign(d, d + static_cast<size_t>(img.w) * img.h * 3);
    stbi_image_free(d);
  }
  return img;
}

inline bool gui_available(std::string& why) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    why = "xvfb-run not installed";
    return false;
  }
  if (!CAGEWRAP_TESTS_HAVE_EDITOR) {
    why = "cagewrap was built without the editor (CAGEWRAP_GUI=OFF)";
    return false;
  }
  return true;
}

// The shell command that runs the editor on a 1280 x 720 virtual screen with `args`, its
// preferences in `config_dir` (a test never reads or writes the user's preferences), and stdout
// and stderr in `log`.
inline std::string editor_command(const std::string& args, const std::string& config_dir, const std::string& log) {
  return "CAGEWRAP_CONFIG_DIR='" + config_dir + "' xvfb-run -a -s '-screen 0 1280x720x24' " + std::string(CAGEWRAP_BINARY) + " " +
         args + " > '" + log + "' 2>&1";
}

// The same run with the editor's process id written to `pid_file` (the editor replaces the shell
// that wrote it), so a test can signal it (a SIGKILL test).
inline std::string editor_command_with_pid(const std::string& args, const std::string& config_dir, const std::string& log,
                                           const std::string& pid_file) {
  return "CAGEWRAP_CONFIG_DIR='" + config_dir + "' xvfb-run -a -s '-screen 0 1280x720x24' sh -c \"echo \\$\\$ > '" + pid_file +
         "'; exec " + std::string(CAGEWRAP_BINARY) + " " + args + "\" > '" + log + "' 2>&1";
}

// A file's bytes ("" when it cannot be read): a run's log, a saved file.
inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

struct EditorRun {
  int status = -1;  // std::system's
  std::string log;  // stdout and stderr
};
// Runs the editor with `script` (written to DIR/NAME.script) and `args`, its preferences in
// `config_dir`; the log is DIR/NAME.log.
inline EditorRun run_editor_script(const std::filesystem::path& dir, const std::string& name, const std::string& script,
                                   const std::string& args, const std::filesystem::path& config_dir) {
  const std::filesystem::path s = dir / (name + ".script");
  std::ofstream(s) << script;
  const std::filesystem::path log = dir / (name + ".log");
  EditorRun run;
  run.status = std::system(editor_command("--script " + s.string() + " " + args, config_dir.string(), log.string()).c_str());
  run.log = read_file(log);
  return run;
}

// A scratch folder for GUI test files, one per build of the editor (two checkouts running their GUI
// tests at once never share files).
inline std::filesystem::path gui_test_dir() {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("cagewrap_gui_test_" + std::to_string(std::hash<std::string>{}(CAGEWRAP_BINARY) % 1000000007));
  std::filesystem::create_directories(dir);
  return dir;
}

// Runs the editor and returns the screenshot (asserting exit status 0); its log is NAME.log.
inline Image screenshot(const std::string& args, const std::string& name) {
  std::filesystem::path dir = gui_test_dir();
  std::filesystem::path png = dir / (name + ".png");
  std::filesystem::remove(png);
  std::string cmd = editor_command("--width 1280 --height 720 --screenshot " + png.string() + " " + args,
                                   (dir / ("config_" + name)).string(), (dir / (name + ".log")).string());
  int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << cmd;
  Image img = load_png(png.string());
  EXPECT_FALSE(img.rgb.empty()) << png;
  return img;
}

// The 3-D view in a fresh configuration: what the panels leave free at their default sizes (read
// from the editor's own layout, app/workspace/panel_layout.h), 2 pixels in from their borders.
constexpr cagewrap::app::PanelLayout kDefaultLayout{};
constexpr int kLeft = static_cast<int>(kDefaultLayout.left) + 2, kRight = static_cast<int>(kDefaultLayout.right) + 2,
              kTop = static_cast<int>(cagewrap::app::PanelLayout::kMenuHeight) + 2, kBottom = static_cast<int>(kDefaultLayout.bottom) + 2;

// A rectangle of window pixels [x0, x1) x [y0, y1).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};
// Where the stats overlay (fps, frame times: different on every run) sits in the view's top left.
constexpr PixelRect kStatsOverlay{kLeft, kTop, kLeft + 420, kTop + 200};

// Share of the view's pixels (those outside `exclude`: by default the stats overlay, whose timings
// differ on every run) that differ by more than `tolerance` in a channel.
inline double share_differing(const Image& a, const Image& b, int tolerance, PixelRect exclude = kStatsOverlay) {
  size_t diff = 0, total = 0;
  for (int y = kTop; y < a.h - kBottom; ++y)
    for (int x = kLeft; x < a.w - kRight; ++x) {
      if (exclude.contains(x, y)) continue;
      ++total;
      const unsigned char *p = a.at(x, y), *q = b.at(x, y);
      if (std::abs(p[0] - q[0]) > tolerance || std::abs(p[1] - q[1]) > tolerance || std::abs(p[2] - q[2]) > tolerance) ++diff;
    }
  return total ? double(diff) / total : 0.0;
}

// Share of view pixels that are the skin's warm colour (red clearly above blue).
inline double skin_share(const Image& img) {
  size_t skin = 0, total = 0;
  for (int y = kTop; y < img.h - kBottom; ++y)
    for (int x = kLeft; x < img.w - kRight; ++x, ++total) {
      const unsigned char* p = img.at(x, y);
      if (p[0] > 90 && p[0] > p[2] + 30) ++skin;
    }
  return total ? double(skin) / total : 0.0;
}

}  // namespace cagewrap::test
