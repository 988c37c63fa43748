// The editor's selection modes and move tool, run for real under Xvfb on the demo character at its
// bind pose: a click picks the front-most vertex under the cursor, a plane drag of the gizmo with
// soft selection and X-mirror moves exactly what app/workspace/soft_selection.h says (checked in the saved
// project), a face selection moves the face's corners, and a skin selection is drawn.
#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <fstream>
#include <algorithm>
#include <sstream>
#include <iterator>
#include <string>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/geometry/mesh_io.h"
#include "core/geometry/selection.h"
#include "tests/fixtures.h"
#include "tests/gui_harness.h"

namespace {

namespace fs = std::filesystem;
using namespace cagewrap;
using namespace cagewrap::test;

// A project the script saved, parsed; null (and a failure) when it cannot be read.
nlohmann::json saved_project(const fs::path& project) {
  std::ifstream in(project);
  EXPECT_TRUE(in) << project;
  return in ? nlohmann::json::parse(in) : nlohmann::json();
}

std::vector<glm::dvec3> saved_offsets(const fs::path& project) {
  std::vector<glm::dvec3> out;
  const auto j = saved_project(project);
  if (j.is_null()) return out;
  for (const auto& o : j.at("cage").at("offsets")) out.emplace_back(o[0].get<double>(), o[1].get<double>(), o[2].get<double>());
  return out;
}

PolyMesh demo_cage() {
  auto m = load_mesh(std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
  EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().message);
  return m.ok() ? std::move(m).value() : PolyMesh{};
}

void write_script(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// A box cage around the demo character, 6 x 6 quads a side, symmetric across x = 0 (the auto cage
// is only nearly symmetric), written as OBJ.
PolyMesh symmetric_cage(const fs::path& path) {
  const Aabb box = bounding_box(demo_cage().positions);
  const glm::dvec3 half(std::max(-box.lo.x, box.hi.x) * 1.05, 0.5 * (box.hi.y - box.lo.y) * 1.05, 0.5 * (box.hi.z - box.lo.z) * 1.05);
  const glm::dvec3 centre(0.0, box.center().y, box.center().z);
  PolyMesh m = fixtures::box_cage(1.0, 6).polygons;
  for (auto& p : m.positions) p = glm::vec3(centre + glm::dvec3(p) * half);
  EXPECT_TRUE(save_obj(path.string(), m.positions, m).ok());
  return m;
}

TEST(EditorTools, ClickPicksTheFrontVertexAndSoftMirroredPlaneDragMovesBothSides) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path cage_path = gui_test_dir() / "tools_symmetric_cage.obj";
  PolyMesh cage = symmetric_cage(cage_path);
  ASSERT_GT(cage.num_vertices(), 0u);
  // the front-most vertex (largest z) among those well off the mirror plane, the one with the
  // lowest y of those: the front view looks down -Z, so a click on its projection must pick it and
  // nothing behind it
  const Aabb box = bounding_box(cage.positions);
  uint32_t v = 0;
  auto better = [&](uint32_t i) {
    const glm::vec3 p = cage.positions[i], q = cage.positions[v];
    if (std::abs(p.x) < 0.1 * box.diagonal()) return false;
    if (std::abs(q.x) < 0.1 * box.diagonal()) return true;
    return p.z > q.z + 1e-6 || (std::abs(p.z - q.z) <= 1e-6 && p.y < q.y - 1e-6) ||
           (std::abs(p.z - q.z) <= 1e-6 && std::abs(p.y - q.y) <= 1e-6 && p.x > q.x);
  };
  for (uint32_t i = 0; i < cage.num_vertices(); ++i)
    if (better(i)) v = i;
  auto mirror = mirror_x(IndexSet{v}, cage.positions, 1e-3 * box.diagonal());
  ASSERT_EQ(mirror.mirrored.size(), 1u) << "the box cage is symmetric";
  const uint32_t m = mirror.mirrored.indices()[0];
  ASSERT_NE(m, v);

  fs::path dir = gui_test_dir(), project = dir / "tools_soft.cagewrap", script = dir / "tools_soft.script";
  fs::remove(project);
  const double radius = 0.15 * box.diagonal();
  write_script(script, "clip rest\nview front\nwait 2\nclick_cage_vertex " + std::to_string(v) + "\nsoft on " + std::to_string(radius) +
                           " linear\nmirror on\ngizmo_drag xy 30 -20\nsave " + project.string() + "\n");
  screenshot(std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb --cage " + cage_path.string() + " --script " + script.string(),
             "tools_soft");
  auto off = saved_offsets(project);
  ASSERT_EQ(off.size(), cage.num_vertices());
  const glm::dvec3 d = off[v];
  EXPECT_GT(std::abs(d.x), 1e-4) << "the plane drag moves along x";
  EXPECT_GT(d.y, 1e-4) << "dragging up moves up";
  EXPECT_NEAR(d.z, 0.0, 1e-9) << "an XY-plane drag never changes z";
  EXPECT_NEAR(off[m].x, -d.x, 1e-6);  // the counterpart: x negated
  EXPECT_NEAR(off[m].y, d.y, 1e-6);
  EXPECT_NEAR(off[m].z, 0.0, 1e-6);
  // soft selection: every other moved vertex lies within the radius of v or m and moves by a share
  // in (0, 1) of d or of its mirror image
  size_t soft_moved = 0;
  for (uint32_t i = 0; i < off.size(); ++i) {
    if (i == v || i == m || glm::length(off[i]) == 0.0) continue;
    ++soft_moved;
    const glm::dvec3 p(cage.positions[i]);
    const double dv = glm::length(p - glm::dvec3(cage.positions[v])), dm = glm::length(p - glm::dvec3(cage.positions[m]));
    EXPECT_LT(std::min(dv, dm), radius * (1 + 1e-6)) << "vertex " << i;
    const glm::dvec3 ref = dv <= dm ? d : glm::dvec3(-d.x, d.y, d.z);
    const double share = glm::dot(off[i], ref) / glm::dot(ref, ref);
    EXPECT_GT(share, 0.0) << "vertex " << i;
    EXPECT_LT(share, 1.0) << "vertex " << i;
    EXPECT_NEAR(glm::length(off[i] - share * ref), 0.0, 1e-5) << "vertex " << i << " moves along the drag";
  }
  EXPECT_GT(soft_moved, 4u) << "the falloff reaches the neighbours";
}

TEST(EditorTools, FaceSelectionMovesTheFaceCornersOnly) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  PolyMesh cage = demo_cage();
  ASSERT_GT(cage.num_faces(), 20u);
  fs::path dir = gui_test_dir(), project = dir / "tools_face.cagewrap", script = dir / "tools_face.script";
  fs::remove(project);
  write_script(script, "clip rest\nwait 2\nmode cage_faces\nselect_cage_face 17\nmove 0 0.05 0\nsave " + project.string() + "\n");
  screenshot("--script " + script.string(), "tools_face");
  auto off = saved_offsets(project);
  ASSERT_EQ(off.size(), cage.num_vertices());
  std::vector<bool> corner(cage.num_vertices(), false);
  for (uint32_t c : cage.face(17)) corner[c] = true;
  for (uint32_t i = 0; i < off.size(); ++i) {
    if (corner[i]) {
      EXPECT_NEAR(off[i].y, 0.05, 1e-6) << "corner " << i;
    } else {
      EXPECT_EQ(glm::length(off[i]), 0.0) << "vertex " << i;
    }
  }
}

