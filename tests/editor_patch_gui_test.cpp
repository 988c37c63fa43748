// The editor's Parametric driver window (app/patch_panel.h), run for real under Xvfb: a sheet of
// quads is imported as the cage in front of the demo character's chest, its faces are selected and a
// B-spline grid is fitted to them (drawn as a control net), two control points are moved (one picked
// by a click in the view and moved by the move gizmo's path; the skin follows: the view changes around
// the chest and the exported driver holds exactly the moves), the density is raised, and a missing
// driver file is an error that keeps everything. Undo, redo, cancel and the project are tested
// in-process (tests/workspace_jobs_test.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <glm/geometric.hpp>

#include "core/deform/patch_fit.h"
#include "tests/patch_fixtures.h"
#include "core/io/patch_io.h"
#include "core/geometry/mesh_io.h"
#include "tests/gui_harness.h"

namespace {

namespace fs = std::filesystem;
using namespace cagewrap;
using namespace cagewrap::test;

// Cyan pixels: the control net's colour (render/viewport_renderer.cpp kNetColor).
size_t net_pixels(const Image& img) {
  size_t n = 0;
  for (int y = kTop; y < img.h - kBottom; ++y)
    for (int x = kLeft; x < img.w - kRight; ++x) {
      const unsigned char* p = img.at(x, y);
      if (p[0] < 110 && p[1] > 180 && p[2] > 200) ++n;
    }
  return n;
}

TEST(EditorPatchGui, FitMoveAndDensityDriveTheSkin) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = gui_test_dir();
  const fs::path sheet = dir / "patch_sheet.obj", exported = dir / "patch_moved.cwpatch", kept = dir / "patch_kept.cwpatch";
  const PolyMesh cage = chest_sheet();
  ASSERT_TRUE(save_obj(sheet.string(), cage.positions, cage).ok());
  for (const char* f : {"patch_fit.png", "patch_moved.png", "patch_dense.png", "patch_error.png"}) fs::remove(dir / f);
  fs::remove(exported);
  fs::remove(kept);
  // at the bind pose: the sheet is the cage here, and posed it would shear the skin (the driver adds its
  // sculpt to the cage's skin)
  std::string script = "import_cage " + sheet.string() + "\nclip rest\nwait 2\n";
  for (uint32_t f = 0; f < cage.num_faces(); ++f) script += "select_cage_face " + std::to_string(f) + " add\n";
  script += "patch_panel\npatch_fit\nwait 2\nscreenshot " + (dir / "patch_fit.png").string() +
            "\nclick_patch_point 14\nwait 2\nmove 0.1 0.15 0\npatch_select 15\npatch_move -0.1 0.15 0\nwait 2\n"
            "screenshot " + (dir / "patch_moved.png").string() + "\npatch_export " + exported.string() +
            "\npatch_density 6\nwait 2\nscreenshot " + (dir / "patch_dense.png").string() +
            "\npatch_import " + (dir / "missing.cwpatch").string() + "\nwait 2\nscreenshot " + (dir / "patch_error.png").string() + "\npatch_export " + kept.string() + "\n";
  const std::string demo = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb";
  EditorRun run = run_editor_script(dir, "patch", script, demo + " --width 1280 --height 720", dir / "config_patch");
  ASSERT_EQ(run.status, 0) << run.log;
  EXPECT_NE(run.log.find("Fit a 5 x 6 parametric driver to 20 cage faces"), std::string::npos) << run.log;
  EXPECT_NE(run.log.find("to 35 samples (density 2"), std::string::npos) << run.log;   // 3 x 4 spans
  EXPECT_NE(run.log.find("to 247 samples (density 6"), std::string::npos) << run.log;  // 19 x 13
  EXPECT_NE(run.log.find("missing.cwpatch"), std::string::npos) << run.log;

  // the exported driver is the fit with exactly the two moves
  auto grid = fit_patch_to_faces(cage, cage.positions, std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
                                                                             15, 16, 17, 18, 19});
  ASSERT_TRUE(grid.ok());
  auto moved = load_patch(exported.string());
  ASSERT_TRUE(moved.ok()) << moved.error().message;
  ASSERT_EQ(moved->grids.size(), 1u);
  ASSERT_EQ(moved->grids[0].points.size(), grid->points.size());
  for (size_t k = 0; k < grid->points.size(); ++k) {
    const glm::dvec3 want = grid->points[k] + (k == 14 ? glm::dvec3(0.1, 0.15, 0) : k == 15 ? glm::dvec3(-0.1, 0.15, 0) : glm::dvec3(0.0));
    EXPECT_LT(glm::length(moved->grids[0].points[k] - want), 1e-9) << "control point " << k;
  }

  const Image fit = load_png((dir / "patch_fit.png").string()), after = load_png((dir / "patch_moved.png").string()),
              dense = load_png((dir / "patch_dense.png").string()), error = load_png((dir / "patch_error.png").string());
  ASSERT_FALSE(fit.rgb.empty() || after.rgb.empty() || dense.rgb.empty() || error.rgb.empty());
  EXPECT_GT(net_pixels(fit), 300u) << "the control net is drawn";
  // the moved control points pull the chest: the view changes, but only in part (not a blank or a jump)
  const double changed = share_differing(fit, after, 24);
  EXPECT_GT(changed, 0.002);
  EXPECT_LT(changed, 0.2);
  // a denser sampling of the same driver changes the skin only slightly
  EXPECT_LT(share_differing(after, dense, 24), changed);
  // the failed import (an error box over the view) kept the driver as it was
  auto after_error = load_patch(kept.string());
  ASSERT_TRUE(after_error.ok()) << after_error.error().message;
  EXPECT_EQ(*after_error, *moved);
}

// The driver's set edits picked in the view (issue 21): with the sample tool on, two clicks on the driver's
// samples (the second shift-click adds) pick them, and "only" on a selected chest vertex makes them its set;
// the saved project holds exactly that edit, and the driver was bound again with it.
TEST(EditorPatchGui, SamplesPickedInTheViewMakeTheDriversSetEdit) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = gui_test_dir();
  const fs::path driver = dir / "samples_chest.cwpatch", project = dir / "samples.cagewrap";
  const PolyMesh cage = chest_sheet();
  std::vector<uint32_t> faces(cage.num_faces());
  for (uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
  auto grid = fit_patch_to_faces(cage, cage.positions, faces);
  ASSERT_TRUE(grid.ok());
  PatchSurface rest;
  rest.grids = {*grid};
  ASSERT_TRUE(save_patch_any(driver.string(), rest).ok());
  fs::remove(project);
  const std::string script = "driver_add " + driver.string() + "\nwait 3\nclip rest\npatch_panel\npatch_samples on\ncamera 0 0 1.5 0 1.2 0\nwait 2\n"
                             "click_patch_sample 0\nclick_patch_sample 8 add\nselect_skin_vertex 32831\npatch_set_edit only\nwait 3\n"
                             "screenshot " + (dir / "patch_samples.png").string() + "\nsave " + project.string() + "\n";
  const std::string demo = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb";
  EditorRun run = run_editor_script(dir, "patch_samples", script, demo + " --width 1280 --height 720", dir / "config_patch_samples");
  ASSERT_EQ(run.status, 0) << run.log;
  EXPECT_NE(run.log.find("Driver sets: only 2 samples on 1 points"), std::string::npos) << run.log;
  std::ifstream in(project);
  ASSERT_TRUE(in) << run.log;
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"point\": 32831, \"exclude\": [], \"include\": [0, 8], \"only\": true"), std::string::npos) << text.substr(0, 400);
}

}  // namespace
