// The GPU deformer (render/gpu_deformer.h) against the CPU path (core/deformer.h, core/mesh_normals.h):
// the same binding and cage states through both, read back and compared. Positions must agree within
// 1e-5 of the skin's bounding-box diagonal (the performance issue's bar); normals within a small angle.
// Runs in a headless EGL context (Mesa's llvmpipe in CI has compute shaders); skips with a message
// where no OpenGL 4.3 context can be had or the build has no GL.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/cage_import.h"
#include "core/deformer.h"
#include "core/document.h"
#include "core/mesh_io.h"
#include "core/mesh_normals.h"
#include "core/registration.h"
#include "core/rig.h"
#include "core/skinning.h"
#include "core/twist.h"
#include "tests/test_assets.h"

#if CAGEWRAP_GUI
#include "render/gpu_deformer.h"
#include "render/headless_gl.h"
#endif

namespace cagewrap {
namespace {

#if CAGEWRAP_GUI

constexpr double kPositionTolerance = 1e-5;  // of the bounding-box diagonal: the bar
// Normals: the GPU sums the same float cross products in the same order, so they differ from the
// CPU's only through rounding of positions that already agree to ~1e-7 of the diagonal; a tiny
// triangle turns that into a larger angle, so allow a tenth of a degree.
constexpr double kNormalToleranceDegrees = 0.1;

class GpuDeformerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto gl = render::HeadlessGl::create();
    if (!gl) {
      skip_reason_ = gl.error().message;
      return;
    }
    gl_ = std::move(gl).value();
    skip_reason_ = render::GpuDeformer::unsupported_reason();
  }
  static void TearDownTestSuite() { gl_.reset(); }
  void SetUp() override {
    if (!skip_reason_.empty()) GTEST_SKIP() << "no OpenGL 4.3 here, the GPU path is not tested: " << skip_reason_;
  }
  static inline std::unique_ptr<render::HeadlessGl> gl_;
  static inline std::string skip_reason_;
};

struct Agreement {
  double max_distance = 0;  // relative to the diagonal
  double rms_distance = 0;
  double max_normal_degrees = 0;
};

// One cage state through both paths. `gpu_deformer` may be made from another (deliberately wrong)
// table than `cpu`, to show a difference is caught.
struct Paths {
  Deformer& cpu;
  Deformer& gpu_maps;  // the deformer whose maps the GPU applies
  render::GpuDeformer& gpu;
  render::TriangleBuffer& target;
  NormalComputer& normals;
  double diagonal;

  Agreement compare(std::span<const glm::vec3> cage, std::span<const glm::dmat3> frames = {}) {
    const size_t n = cpu.binding().num_points;
    std::vector<glm::vec3> cpu_pos(n), cpu_nrm(n), gpu_pos(n), gpu_nrm(n);
    EXPECT_TRUE(cpu.deform(cage, cpu_pos, frames).ok());
    normals.compute(cpu_pos, cpu_nrm);
    EXPECT_TRUE(gpu_maps.update_maps(cage, frames).ok());
    gpu.deform(target);
    gpu.normals(target);
    target.read_positions(gpu_pos);
    target.read_normals(gpu_nrm);
    Fidelity f = relative_distance(gpu_pos, cpu_pos, diagonal);
    Agreement a;
    a.max_distance = std::isfinite(f.rms) ? f.max : INFINITY;  // a NaN anywhere makes the RMS NaN
    a.rms_distance = f.rms;
    a.max_normal_degrees = max_normal_angle(gpu_nrm, cpu_nrm) * 180.0 / M_PI;
    return a;
  }
};


// The worst agreement seen by a test, printed at its end (the figures docs/benchmarks.md quotes).
struct Worst {
  Agreement a;
  ~Worst() {
    std::printf("  worst GPU - CPU difference: positions %.2e of the diagonal, normals %.2e degrees\n", a.max_distance,
                a.max_normal_degrees);
  }
};