// "Edit rest" (move_target rest): the move goes into the reference cage, not the offsets; the
// distance scale is fixed to the bound h; only the skin points near the vertex register again.
TEST(EditorTools, RestEditMovesTheReferenceCageAndRegistersOnlyNearbyPoints) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  PolyMesh cage = demo_cage();
  fs::path dir = gui_test_dir(), project = dir / "tools_rest.cagewrap", script = dir / "tools_rest.script";
  fs::remove(project);
  write_script(script, "clip rest\nwait 2\nmode cage_vertices\nselect_cage_vertex 500\nmove_target rest\nmove 0 0.03 0\n"
                       "wait 2\nsave " + project.string() + "\n");
  screenshot("--script " + script.string(), "tools_rest");
  const auto j = saved_project(project);
  ASSERT_FALSE(j.is_null()) << project;
  const auto& pos = j.at("cage").at("positions");
  ASSERT_EQ(pos.size(), cage.num_vertices());
  for (uint32_t i = 0; i < cage.num_vertices(); ++i) {
    const glm::dvec3 p(pos[i][0].get<double>(), pos[i][1].get<double>(), pos[i][2].get<double>());
    const glm::dvec3 expect = glm::dvec3(cage.positions[i]) + (i == 500 ? glm::dvec3(0, 0.03, 0) : glm::dvec3(0.0));
    EXPECT_NEAR(glm::length(p - expect), 0.0, 1e-5) << "vertex " << i;
  }
  for (const auto& o : j.at("cage").value("offsets", nlohmann::json::array()))
    EXPECT_EQ(o[0].get<double>() * o[0].get<double>() + o[1].get<double>() * o[1].get<double>() +
                  o[2].get<double>() * o[2].get<double>(), 0.0);
  EXPECT_GT(j.at("binding").at("scale").get<double>(), 0.0) << "h is fixed so the edit stays local";
  const std::string log = read_file(dir / "tools_rest.log");
  const auto at = log.find("rest cage edit: 1 moved vertices, ");
  ASSERT_NE(at, std::string::npos) << log;
  unsigned long points = 0, total = 0;
  ASSERT_EQ(std::sscanf(log.c_str() + at, "rest cage edit: 1 moved vertices, %lu of %lu", &points, &total), 2) << log;
  EXPECT_GT(points, 0u);
  EXPECT_LT(points * 10, total) << "a one-vertex edit registers under a tenth of the skin";
}

