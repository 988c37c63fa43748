// The real editor under Xvfb (Mesa's software OpenGL): screenshots are taken with
// `cagewrap --screenshot`, loaded back and compared with tolerances. Skips when the editor was not
// built or xvfb-run is missing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <stb_image.h>

#include "tests/test_assets.h"

namespace {

namespace fs = std::filesystem;

struct Image {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;  // w x h x 3
  const unsigned char* at(int x, int y) const { return &rgb[(static_cast<size_t>(y) * w + x) * 3]; }
};

bool gui_available(std::string& why) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    why = "xvfb-run not installed";
    return false;
  }
  if (std::system((std::string(CAGEWRAP_BINARY) + " --help 2>/dev/null | grep -q -- --screenshot").c_str()) != 0) {
    why = "cagewrap has no editor";
    return false;
  }
  return true;
}

// Runs the editor and returns the screenshot (asserting exit status 0).
Image screenshot(const std::string& args, const std::string& name) {
  fs::path dir = fs::temp_directory_path() / "cagewrap_gui_test";
  fs::create_directories(dir);
  fs::path png = dir / (name + ".png");
  fs::remove(png);
  std::string cmd = "xvfb-run -a -s '-screen 0 1280x720x24' " + std::string(CAGEWRAP_BINARY) +
                    " --width 1280 --height 720 --screenshot " + png.string() + " " + args + " > " +
                    (dir / (name + ".log")).string() + " 2>&1";
  int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << cmd;
  Image img;
  int n = 0;
  unsigned char* data = stbi_load(png.string().c_str(), &img.w, &img.h, &n, 3);
  EXPECT_NE(data, nullptr) << png;
  if (data) {
    img.rgb.assign(data, data + static_cast<size_t>(img.w) * img.h * 3);
    stbi_image_free(data);
  }
  return img;
}

// The 3-D view: what the fixed panels leave free (see app/editor.cpp).
constexpr int kLeft = 262, kRight = 302, kTop = 21, kBottom = 172;

double share_differing(const Image& a, const Image& b, int tolerance) {
  size_t diff = 0, total = 0;
  for (int y = kTop; y < a.h - kBottom; ++y)
    for (int x = kLeft; x < a.w - kRight; ++x, ++total) {
      const unsigned char *p = a.at(x, y), *q = b.at(x, y);
      if (std::abs(p[0] - q[0]) > tolerance || std::abs(p[1] - q[1]) > tolerance || std::abs(p[2] - q[2]) > tolerance) ++diff;
    }
  return total ? double(diff) / total : 0.0;
}

// Share of view pixels that are the skin's warm colour (red clearly above blue).
double skin_share(const Image& img) {
  size_t skin = 0, total = 0;
  for (int y = kTop; y < img.h - kBottom; ++y)
    for (int x = kLeft; x < img.w - kRight; ++x, ++total) {
      const unsigned char* p = img.at(x, y);
      if (p[0] > 90 && p[0] > p[2] + 30) ++skin;
    }
  return total ? double(skin) / total : 0.0;
}

TEST(EditorGui, DemoCharacterIsVisibleFramedAndAnimates) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  Image rest = screenshot("--frames 2", "rest");
  ASSERT_EQ(rest.w, 1280);
  ASSERT_EQ(rest.h, 720);
  // the character fills a good part of the view, but is framed (not cut off at the view's edges)
  double share = skin_share(rest);
  EXPECT_GT(share, 0.04) << "the character should be plainly visible";
  EXPECT_LT(share, 0.6) << "the character should be framed, not fill the view";
  // the same frame twice gives the same picture (deterministic rendering, fixed time step)
  Image again = screenshot("--frames 2", "rest_again");
  EXPECT_LT(share_differing(rest, again, 8), 0.01);
  // playing the walk (1 s loop) for half a second moves the skin
  Image walking = screenshot("--frames 15 --play", "walking");  // half a walk cycle
  EXPECT_GT(share_differing(rest, walking, 24), 0.005) << "the walk clip should move the character";
}

TEST(EditorGui, BadFileKeepsRunningAndSaysWhy) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  fs::path bad = fs::temp_directory_path() / "cagewrap_gui_test" / "not_a_character.glb";
  fs::create_directories(bad.parent_path());
  { std::ofstream(bad) << "this is not glTF"; }
  Image img = screenshot(bad.string() + " --frames 2", "bad_file");
  EXPECT_EQ(img.w, 1280);  // the editor still ran and rendered: no crash
  std::ifstream log((fs::temp_directory_path() / "cagewrap_gui_test" / "bad_file.log").string());
  std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("not_a_character.glb"), std::string::npos) << text;
}

TEST(EditorGui, MannequinDeformsThroughItsCage) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  CAGEWRAP_REQUIRE_ASSETS(assets);
  std::string args = assets + "/mannequiny.glb --cage " + assets + "/bench/mannequiny/cage.obj";
  Image img = screenshot(args + " --frames 20 --play", "mannequin");
  EXPECT_GT(skin_share(img), 0.01);
  std::ifstream log((fs::temp_directory_path() / "cagewrap_gui_test" / "mannequin.log").string());
  std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("bound 10366 points to 2000 elements"), std::string::npos) << text;
}

}  // namespace