void expect_agreement(const Agreement& a, const std::string& what, Worst& worst) {
  EXPECT_LE(a.max_distance, kPositionTolerance) << what << ": rms " << a.rms_distance;
  EXPECT_LE(a.max_normal_degrees, kNormalToleranceDegrees) << what;
  worst.a.max_distance = std::max(worst.a.max_distance, a.max_distance);
  worst.a.max_normal_degrees = std::max(worst.a.max_normal_degrees, a.max_normal_degrees);
}

// A bench triplet from the shared assets: every variant, the cage moving from rest to the twisted
// cage and beyond (extrapolated), fitted vertex frames (no attachment).
void check_triplet(const std::string& dir, const std::string& mesh_name, Worst& worst) {
  auto mesh = load_mesh(dir + "/" + mesh_name);
  ASSERT_TRUE(mesh.ok()) << mesh.error().message;
  auto cage_mesh = load_cage_mesh(dir + "/cage.obj");
  ASSERT_TRUE(cage_mesh.ok());
  auto cage = make_cage(std::move(cage_mesh).value(), "cage.obj");
  ASSERT_TRUE(cage.ok());
  auto posed = load_mesh(dir + "/cage_posed.obj");
  ASSERT_TRUE(posed.ok());
  const auto triangles = triangulate(*mesh).triangles;
  const double diagonal = bounding_box(mesh->positions).diagonal();
  for (Variant v : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    BindParams params;
    params.variant = v;
    auto b = bind_skin(mesh->positions, *cage, cage->polygons.positions, params);
    ASSERT_TRUE(b.ok()) << b.error().message;
    auto d = Deformer::create(*b, mesh->positions);
    ASSERT_TRUE(d.ok());
    auto gpu = render::GpuDeformer::create(*d, triangles);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    render::TriangleBuffer target;
    target.upload_indices(triangles);
    NormalComputer normals(mesh->positions.size(), triangles);
    Paths paths{*d, *d, **gpu, target, normals, diagonal};
    for (double t : {0.0, 0.35, 1.0, 1.6}) {
      std::vector<glm::vec3> state(cage->num_vertices());
      for (size_t i = 0; i < state.size(); ++i)
        state[i] = glm::mix(cage->polygons.positions[i], posed->positions[i], static_cast<float>(t));
      expect_agreement(paths.compare(state), dir + " " + variant_name(v) + " t=" + std::to_string(t), worst);
    }
  }
}

TEST_F(GpuDeformerTest, BenchTripletsAgreeWithTheCpuPathEveryVariant) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  Worst worst;
  check_triplet(assets + "/bench/mannequiny", "mesh_7136.obj", worst);
  check_triplet(assets + "/bench/armadillo", "mesh_10001.obj", worst);
}

// The demo character posed by its clips through its attachment (the editor's path: the extended
// variant takes the bones' linear parts), every variant.
TEST_F(GpuDeformerTest, DemoCharacterPosedByItsClipsAgreesEveryVariant) {
  const std::string assets = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/";
  auto doc = document_from_files(assets + "demo_character.glb", assets + "demo_cage.obj");
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  const Character& ch = *doc->character;
  std::vector<glm::vec3> skin;
  for (const auto& prim : ch.primitives) skin.insert(skin.end(), prim.positions.begin(), prim.positions.end());
  const auto triangles = triangulate(combined_topology(ch)).triangles;
  auto attachment = attach_cage(ch, doc->cage->polygons.positions, doc->attachment);
  ASSERT_TRUE(attachment.ok()) << attachment.error().message;
  const double diagonal = bounding_box(skin).diagonal();
  ASSERT_GE(ch.clips.size(), 2u);
  Worst worst;
  for (Variant v : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    BindParams params = doc->params;
    params.variant = v;
    Document d = with_params(*doc, params);
    auto b = bind_document(d, skin, &*attachment);
    ASSERT_TRUE(b.ok()) << b.error().message;
    auto def = Deformer::create(*b, skin);
    ASSERT_TRUE(def.ok());
    auto gpu = render::GpuDeformer::create(*def, triangles);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    render::TriangleBuffer target;
    target.upload_indices(triangles);
    NormalComputer normals(skin.size(), triangles);
    Paths paths{*def, *def, **gpu, target, normals, diagonal};
    PosedCage posed;
    for (int clip = 0; clip < 2; ++clip)
      for (double share : {0.0, 0.3, 0.65, 1.0}) {
        pose_document_cage(d, &*attachment, compose_pose(ch, clip, share * ch.clips[clip].duration, false), posed);
        ASSERT_TRUE(posed.attached);
        expect_agreement(paths.compare(posed.positions, cage_vertex_frames(*b, posed)),
                         std::string(variant_name(v)) + " clip " + ch.clips[clip].name + " at " + std::to_string(share),
                         worst);
      }
  }
}