// Pink points are the skin selection's colour (render/viewport_renderer.cpp).
size_t pink_pixels(const Image& img) {
  size_t n = 0;
  for (int y = kTop; y < img.h - kBottom; ++y)
    for (int x = kLeft; x < img.w - kRight; ++x) {
      const unsigned char* p = img.at(x, y);
      if (p[0] > 220 && p[1] < 120 && p[2] > 100 && p[2] < 180) ++n;
    }
  return n;
}

TEST(EditorTools, SkinSelectionIsDrawn) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  fs::path dir = gui_test_dir(), script = dir / "tools_skin.script";
  write_script(script, "clip rest\nwait 2\nmode skin_vertices\nselect_skin_vertex 20000\nselect grow\nselect grow\nselect grow\nwait 1\n");
  Image selected = screenshot("--script " + script.string(), "tools_skin");
  write_script(script, "clip rest\nwait 3\n");
  Image plain = screenshot("--script " + script.string(), "tools_skin_none");
  EXPECT_GT(pink_pixels(selected), 20u);
  EXPECT_EQ(pink_pixels(plain), 0u);
}

// Posing a joint with the rotation gizmo (a drag along its X ring, hit-tested like a click) gives
// the same picture as setting the angle directly; the pose changes the skin, and the comparison
// with the file's own skinning shows a different skin.
TEST(EditorTools, RotationRingPosesTheJointLikeTheAngleFields) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = gui_test_dir(), script = dir / "tools_rotate.script";
  const std::string head = "clip rest\nwait 2\nmode joints\nselect_joint 7\n";  // forearm.L
  write_script(script, head + "rotate_drag x 50\nwait 2\n");
  Image dragged = screenshot("--script " + script.string(), "tools_rotate_drag");
  write_script(script, head + "pose 7 50 0 0\nwait 2\n");
  Image typed = screenshot("--script " + script.string(), "tools_rotate_typed");
  write_script(script, head + "wait 2\n");
  Image rest = screenshot("--script " + script.string(), "tools_rotate_rest");
  write_script(script, head + "pose 7 50 0 0\ncompare on\nwait 2\n");
  Image file_skinning = screenshot("--script " + script.string(), "tools_rotate_lbs");
  ASSERT_FALSE(dragged.rgb.empty() || typed.rgb.empty() || rest.rgb.empty() || file_skinning.rgb.empty());
  EXPECT_GT(share_differing(rest, typed, 24), 0.002) << "bending the forearm changes the picture";
  // the gizmo overlay differs (it shows the angle while dragging only), the character must not
  EXPECT_LT(share_differing(dragged, typed, 24), 0.001) << "the ring drag turns the joint by the dragged angle";
  // With the cage wire over the skin the two skins differ in a few dozen pixels at this pose; what
  // tells them apart is mostly the stats overlay's line naming the skin shown, so it is compared too.
  EXPECT_GT(share_differing(typed, file_skinning, 24, PixelRect{}), 0.0005) << "the file's skinning is not the cage deformation";
}

