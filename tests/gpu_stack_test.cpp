// A stack of deformers on the GPU (issue 21: render/gpu_deformer.h GpuStack, the editor's Scene::gpu_frame):
// a coarse demo character (a few thousand skin points) with the demo cage and two layers (a sculpted copy
// of the cage under the head's mask, and the cage grown by 4% with a sculpt of its own), posed by the
// editor's scene with the skin left to the GPU: each deformer's maps built on the CPU, the skin deformed and
// combined on the GPU, read back and held to the whole document's CPU rig (Rig::pose_clip, what `cagewrap
// pose` and the exports make) within 1e-5 of the skin's bounding-box diagonal, for in_order, sum and blend,
// with another deformer active, the document's cage muted, and a layer muted. The CPU copy the scene makes
// when picking asks (Scene::skin_posed) is the rig's skin too. The checks can fail: the layers move the skin
// well beyond the tolerance from the cage alone, and the same frame without the head's mask misses the rig.
// Runs in a headless EGL context (Mesa's llvmpipe in CI has compute shaders); skips with a message where no
// OpenGL 4.3 context can be had or the build has no GL.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "tests/driver_fixtures.h"
#include "tests/gl_fixtures.h"
#include "app/workspace/scene.h"
#include "core/character/demo_character.h"
#include "core/character/skin_mask.h"
#include "core/geometry/mesh_normals.h"
#include "core/io/gltf_writer.h"
#include "core/rig/rig.h"

#if CAGEWRAP_GUI
#include "render/gpu_deformer.h"
#include "render/headless_gl.h"
#endif

