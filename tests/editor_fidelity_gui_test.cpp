// The editor's Fidelity section (app/fidelity_panel.h), run for real under Xvfb: the heat map
// colours the skin where the rig leaves the file's skinning, the warning names a joint, "Check all
// clips" reports every clip in the log. Cancel, the check's figures and the heat map's colours at
// rest are tested in-process (tests/workspace_jobs_test.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gui_harness.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using namespace cagewrap::test;

// A project on the demo whose cage is shifted 30 cm sideways: its vertices take the weights of the
// wrong limbs, and the rig is far from the file's skinning.
fs::path bad_project(const fs::path& dir) {
  const fs::path cage = dir / "shifted_cage.obj", project = dir / "shifted.cagewrap";
  std::ifstream in(std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
  std::ofstream out(cage);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) == 0) {
      double x, y, z;
      std::sscanf(line.c_str(), "v %lf %lf %lf", &x, &y, &z);
      out << "v " << x + 0.3 << " " << y << " " << z << "\n";
    } else {
      out << line << "\n";
    }
  }
  out.close();
  const std::string cmd = std::string(CAGEWRAP_BINARY) + " new --character '" + CAGEWRAP_SOURCE_DIR +
                          "/assets/demo_character.glb' --cage '" + cage.string() + "' --out '" + project.string() + "' > /dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return project;
}

size_t red_pixels(const Image& img) {
  size_t hot = 0;
  for (int y = kTop; y < img.h - kBottom; ++y)
    for (int x = kLeft; x < img.w - kRight; ++x) {
      const unsigned char* p = img.at(x, y);
      if (p[0] > 170 && p[1] < 80 && p[2] < 80) ++hot;
    }
  return hot;
}

TEST(EditorFidelity, HeatMapWarningAndCheckAllClipsOnABadCage) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = gui_test_dir() / "fidelity";
  fs::create_directories(dir);
  const fs::path project = bad_project(dir);
  std::ofstream(dir / "bad.script") << "clip walk\ntime 0.5\nheatmap on\nwait 3\nfidelity_frame\nfidelity_check\nwait 1\n";
  const Image hot = screenshot(project.string() + " --script " + (dir / "bad.script").string(), "fidelity_bad");
  const std::string log = read_file(gui_test_dir() / "fidelity_bad.log");
  EXPECT_NE(log.find("fidelity, this frame: worst "), std::string::npos) << log;
  EXPECT_NE(log.find("fidelity, every clip ("), std::string::npos) << log;
  EXPECT_NE(log.find("(over the thresholds)"), std::string::npos) << log;
  EXPECT_NE(log.find("warning: fidelity: worst vertex"), std::string::npos) << log;
  EXPECT_NE(log.find("joint '"), std::string::npos) << log;
  // the same frame without the heat map: the red is the map's
  std::ofstream(dir / "plain.script") << "clip walk\ntime 0.5\nwait 3\n";
  const Image plain = screenshot(project.string() + " --script " + (dir / "plain.script").string(), "fidelity_plain");
  // measured at 1280 x 720: 922 red pixels with the map (the right leg); without it, under 40
  EXPECT_GT(red_pixels(hot), 400u);
  EXPECT_LT(red_pixels(plain), 40u);
}

// The editor's automatic cage (Cage > Automatic cage, default settings) is the cage `cagewrap cage`
// builds, vertex for vertex: the default path gives one rig in the editor and on the command line.
TEST(EditorFidelity, TheEditorsAutomaticCageIsTheCommandLinesCage) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = gui_test_dir() / "fidelity";
  fs::create_directories(dir);
  const std::string demo = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb";
  const fs::path saved = dir / "auto.cagewrap", cli = dir / "cli_cage.obj";
  fs::remove(saved);
  std::ofstream(dir / "auto.script") << "auto_cage\nwait 2\nsave " << saved.string() << "\n";
  screenshot(demo + " --script " + (dir / "auto.script").string(), "fidelity_auto");
  const std::string cmd = std::string(CAGEWRAP_BINARY) + " cage --mesh '" + demo + "' --out '" + cli.string() + "' > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream pf(saved);
  ASSERT_TRUE(pf.good()) << saved << "\n" << read_file(gui_test_dir() / "fidelity_auto.log");
  const nlohmann::json project = nlohmann::json::parse(pf);
  const auto& positions = project.at("cage").at("positions");
  std::vector<std::array<double, 3>> from_cli;
  size_t cli_faces = 0;
  std::ifstream obj(cli);
  std::string line;
  while (std::getline(obj, line))
    if (line.rfind("f ", 0) == 0) {
      ++cli_faces;
    } else if (line.rfind("v ", 0) == 0) {
      std::array<double, 3> v{};
      std::sscanf(line.c_str(), "v %lf %lf %lf", &v[0], &v[1], &v[2]);
      from_cli.push_back(v);
    }
  ASSERT_EQ(positions.size(), from_cli.size());
  double worst = 0;
  for (size_t i = 0; i < from_cli.size(); ++i)
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(positions[i][k].get<double>() - from_cli[i][k]));
  EXPECT_LT(worst, 1e-6) << "the OBJ keeps 9 significant digits";
  EXPECT_EQ(project.at("cage").at("faces").size(), cli_faces);
}

}  // namespace
}  // namespace cagewrap
