// The editor's cage simulation, run for real under Xvfb: the cape project of `cagewrap demo-sim cape`
// drawn mid-walk with the simulation on and off (the cape must differ), the Simulation window open,
// and weights painted on a selected cage vertex by script, saved, undone and saved again.
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/gui_harness.h"

namespace {

namespace fs = std::filesystem;
using namespace cagewrap::test;

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  EXPECT_TRUE(in) << p;
  return in ? nlohmann::json::parse(in) : nlohmann::json();
}

TEST(EditorSim, CapeDrapesWhenSimulatedAndWeightsArePaintedAsOneUndoStep) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = gui_test_dir(), project = dir / "sim_cape.cagewrap";
  const std::string make = std::string(CAGEWRAP_BINARY) + " demo-sim cape --out " + project.string() + " --character " +
                           CAGEWRAP_SOURCE_DIR + "/assets/demo_character.glb --cage " + CAGEWRAP_SOURCE_DIR +
                           "/assets/demo_cage.obj > " + (dir / "sim_make.log").string() + " 2>&1";
  ASSERT_EQ(std::system(make.c_str()), 0) << read_file(dir / "sim_make.log");
  const nlohmann::json made = read_json(project);
  const size_t nv = made.at("cage").at("positions").size();
  const auto& pinned = made.at("simulation").at("pinned");
  ASSERT_EQ(pinned.size(), nv);
  ASSERT_EQ(pinned[nv - 1], 0) << "the cape's last vertex is free";

  const fs::path on = dir / "sim_on.png", off = dir / "sim_off.png", panel = dir / "sim_panel.png",
                 painted = dir / "sim_painted.cagewrap", undone = dir / "sim_undone.cagewrap";
  for (const fs::path& f : {on, off, panel, painted, undone}) fs::remove(f);
  const std::string v = std::to_string(nv - 1);
  const std::string script = "clip walk\nview right\ntime 0.6\nwait 3\nscreenshot " + on.string() +
                             "\nsim off\nwait 2\nscreenshot " + off.string() +
                             "\nsim on\nsim_panel\nselect_cage_vertex " + v + "\nwait 2\nscreenshot " + panel.string() +
                             "\nsim_weights pin\nsave " + painted.string() + "\nundo\nsave " + undone.string() + "\n";
  const EditorRun run = run_editor_script(dir, "sim_cape", script, "--width 1280 --height 720 " + project.string(),
                                          dir / "config_sim");
  ASSERT_EQ(run.status, 0) << run.log;
  EXPECT_EQ(run.log.find("error:"), std::string::npos) << run.log;
  const Image a = load_png(on.string()), b = load_png(off.string());
  ASSERT_FALSE(a.rgb.empty());
  ASSERT_FALSE(b.rgb.empty());
  // the draped, swinging cape against the cape held in its modelled, slanted shape
  EXPECT_GT(share_differing(a, b, 40), 0.01);
  EXPECT_FALSE(load_png(panel.string()).rgb.empty());

  const nlohmann::json p = read_json(painted), u = read_json(undone);
  EXPECT_EQ(p.at("simulation").at("enabled"), true);
  EXPECT_EQ(p.at("simulation").at("pinned")[nv - 1], 1) << "the selected vertex was pinned";
  EXPECT_EQ(u.at("simulation").at("pinned")[nv - 1], 0) << "undo frees it again";
  EXPECT_EQ(u.at("simulation").at("enabled"), true);
}

}  // namespace
