// The GPU deformer (render/gpu_deformer.h) against the CPU path (core/deform/deformer.h, core/geometry/mesh_normals.h):
// the same binding and cage states through both, read back and compared. Positions must agree within
// 1e-5 of the skin's bounding-box diagonal (the performance issue's bar); normals within a small angle.
// Runs in a headless EGL context (Mesa's llvmpipe in CI has compute shaders); skips with a message
// where no OpenGL 4.3 context can be had or the build has no GL.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tests/gl_fixtures.h"
#include "core/cage/cage.h"
#include "core/io/cage_import.h"
#include "core/deform/deformer.h"
#include "core/document/document.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/mesh_normals.h"
#include "core/geometry/subdivide.h"
#include "core/deform/registration.h"
#include "core/rig/rig.h"
#include "core/character/skinning.h"
#include "core/deform/twist.h"
#include "tests/fixtures.h"
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

class GpuDeformerTest : public test::GlSuite {
 protected:
  void SetUp() override {
    if (no_gl()) GTEST_SKIP() << "no OpenGL 4.3 here, the GPU path is not tested: " << no_gl_reason();
  }
};

struct Agreement {
  double max_distance = 0;  // relative to the diagonal
  double rms_distance = 0;
  double max_normal_degrees = 0;
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

// A skin with its triangles, and a cage at rest.
struct GpuTestSkin {
  std::vector<glm::vec3> rest;
  std::vector<Tri> triangles;
  double diagonal = 0;
};

// A bench triplet from the shared assets: the skin, the cage and the twisted cage.
struct Triplet {
  GpuTestSkin skin;
  std::optional<Cage> cage;
  std::vector<glm::vec3> posed;
};

Triplet load_triplet(const std::string& dir, const std::string& mesh_name, uint32_t subdivide = 0) {
  Triplet t;
  auto mesh = load_mesh(dir + "/" + mesh_name);
  if (mesh.ok() && subdivide > 0) *mesh = subdivide_edges_uniform(*mesh, subdivide);
  EXPECT_TRUE(mesh.ok()) << (mesh.ok() ? "" : mesh.error().message);
  auto cage_mesh = load_cage_mesh(dir + "/cage.obj");
  auto posed = load_mesh(dir + "/cage_posed.obj");
  EXPECT_TRUE(cage_mesh.ok() && posed.ok()) << dir;
  if (!mesh.ok() || !cage_mesh.ok() || !posed.ok()) return t;
  auto cage = make_cage(std::move(cage_mesh).value(), "cage.obj");
  EXPECT_TRUE(cage.ok());
  if (!cage.ok()) return t;
  t.cage.emplace(std::move(cage).value());
  t.skin.triangles = triangulate(*mesh).triangles;
  t.skin.rest = std::move(mesh->positions);
  t.skin.diagonal = bounding_box(t.skin.rest).diagonal();
  t.posed = std::move(posed->positions);
  return t;
}

// Both paths over one binding. The GPU may apply the maps of another deformer (`gpu_maps`, made
// from a deliberately wrong table) to show that a difference is caught.
class Paths {
 public:
  Paths(Deformer& cpu, const GpuTestSkin& skin, Deformer* gpu_maps = nullptr)
      : cpu_(cpu), gpu_maps_(gpu_maps ? *gpu_maps : cpu), skin_(skin), normals_(skin.rest.size(), skin.triangles) {
    target_.upload_indices(skin.triangles);
    auto g = render::GpuDeformer::create(gpu_maps_, skin.triangles);
    EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.error().message);
    if (g.ok()) gpu_ = std::move(g).value();
  }
  bool ok() const { return gpu_ != nullptr; }
  render::GpuDeformer& gpu() { return *gpu_; }