// A maximum distance leaves the points deep inside the armadillo with no element: they follow
// their nearest element rigidly (the fallback pass, which runs after the main one), every variant.
TEST_F(GpuDeformerTest, FallbackPointsAgree) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  const std::string dir = assets + "/bench/armadillo";
  auto mesh = load_mesh(dir + "/mesh_10001.obj");
  ASSERT_TRUE(mesh.ok());
  auto cage_mesh = load_cage_mesh(dir + "/cage.obj");
  ASSERT_TRUE(cage_mesh.ok());
  auto cage = make_cage(std::move(cage_mesh).value(), "cage.obj");
  ASSERT_TRUE(cage.ok());
  auto posed = load_mesh(dir + "/cage_posed.obj");
  ASSERT_TRUE(posed.ok());
  const auto triangles = triangulate(*mesh).triangles;
  const double diagonal = bounding_box(mesh->positions).diagonal();
  Worst worst;
  for (Variant v : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    BindParams params;
    params.variant = v;
    params.max_distance = 0.004 * diagonal;  // points deeper inside than this get no element
    auto b = bind_skin(mesh->positions, *cage, cage->polygons.positions, params);
    ASSERT_TRUE(b.ok()) << b.error().message;
    ASSERT_GT(b->rigid_points.size(), 20u) << "the case must exercise the fallback pass";
    ASSERT_LT(b->rigid_points.size(), mesh->positions.size() / 2);
    auto d = Deformer::create(*b, mesh->positions);
    ASSERT_TRUE(d.ok());
    auto gpu = render::GpuDeformer::create(*d, triangles);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    render::TriangleBuffer target;
    target.upload_indices(triangles);
    NormalComputer normals(mesh->positions.size(), triangles);
    Paths paths{*d, *d, **gpu, target, normals, diagonal};
    expect_agreement(paths.compare(posed->positions), std::string("fallback, ") + variant_name(v), worst);
  }
}