// Opening another file with unsaved changes asks first: Cancel keeps the work, Discard opens.
TEST(EditorTools, OpeningWithUnsavedChangesAsksFirst) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = gui_test_dir(), script = dir / "tools_prompt.script", kept = dir / "tools_prompt_kept.cagewrap",
                 fresh = dir / "tools_prompt_fresh.cagewrap", prompt_png = dir / "tools_prompt_dialog.png";
  for (const auto& p : {kept, fresh, prompt_png}) fs::remove(p);
  const std::string demo = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb";
  write_script(script, "clip rest\nwait 2\nselect_cage_vertex 10\nmove 0 0.1 0\nopen_asking " + demo + "\nwait 1\nscreenshot " +
                           prompt_png.string() + "\nanswer cancel\nsave " + kept.string() + "\nmove 0 0.1 0\nopen_asking " + demo +
                           "\nanswer discard\nwait 2\nsave " + fresh.string() + "\n");
  screenshot("--script " + script.string(), "tools_prompt");
  auto k = saved_offsets(kept);
  ASSERT_GT(k.size(), 10u);
  EXPECT_NEAR(k[10].y, 0.1, 1e-6) << "Cancel keeps the document and its move";
  const auto saved = saved_project(fresh);
  ASSERT_FALSE(saved.is_null()) << fresh;
  EXPECT_TRUE(saved.at("cage").at("positions").empty()) << "Discard opened the character alone, a new untitled project";
  EXPECT_TRUE(fs::exists(prompt_png));
}

// Contributing sets: a brush stroke on the skin removes the selected cage faces from the sets of
// the points it covers (one undo step), the heat map of those faces' influence is drawn.
TEST(EditorTools, PaintingSetsRemovesFacesFromThePointsUnderTheBrush) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = gui_test_dir(), script = dir / "tools_sets.script", painted = dir / "tools_painted.cagewrap",
                 undone = dir / "tools_paint_undone.cagewrap";
  for (const auto& p : {painted, undone}) fs::remove(p);
  write_script(script, "clip rest\nwait 2\nmode cage_faces\nselect_cage_face 600\nselect grow\nsets_panel influence\nwait 1\n"
                       "mode skin_vertices\npaint_at_skin_vertex 20000 0.15\nsave " + painted.string() + "\nundo\nsave " +
                           undone.string() + "\n");
  Image shot = screenshot("--script " + script.string(), "tools_sets");
  const auto saved = saved_project(painted);
  ASSERT_FALSE(saved.is_null()) << painted;
  const auto edits = saved.at("set_edits");
  EXPECT_GT(edits.size(), 50u) << "the brush covers many points";
  for (const auto& e : edits) {
    EXPECT_FALSE(e.at("exclude").empty());
    EXPECT_TRUE(!e.contains("include") || e.at("include").empty());
  }
  std::ifstream in2(undone);
  ASSERT_TRUE(in2) << undone;
  const auto j2 = nlohmann::json::parse(in2);
  EXPECT_TRUE(!j2.contains("set_edits") || j2.at("set_edits").empty()) << "one undo takes the stroke back";
  // the heat map: hot (red) pixels where the faces drive the skin
  size_t hot = 0;
  for (int y = kTop; y < shot.h - kBottom; ++y)
    for (int x = kLeft; x < shot.w - kRight; ++x) {
      const unsigned char* p = shot.at(x, y);
      if (p[0] > 180 && p[1] < 90 && p[2] < 90) ++hot;
    }
  EXPECT_GT(hot, 30u);
}

}  // namespace