  // One cage state through both paths, read back and compared.
  Agreement compare(std::span<const glm::vec3> cage, std::span<const glm::dmat3> frames = {}) {
    const size_t n = skin_.rest.size();
    std::vector<glm::vec3> cpu_pos(n), cpu_nrm(n), gpu_pos(n), gpu_nrm(n);
    EXPECT_TRUE(cpu_.deform(cage, cpu_pos, frames).ok());
    normals_.compute(cpu_pos, cpu_nrm);
    EXPECT_TRUE(gpu_maps_.update_maps(cage, frames).ok());
    gpu_->deform(target_);
    gpu_->normals(target_);
    target_.read_positions(gpu_pos);
    target_.read_normals(gpu_nrm);
    Fidelity f = relative_distance(gpu_pos, cpu_pos, skin_.diagonal);
    Agreement a;
    a.max_distance = std::isfinite(f.rms) ? f.max : INFINITY;  // a NaN anywhere makes the RMS NaN
    a.rms_distance = f.rms;
    a.max_normal_degrees = max_normal_angle(gpu_nrm, cpu_nrm) * 180.0 / M_PI;
    return a;
  }

 private:
  Deformer& cpu_;
  Deformer& gpu_maps_;
  const GpuTestSkin& skin_;
  NormalComputer normals_;
  render::TriangleBuffer target_;
  std::unique_ptr<render::GpuDeformer> gpu_;
};

constexpr Variant kVariants[] = {Variant::kBasic, Variant::kClamped, Variant::kExtended};

Binding bind_triplet(const Triplet& t, BindParams params) {
  auto b = bind_skin(t.skin.rest, *t.cage, t.cage->polygons.positions, params);
  EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error().message);
  return b.ok() ? std::move(b).value() : Binding{};
}

// Every variant, the cage moving from rest to the twisted cage and beyond (extrapolated), vertex
// frames fitted from the one-rings (no attachment). Both tables: the compact one where the deformer
// makes it (at 64k points, subdivided, for basic and extended; the original meshes' vertex order is too
// scattered for some variants, and the clamped variant's three weight rows outweigh its float table
// below ~180k points: those keep the float table; CompactClampedTableAgrees covers it) and the float one.
void check_triplet(const std::string& dir, const std::string& mesh_name, Worst& worst, uint32_t subdivide = 0) {
  const Triplet t = load_triplet(dir, mesh_name, subdivide);
  ASSERT_TRUE(t.cage);
  for (Variant v : kVariants) {
    BindParams params;
    params.variant = v;
    const Binding b = bind_triplet(t, params);
    // the compact table both paths read by default (core/deform/kernel_table.h), and the float table
    for (TableFormat format : {TableFormat::kCompact, TableFormat::kFloat}) {
    auto d = Deformer::create(b, t.skin.rest, format);
    ASSERT_TRUE(d.ok());
    if (format == TableFormat::kFloat || (subdivide > 0 && v != Variant::kClamped))
      EXPECT_EQ(d->kernel_table() != nullptr, format == TableFormat::kCompact) << dir << " " << variant_name(v);
    Paths paths(*d, t.skin);
    ASSERT_TRUE(paths.ok());
    EXPECT_EQ(paths.gpu().reads_compact_table(), d->kernel_table() != nullptr) << "the GPU reads the CPU's table";
    for (float share : {0.0f, 0.35f, 1.0f, 1.6f}) {
      std::vector<glm::vec3> state(t.posed.size());
      for (size_t i = 0; i < state.size(); ++i) state[i] = glm::mix(t.cage->polygons.positions[i], t.posed[i], share);
      expect_agreement(paths.compare(state), dir + " " + variant_name(v) + " at " + std::to_string(share), worst);
    }
    }
  }
}

TEST_F(GpuDeformerTest, BenchTripletsAgreeWithTheCpuPathEveryVariant) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  Worst worst;
  check_triplet(assets + "/bench/mannequiny", "mesh_7136.obj", worst);
  check_triplet(assets + "/bench/armadillo", "mesh_10001.obj", worst);
  check_triplet(assets + "/bench/mannequiny", "mesh_7136.obj", worst, 2);
}