// The check can fail: a GPU table that leaves out one entry of one point (as a kernel skipping an
// element would) is caught by the tolerance, positions and normals both.
TEST_F(GpuDeformerTest, OneSkippedElementIsCaught) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  const std::string dir = assets + "/bench/mannequiny";
  auto mesh = load_mesh(dir + "/mesh_7136.obj");
  ASSERT_TRUE(mesh.ok());
  auto cage_mesh = load_cage_mesh(dir + "/cage.obj");
  ASSERT_TRUE(cage_mesh.ok());
  auto cage = make_cage(std::move(cage_mesh).value(), "cage.obj");
  ASSERT_TRUE(cage.ok());
  auto posed = load_mesh(dir + "/cage_posed.obj");
  ASSERT_TRUE(posed.ok());
  const auto triangles = triangulate(*mesh).triangles;
  const double diagonal = bounding_box(mesh->positions).diagonal();
  for (Variant v : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    BindParams params;
    params.variant = v;
    auto b = bind_skin(mesh->positions, *cage, cage->polygons.positions, params);
    ASSERT_TRUE(b.ok());
    // the point whose weakest entry weighs most, dropped from a copy of the table
    uint32_t point = 0;
    float best = 0;
    for (uint32_t i = 0; i < b->num_points; ++i)
      if (b->offsets[i + 1] - b->offsets[i] >= 2 && b->weights[b->offsets[i + 1] - 1] > best) {
        best = b->weights[b->offsets[i + 1] - 1];
        point = i;
      }
    ASSERT_GT(best, 0.05f);
    Binding skipped = *b;
    const uint32_t entry = skipped.offsets[point + 1] - 1;
    skipped.ids.erase(skipped.ids.begin() + entry);
    skipped.weights.erase(skipped.weights.begin() + entry);
    if (!skipped.bary.empty()) skipped.bary.erase(skipped.bary.begin() + 2 * entry, skipped.bary.begin() + 2 * entry + 2);
    for (uint32_t i = point + 1; i <= skipped.num_points; ++i) skipped.offsets[i]--;
    auto good = Deformer::create(*b, mesh->positions);
    auto bad = Deformer::create(skipped, mesh->positions);
    ASSERT_TRUE(good.ok() && bad.ok());
    auto gpu = render::GpuDeformer::create(*bad, triangles);
    ASSERT_TRUE(gpu.ok());
    render::TriangleBuffer target;
    target.upload_indices(triangles);
    NormalComputer normals(mesh->positions.size(), triangles);
    Paths paths{*good, *bad, **gpu, target, normals, diagonal};
    Agreement a = paths.compare(posed->positions);
    EXPECT_GT(a.max_distance, 100 * kPositionTolerance) << variant_name(v);
    EXPECT_GT(a.max_normal_degrees, kNormalToleranceDegrees) << variant_name(v);
  }
}

// A live set edit changes the table in place (Deformer::stencil_changed); table_changed uploads it
// again and the GPU follows, where the old table would not.
TEST_F(GpuDeformerTest, TableChangedInPlaceIsUploadedAgain) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  const std::string dir = assets + "/bench/mannequiny";
  auto mesh = load_mesh(dir + "/mesh_7136.obj");
  ASSERT_TRUE(mesh.ok());
  auto cage_mesh = load_cage_mesh(dir + "/cage.obj");
  ASSERT_TRUE(cage_mesh.ok());
  auto cage = make_cage(std::move(cage_mesh).value(), "cage.obj");
  ASSERT_TRUE(cage.ok());
  auto posed = load_mesh(dir + "/cage_posed.obj");
  ASSERT_TRUE(posed.ok());
  const auto triangles = triangulate(*mesh).triangles;
  const double diagonal = bounding_box(mesh->positions).diagonal();
  BindParams params;
  params.variant = Variant::kBasic;
  auto first = bind_skin(mesh->positions, *cage, cage->polygons.positions, params);
  params.max_elements = 1;  // another table for the same skin and cage: one element per point
  auto second = bind_skin(mesh->positions, *cage, cage->polygons.positions, params);
  ASSERT_TRUE(first.ok() && second.ok());
  Binding live = *first;
  auto d = Deformer::create(live, mesh->positions);
  ASSERT_TRUE(d.ok());
  auto gpu = render::GpuDeformer::create(*d, triangles);
  ASSERT_TRUE(gpu.ok());
  render::TriangleBuffer target;
  target.upload_indices(triangles);
  NormalComputer normals(mesh->positions.size(), triangles);
  Paths paths{*d, *d, **gpu, target, normals, diagonal};
  Worst worst;
  expect_agreement(paths.compare(posed->positions), "first table", worst);
  live = *second;
  ASSERT_TRUE(d->stencil_changed().ok());
  EXPECT_GT(paths.compare(posed->positions).max_distance, 10 * kPositionTolerance) << "stale table on the GPU";
  ASSERT_TRUE((*gpu)->table_changed().ok());
  expect_agreement(paths.compare(posed->positions), "second table", worst);
}

#else

TEST(GpuDeformerTest, NeedsGl) { GTEST_SKIP() << "built without OpenGL (CAGEWRAP_GUI=OFF): the GPU path is not tested"; }

#endif

}  // namespace
}  // namespace cagewrap