namespace cagewrap::app {
namespace {

#if CAGEWRAP_GUI

namespace fs = std::filesystem;

constexpr double kPositionTolerance = 1e-5;  // of the bounding-box diagonal: the bar
// the normals of the combined skin: float combining moves positions by ~1e-7 of the diagonal, which a
// small triangle turns into a larger angle (tests/gpu_deformer_test.cpp's bar)
constexpr double kNormalToleranceDegrees = 0.1;

class GpuStackTest : public test::GlSuite {
 protected:
  void SetUp() override {
    if (no_gl()) GTEST_SKIP() << "no OpenGL 4.3 here, the GPU stack is not tested: " << no_gl_reason();
    dir_ = fs::temp_directory_path() / ("cagewrap-gpu-stack-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // The scene: the coarse demo character (written to a .glb, as the editor opens one) and the demo cage,
  // with `layers` added as one edit; every bind finished.
  std::unique_ptr<Scene> make_scene() {
    DemoCharacterOptions o;
    o.cell_size = 0.05;  // about 3,000 skin points instead of 35,000: the binds and llvmpipe stay quick
    const std::string glb = (dir_ / "coarse.glb").string();
    EXPECT_TRUE(write_glb(glb, make_demo_character(o)).ok());
    auto scene = load_scene(glb, std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_cage.obj");
    EXPECT_TRUE(scene.ok()) << scene.error().message;
    if (!scene.ok()) return nullptr;
    std::unique_ptr<Scene> s = std::move(scene).value();
    const Document& doc = s->work();
    DeformerLayer face;
    face.name = "face";
    face.cage = doc.cage;
    face.params = doc.params;
    face.attachment = doc.attachment;
    face.cage_offsets.assign(face.cage->num_vertices(), glm::vec3(0.0f, 0.01f, 0.03f));
    const std::string head[] = {"head", "neck"};
    auto mask = joint_region_mask(*doc.character, head);
    EXPECT_TRUE(mask.ok());
    if (!mask.ok()) return nullptr;
    face.mask = std::make_shared<const std::vector<float>>(*mask);
    // the cage grown about its centre: another binding of the same skin, and a sculpt that grows with the pose
    std::vector<glm::vec3> grown(doc.cage_positions().begin(), doc.cage_positions().end());
    glm::vec3 centre(0.0f);
    for (const auto& p : grown) centre += p / float(grown.size());
    for (auto& p : grown) p = centre + 1.04f * (p - centre);
    DeformerLayer big = face;
    big.name = "grown";
    big.cage = with_cage_positions(doc, grown).cage;
    big.mask = nullptr;
    big.cage_offsets.assign(big.cage->num_vertices(), glm::vec3(0.0f));
    for (size_t v = 0; v < big.cage_offsets.size(); ++v)
      big.cage_offsets[v] = glm::vec3(0.02f * std::sin(float(v)), 0.0f, 0.015f * std::cos(0.5f * float(v)));
    EXPECT_TRUE(s->apply_work("Add layers", with_layers(doc, {face, big})));
    settle(*s);
    return s;
  }

  // Every bind polled to its end, as the editor's frame loop polls them.
  static void settle(Scene& s) {
    const auto busy = [&] {
      return s.job != nullptr ||
             std::any_of(s.stack_rigs.begin(), s.stack_rigs.end(), [](const StackRig& r) { return r.job != nullptr; }) ||
             std::any_of(s.driver_rigs.begin(), s.driver_rigs.end(), [](const DriverRig& r) { return r.job != nullptr; });
    };
    for (int i = 0; i < 60000 && busy(); ++i) {
      s.poll_bind();
      s.poll_stack();
      if (busy()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_FALSE(busy()) << "the binds did not finish";
    for (const StackRig& r : s.stack_rigs) ASSERT_TRUE(r.rig) << "deformer " << r.deformer << ": " << r.error;
    for (const DriverRig& r : s.driver_rigs) ASSERT_TRUE(r.layer) << "driver '" << r.name << "': " << r.error;
  }

  static Playback at(const Scene& s, const std::string& clip, double t) {
    const auto& clips = s.doc().character->clips;
    Playback pb;
    for (size_t c = 0; c < clips.size(); ++c)
      if (clips[c].name == clip) pb.clip = static_cast<int32_t>(c), pb.player = ClipPlayer(clips[c].duration);
    EXPECT_GE(pb.clip, 0) << clip;
    pb.player.scrub(t);
    return pb;
  }

  // The frame's skin the editor's GPU path makes: the scene builds the maps (skin_on_gpu), the GPU
  // deforms and combines them into `target`. `drop_masks`: as if no layer had a mask.
  std::vector<glm::vec3> gpu_skin(Scene& s, const Playback& pb, std::vector<glm::vec3>* normals = nullptr,
                                  bool drop_masks = false) {
    s.skin_on_gpu = true;
    s.update_pose(pb);
    const GpuFrame& f = s.gpu_frame();
    EXPECT_TRUE(s.skin_from_cage && f.built) << "the scene left the skin to the GPU";
    if (!gpu_) {
      auto g = render::GpuStack::create(s.skin_rest, s.skin_triangles());
      EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.error().message);
      if (!g.ok()) return {};
      gpu_ = std::move(g).value();
      target_ = std::make_unique<render::TriangleBuffer>();
      target_->upload_indices(s.skin_triangles());
    }
    const auto to_gpu = [&](const GpuFrame::Deformed& d) {
      return render::GpuStack::Deformed{d.index, d.deformer, d.revision, drop_masks ? nullptr : d.mask, d.displacement};
    };
    std::optional<render::GpuStack::Deformed> base;
    if (f.base) base = to_gpu(*f.base);
    std::vector<render::GpuStack::Deformed> layers;
    for (const auto& l : f.layers) layers.push_back(to_gpu(l));
    Status st = gpu_->deform(f.stack, base ? &*base : nullptr, layers, *target_);
    EXPECT_TRUE(st.ok()) << (st.ok() ? "" : st.error().message);
    gpu_->normals(*target_);
    std::vector<glm::vec3> out(s.skin_rest.size());
    target_->read_positions(out);
    if (normals) {
      normals->resize(out.size());
      target_->read_normals(*normals);
    }
    return out;
  }

  // The same frame posed on the CPU by the whole document's rig (made once for each set of bindings: a
  // rig poses any document with the same cages, parameters and mutes).
  std::vector<glm::vec3> rig_skin(const Document& d, const Playback& pb) {
    auto rig = std::find_if(rigs_.begin(), rigs_.end(), [&](const Rig& r) { return r.fits(d); });
    if (rig == rigs_.end()) {
      auto made = Rig::create(d);
      EXPECT_TRUE(made.ok()) << made.error().message;
      if (!made.ok()) return {};
      rig = rigs_.insert(rigs_.end(), std::move(made).value());
    }
    std::vector<glm::vec3> skin(rig->num_skin_points());
    PosedCage cage;
    Status s = rig->pose_clip(d, pb.clip, pb.player.time(), pb.pose_override, cage, skin);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return skin;
  }

  // The largest distance between two skins, relative to the diagonal (infinite with a NaN or a size that differs).
  static double gap(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b, double diagonal) {
    if (a.size() != b.size() || a.empty()) return INFINITY;
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      const double d = glm::distance(a[i], b[i]);
      if (!std::isfinite(d)) return INFINITY;
      worst = std::max(worst, d);
    }
    return worst / diagonal;
  }

  // One frame: the GPU's skin and normals against the rig's, and the scene's CPU copy too. Returns the
  // GPU's gap, and records the worst.
  double check(Scene& s, const Playback& pb, const std::string& what) {
    std::vector<glm::vec3> normals;
    const std::vector<glm::vec3> gpu = gpu_skin(s, pb, &normals);
    const std::vector<glm::vec3> cpu = rig_skin(s.work(), pb);
    const double g = gap(gpu, cpu, s.skin_diagonal);
    EXPECT_LE(g, kPositionTolerance) << what;
    // the CPU copy picking and brushes read (the GPU has the frame: the scene deforms and combines it now)
    EXPECT_LE(gap(s.skin_posed(), cpu, s.skin_diagonal), kPositionTolerance) << what << ": the scene's CPU copy";
    std::vector<glm::vec3> cpu_normals(cpu.size());
    NormalComputer(cpu.size(), s.skin_triangles()).compute(cpu, cpu_normals);
    const double degrees = max_normal_angle(normals, cpu_normals) * 180.0 / M_PI;
    EXPECT_LE(degrees, kNormalToleranceDegrees) << what;
    worst_ = std::max(worst_, g);
    worst_normal_ = std::max(worst_normal_, degrees);
    return g;
  }

  fs::path dir_;
  std::unique_ptr<render::GpuStack> gpu_;
  std::unique_ptr<render::TriangleBuffer> target_;  // made with the GPU stack, in the test's GL context
  std::vector<Rig> rigs_;
  double worst_ = 0, worst_normal_ = 0;
};

TEST_F(GpuStackTest, EveryModeMaskAndMuteAgreesWithTheRig) {
  std::unique_ptr<Scene> s = make_scene();
  ASSERT_TRUE(s);
  const double diag = s->skin_diagonal;
  std::printf("  %zu skin points, %zu deformers\n", s->skin_rest.size(), deformer_count(s->work()));
  ASSERT_GT(s->skin_rest.size(), 1000u);
  ASSERT_LT(s->skin_rest.size(), 10000u);
  const Playback frames[] = {at(*s, "walk", 0.3), at(*s, "arm_raise", 1.2)};

  // the document's cage alone (its own rig), to show that the layers change the skin
  Document alone = deformer_document(s->work(), 0);
  for (StackMode mode : {StackMode::kInOrder, StackMode::kSum, StackMode::kBlend}) {
    DeformerStack stack = s->work().stack;
    stack.mode = mode;
    stack.exponent = 2.0;
    s->apply_work("Stack mode", with_stack(s->work(), stack));
    settle(*s);
    for (const Playback& pb : frames) {
      const std::string what = std::string(stack_mode_name(mode)) + " at " + std::to_string(pb.player.time()) + " s";
      check(*s, pb, what);
      const GpuFrame& f = s->gpu_frame();
      ASSERT_TRUE(f.base);
      EXPECT_EQ(f.layers.size(), 2u) << what;
      EXPECT_GT(gap(gpu_skin(*s, pb), rig_skin(alone, pb), diag), 1e-3) << what << ": the layers move the skin";
    }
  }
  // the check can miss: the same frame with the head's mask left out is far from the rig's
  {
    const Playback& pb = frames[0];
    EXPECT_GT(gap(gpu_skin(*s, pb, nullptr, true), rig_skin(s->work(), pb), diag), 100 * kPositionTolerance)
        << "the mask changes the skin";
  }

  // a layer active (the tools edit it): the document's cage is then one of the other rigs
  ASSERT_TRUE(s->set_active_deformer(2));
  settle(*s);
  for (const Playback& pb : frames) check(*s, pb, "blend, layer 2 active");

  // the document's cage muted: f_0 is the rest skin
  DeformerStack stack = s->work().stack;
  stack.mode = StackMode::kInOrder;
  stack.base_muted = true;
  s->apply_work("Mute the cage", with_stack(s->work(), stack));
  settle(*s);
  for (const Playback& pb : frames) {
    check(*s, pb, "in_order, the document's cage muted");
    EXPECT_FALSE(s->gpu_frame().base);
  }
  stack.base_muted = false;
  s->apply_work("Unmute the cage", with_stack(s->work(), stack));

  // a layer muted: left out of the frame
  std::vector<DeformerLayer> layers = s->work().layers;
  layers[0].muted = true;
  s->apply_work("Mute the face", with_layers(s->work(), layers));
  settle(*s);
  for (const Playback& pb : frames) {
    check(*s, pb, "in_order, the face muted");
    ASSERT_EQ(s->gpu_frame().layers.size(), 1u);
    EXPECT_EQ(s->gpu_frame().layers[0].index, 2u);
  }
  std::printf("  worst GPU - rig difference: positions %.2e of the diagonal, normals %.2e degrees\n", worst_,
              worst_normal_);
}

// Parametric drivers on the GPU (Document::more_drivers; the scene binds each in the background): their
// displacements, made on the CPU each frame, go up as slices of the layer table and the combine pass adds
// them where each sits (after every layer, or between the layers in order), scaled by their masks; the frame
// is the rig's within 1e-5 of the diagonal in every mode, and without the drivers it is not.
TEST_F(GpuStackTest, DriversDisplacementsAreAddedOnTheGpuWhereTheySit) {
  std::unique_ptr<Scene> s = make_scene();
  ASSERT_TRUE(s);
  const double diag = s->skin_diagonal;
  const Playback frames[] = {at(*s, "walk", 0.3), at(*s, "arm_raise", 1.2)};
  const Document plain = s->work();
  // the first driver muted (the workspace binds the first; the scene binds the others): two more, sculpted
  auto muted = test::chest_driver(0.06);
  muted->drive_skin = false;
  Document d = with_patch_driver(plain, muted);
  DriverPlacement last, between;
  last.name = "chest";
  between.name = "masked";
  between.after = 1;  // between the face and the grown cage
  const std::string spine[] = {"spine"};
  auto mask = joint_region_mask(*plain.character, spine);
  ASSERT_TRUE(mask.ok());
  between.mask = std::make_shared<const std::vector<float>>(*mask);
  auto pushed = test::chest_driver(0.0);
  auto points = pushed->posed.control_points();
  points[20] += glm::dvec3(0.0, -0.04, 0.05);
  pushed->posed.set_control_points(points);
  d = with_more_drivers(d, {DriverDeformer{test::chest_driver(0.06), last}, DriverDeformer{pushed, between}});
  ASSERT_TRUE(s->apply_work("Add drivers", d));
  settle(*s);
  ASSERT_EQ(s->driver_rigs.size(), 2u);
  for (StackMode mode : {StackMode::kInOrder, StackMode::kSum, StackMode::kBlend}) {
    DeformerStack stack = s->work().stack;
    stack.mode = mode;
    ASSERT_TRUE(s->apply_work("Stack mode", with_stack(s->work(), stack)));
    settle(*s);
    for (const Playback& pb : frames) {
      const std::string what = std::string("drivers, ") + stack_mode_name(mode) + " at " + std::to_string(pb.player.time()) + " s";
      check(*s, pb, what);
      EXPECT_EQ(s->gpu_frame().layers.size(), 4u) << what << ": two layers and two drivers";
      EXPECT_TRUE(s->skin_driven()) << what;
      Document without = s->work();
      without.patch_driver = nullptr;
      without.more_drivers.clear();
      without.revision = next_revision();
      EXPECT_GT(gap(gpu_skin(*s, pb), rig_skin(without, pb), diag), 1e-3) << what << ": the drivers move the skin";
    }
  }
  std::printf("  worst GPU - rig difference with drivers: positions %.2e of the diagonal, normals %.2e degrees\n", worst_,
              worst_normal_);
}

#else

TEST(GpuStackTest, NeedsGl) { GTEST_SKIP() << "built without OpenGL (CAGEWRAP_GUI=OFF): the GPU stack is not tested"; }

#endif

}  // namespace
}  // namespace cagewrap::app