// The clamped variant's compact table (three 24-bit weight rows) through both paths: a cylinder whose
// vertex order is coherent enough for it, bent and twisted.
TEST_F(GpuDeformerTest, CompactClampedTableAgrees) {
  const PolyMesh mesh = fixtures::cylinder_skin(0.5, 4.0, 37, 41);
  const Cage cage = fixtures::cylinder_cage();
  GpuTestSkin skin;
  skin.rest = mesh.positions;
  skin.triangles = triangulate(mesh).triangles;
  skin.diagonal = bounding_box(skin.rest).diagonal();
  BindParams params;
  params.variant = Variant::kClamped;
  auto b = bind_skin(skin.rest, cage, cage.polygons.positions, params);
  ASSERT_TRUE(b.ok());
  auto d = Deformer::create(*b, skin.rest);
  ASSERT_TRUE(d.ok());
  ASSERT_NE(d->kernel_table(), nullptr);
  ASSERT_TRUE(d->kernel_table()->rigid);
  Paths paths(*d, skin);
  ASSERT_TRUE(paths.ok());
  EXPECT_TRUE(paths.gpu().reads_compact_table());
  Worst worst;
  for (double degrees : {30.0, 75.0, 120.0})
    expect_agreement(paths.compare(fixtures::bent(cage.polygons.positions, 2.0, degrees)),
                     "clamped, bent " + std::to_string(degrees), worst);
}

// The demo character posed by its clips through its attachment (the editor's path: the extended
// variant takes the bones' linear parts), every variant.
TEST_F(GpuDeformerTest, DemoCharacterPosedByItsClipsAgreesEveryVariant) {
  const std::string assets = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/";
  auto doc = document_from_files(assets + "demo_character.glb", assets + "demo_cage.obj");
  ASSERT_TRUE(doc.ok()) << doc.error().message;
  const Character& ch = *doc->character;
  GpuTestSkin skin;
  for (const auto& prim : ch.primitives) skin.rest.insert(skin.rest.end(), prim.positions.begin(), prim.positions.end());
  skin.triangles = triangulate(combined_topology(ch)).triangles;
  skin.diagonal = bounding_box(skin.rest).diagonal();
  auto attachment = attach_cage(ch, doc->cage->polygons.positions, doc->attachment);
  ASSERT_TRUE(attachment.ok()) << attachment.error().message;
  ASSERT_GE(ch.clips.size(), 2u);
  Worst worst;
  for (Variant v : kVariants) {
    BindParams params = doc->params;
    params.variant = v;
    Document d = with_params(*doc, params);
    auto b = bind_document(d, skin.rest, &*attachment);
    ASSERT_TRUE(b.ok()) << b.error().message;
    auto def = Deformer::create(*b, skin.rest);
    ASSERT_TRUE(def.ok());
    Paths paths(*def, skin);
    ASSERT_TRUE(paths.ok());
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
  const Triplet t = load_triplet(assets + "/bench/armadillo", "mesh_10001.obj");
  ASSERT_TRUE(t.cage);
  Worst worst;
  for (Variant v : kVariants) {
    BindParams params;
    params.variant = v;
    params.max_distance = 0.004 * t.skin.diagonal;  // points deeper inside than this: their nearest element
    auto bound = bind_skin(t.skin.rest, *t.cage, t.cage->polygons.positions, params,
                           fixtures::empty_set_edits(t.skin.rest.size(), 97));  // and the rigid fallback
    ASSERT_TRUE(bound.ok()) << bound.error().message;
    const Binding b = std::move(bound).value();
    ASSERT_GT(b.rigid_points.size(), 20u) << "the case must exercise the fallback pass";
    ASSERT_LT(b.rigid_points.size(), t.skin.rest.size() / 2);
    auto d = Deformer::create(b, t.skin.rest);
    ASSERT_TRUE(d.ok());
    Paths paths(*d, t.skin);
    ASSERT_TRUE(paths.ok());
    expect_agreement(paths.compare(t.posed), std::string("fallback, ") + variant_name(v), worst);
  }
}

// The check can fail: a GPU table that leaves out one entry of one point (as a kernel skipping an
// element would) is caught by the tolerance, positions and normals both.
TEST_F(GpuDeformerTest, OneSkippedElementIsCaught) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  const Triplet t = load_triplet(assets + "/bench/mannequiny", "mesh_7136.obj");
  ASSERT_TRUE(t.cage);
  for (Variant v : kVariants) {
    BindParams params;
    params.variant = v;
    const Binding b = bind_triplet(t, params);
    // the point whose weakest entry weighs most, dropped from a copy of the table
    uint32_t point = 0;
    float best = 0;
    for (uint32_t i = 0; i < b.num_points; ++i)
      if (b.offsets[i + 1] - b.offsets[i] >= 2 && b.weights[b.offsets[i + 1] - 1] > best) {
        best = b.weights[b.offsets[i + 1] - 1];
        point = i;
      }
    ASSERT_GT(best, 0.05f);
    Binding skipped = b;
    const uint32_t entry = skipped.offsets[point + 1] - 1;
    skipped.ids.erase(skipped.ids.begin() + entry);
    skipped.weights.erase(skipped.weights.begin() + entry);
    if (!skipped.bary.empty()) skipped.bary.erase(skipped.bary.begin() + 2 * entry, skipped.bary.begin() + 2 * entry + 2);
    for (uint32_t i = point + 1; i <= skipped.num_points; ++i) skipped.offsets[i]--;
    auto good = Deformer::create(b, t.skin.rest);
    auto bad = Deformer::create(skipped, t.skin.rest);
    ASSERT_TRUE(good.ok() && bad.ok());
    Paths paths(*good, t.skin, &*bad);
    ASSERT_TRUE(paths.ok());
    Agreement a = paths.compare(t.posed);
    EXPECT_GT(a.max_distance, 100 * kPositionTolerance) << variant_name(v);
    EXPECT_GT(a.max_normal_degrees, kNormalToleranceDegrees) << variant_name(v);
  }
}

// Skins too large for one row of work groups are dispatched on a 2-D grid: forced here with three
// groups (768 invocations) per row on a 7,136-point skin (10 rows), whose 13,932 triangles take 19.
TEST_F(GpuDeformerTest, TwoDimensionalDispatchCoversEveryPoint) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  const Triplet t = load_triplet(assets + "/bench/mannequiny", "mesh_7136.obj");
  ASSERT_TRUE(t.cage);
  BindParams params;
  params.variant = Variant::kBasic;
  const Binding b = bind_triplet(t, params);
  auto d = Deformer::create(b, t.skin.rest);
  ASSERT_TRUE(d.ok());
  Paths paths(*d, t.skin);
  ASSERT_TRUE(paths.ok());
  paths.gpu().limit_groups_per_row(3);
  Worst worst;
  expect_agreement(paths.compare(t.posed), "2-D grid", worst);
}

// A live set edit changes the table in place (Deformer::stencil_changed); table_changed uploads it
// again and the GPU follows, where the old table would not.
TEST_F(GpuDeformerTest, TableChangedInPlaceIsUploadedAgain) {
  CAGEWRAP_REQUIRE_ASSETS(assets);
  const Triplet t = load_triplet(assets + "/bench/mannequiny", "mesh_7136.obj");
  ASSERT_TRUE(t.cage);
  BindParams params;
  params.variant = Variant::kBasic;
  const Binding first = bind_triplet(t, params);
  params.max_elements = 1;  // another table for the same skin and cage: one element per point
  const Binding second = bind_triplet(t, params);
  Binding live = first;
  auto d = Deformer::create(live, t.skin.rest);
  ASSERT_TRUE(d.ok());
  Paths paths(*d, t.skin);
  ASSERT_TRUE(paths.ok());
  Worst worst;
  expect_agreement(paths.compare(t.posed), "first table", worst);
  live = second;
  ASSERT_TRUE(d->stencil_changed().ok());
  EXPECT_GT(paths.compare(t.posed).max_distance, 10 * kPositionTolerance) << "stale table on the GPU";
  ASSERT_TRUE(paths.gpu().table_changed().ok());
  expect_agreement(paths.compare(t.posed), "second table", worst);
}

#else

TEST(GpuDeformerTest, NeedsGl) { GTEST_SKIP() << "built without OpenGL (CAGEWRAP_GUI=OFF): the GPU path is not tested"; }

#endif

}  // namespace
}  // namespace cagewrap
