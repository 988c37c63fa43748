// Writes the fuzz harnesses' seed corpora, made by the project's own writers so they follow the
// formats as they change: `cagewrap_fuzz_seeds OUT` fills OUT/<harness> for gltf, gltf_rig, mesh,
// project, set_edits, patch, binding and assimp (the last from assimp-testmodels: no writer of ours makes FBX). Each harness's seeds also hold the hostile corpus of its
// format (tests/tools/hostile_corpus.h: small files claiming huge counts) and the valid files they
// were made from. Run by scripts/fuzz.sh before each fuzzing run.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/io/binding_io.h"
#include "core/document/document.h"
#include "core/geometry/mesh_io.h"
#include "core/document/character_embedding.h"
#include "core/document/project_io.h"
#include "core/io/patch_io.h"
#include "core/deform/registration.h"
#include "core/io/set_edits_io.h"
#include "tests/fixtures.h"
#include "tests/fuzz/seed_fixtures.h"
#include "tests/tools/hostile_corpus.h"

namespace fs = std::filesystem;
using namespace cagewrap;

static std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
static void write_all(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}
static void fail(const std::string& what) {
  std::fprintf(stderr, "error: %s\n", what.c_str());
  std::exit(1);
}

int main(int argc, char** argv) {
  if (argc != 2) fail("usage: cagewrap_fuzz_seeds OUT");
  const fs::path out = argv[1];
  for (const char* d : {"gltf", "gltf_rig", "mesh", "project", "set_edits", "patch", "binding", "assimp", "scratch"})
    fs::create_directories(out / d);
  const std::string scratch = (out / "scratch").string();

  // glTF: embedded .gltf, .glb, and a skinned one with two joints and a clip
  fuzz::tet_builder().write_embedded((out / "gltf" / "tet.gltf").string());
  fuzz::tet_builder().write_glb((out / "gltf" / "tet.glb").string());
  fuzz::rig_builder().write_glb((out / "gltf" / "skinned.glb").string());
  // glTF rigs: a skin with inverse bind matrices and a clip, LINEAR translation; STEP rotation and
  // CUBICSPLINE scale on the root added
  fuzz::rig_builder().write_glb((out / "gltf_rig" / "rig.glb").string());
  fuzz::rig_builder().write_embedded((out / "gltf_rig" / "rig.gltf").string());
  {
    test::GltfBuilder b = fuzz::rig_builder();
    int times = b.add_floats({0.0f, 1.0f}, "SCALAR", true);
    int turns = b.add_floats({0, 0, 0, 1, 0, 0.7071068f, 0, 0.7071068f}, "VEC4");
    // CUBICSPLINE: in-tangent, value, out-tangent per key
    int scales = b.add_floats({0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 1.5f, 1, 1, 0, 0, 0}, "VEC3");
    const int root = static_cast<int>(b.doc["nodes"].size()) - 1;
    auto& anim = b.doc["animations"][0];
    anim["samplers"].push_back({{"input", times}, {"output", turns}, {"interpolation", "STEP"}});
    anim["samplers"].push_back({{"input", times}, {"output", scales}, {"interpolation", "CUBICSPLINE"}});
    anim["channels"].push_back({{"sampler", 1}, {"target", {{"node", root}, {"path", "rotation"}}}});
    anim["channels"].push_back({{"sampler", 2}, {"target", {{"node", root}, {"path", "scale"}}}});
    b.write_glb((out / "gltf_rig" / "rig_step_cubic.glb").string());
  }

  // meshes: the first byte picks the format (fuzz_mesh.cpp)
  Cage cage = fixtures::box_cage(1.0, 2);
  const std::string obj = scratch + "/cage.obj";
  if (!save_obj(obj, cage.polygons.positions, cage.polygons).ok()) fail("cannot write " + obj);
  write_all((out / "mesh" / "cage.obj").string(), std::string(1, '\0') + read_all(obj));
  write_all((out / "mesh" / "tet.off").string(),
            std::string(1, '\1') + "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  write_all((out / "mesh" / "tet.ply").string(),
            std::string(1, '\2') +
                "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                "3 0 2 1\n4 0 1 3 2\n");
  {
    std::string ply = std::string(1, '\2') +
                      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    ply.append(reinterpret_cast<const char*>(v), sizeof v);
    const uint8_t n = 3;
    const int32_t f[3] = {0, 1, 2};
    ply.append(reinterpret_cast<const char*>(&n), 1);
    ply.append(reinterpret_cast<const char*>(f), sizeof f);
    write_all((out / "mesh" / "tri_binary.ply").string(), ply);
  }
  write_all((out / "mesh" / "tri.stl").string(),
            std::string(1, '\3') +
                "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                "endfacet\nendsolid t\n");
  {
    std::string stl(80, ' ');
    const uint32_t count = 1;
    stl.append(reinterpret_cast<const char*>(&count), 4);
    const float t[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    stl.append(reinterpret_cast<const char*>(t), sizeof t);
    stl.append(2, '\0');
    write_all((out / "mesh" / "tri_binary.stl").string(), std::string(1, '\3') + stl);
  }

  // project: names hero.gltf beside it (fuzz_project.cpp writes one there)
  fuzz::write_tet_gltf(scratch + "/hero.gltf");
  auto doc = document_from_files(scratch + "/hero.gltf", obj);
  if (!doc.ok()) fail(doc.error().message);
  const std::string project = scratch + "/p.cagewrap";
  if (auto s = save_project(project, with_set_edits(*doc, {SetEdit{1, {0, 3}, {}}, SetEdit{2, {}, {5}}})); !s.ok())
    fail(s.error().message);
  fs::copy_file(project, out / "project" / "edits.cagewrap", fs::copy_options::overwrite_existing);
  auto bare = document_from_files(scratch + "/hero.gltf", "");
  if (!bare.ok()) fail(bare.error().message);
  if (auto s = save_project(project, *bare); !s.ok()) fail(s.error().message);
  fs::copy_file(project, out / "project" / "no_cage.cagewrap", fs::copy_options::overwrite_existing);
  // version 3: the character embedded (base64), a binding cache record (caching on, nothing cached)
  auto embedded = embed_character(with_cache_binding(*doc, true));
  if (!embedded.ok()) fail(embedded.error().message);
  if (auto s = save_project(project, *embedded); !s.ok()) fail(s.error().message);
  fs::copy_file(project, out / "project" / "embedded.cagewrap", fs::copy_options::overwrite_existing);

  // set edits: a saved file and one with rules
  const std::string edits = (out / "set_edits" / "saved.json").string();
  std::vector<SetEdit> list = {SetEdit{0, {1, 2}, {}}, SetEdit{3, {}, {4}}};
  if (auto s = save_set_edits(edits, list, 4, cage.num_elements()); !s.ok()) fail(s.error().message);
  write_all((out / "set_edits" / "rules.json").string(),
            R"({"format": "cagewrap-set-edits", "version": 1, "points": 4, "rules": [)"
            R"({"mode": "remove", "points": [0, 1], "faces": [0, 1], "mirror": 0.5}, {"mode": "only", "points": [2], "faces": [3]},)"
            R"({"mode": "add", "points": [3], "faces": [5]}, {"mode": "reset", "points": [1]}]})");
  // patch drivers: a saved .cwpatch (a B-spline and a Bezier grid) and the same in glTF extras
  PatchSurface driver;
  for (PatchBasis basis : {PatchBasis::kBSpline, PatchBasis::kBezier}) {
    PatchGrid g;
    g.basis = basis;
    g.rows = 4;
    g.cols = basis == PatchBasis::kBezier ? 7 : 5;
    for (uint32_t r = 0; r < g.rows; ++r)
      for (uint32_t c = 0; c < g.cols; ++c) g.points.push_back({double(c), 0.1 * r * c, double(r)});
    driver.grids.push_back(g);
  }
  if (auto s = save_patch((out / "patch" / "driver.cwpatch").string(), driver); !s.ok()) fail(s.error().message);
  if (auto s = write_patch_gltf((out / "patch" / "driver.gltf").string(), driver); !s.ok()) fail(s.error().message);

  // bindings: a sphere bound to the box cage, extended (with its set table) and clamped (anchors, and
  // fallback points where set edits empty a point's set)
  {
    const PolyMesh skin = fixtures::sphere_skin(0.5, 4, 6);
    BindParams clamped;
    clamped.variant = Variant::kClamped;
    for (const auto& [name, params, edits] :
         {std::tuple{"extended.cwb", BindParams{}, std::vector<SetEdit>{}},
          std::tuple{"clamped.cwb", clamped, fixtures::empty_set_edits(skin.num_vertices(), 5)}}) {
      auto b = bind_skin(skin.positions, cage, cage.polygons.positions, params, edits);
      if (!b.ok()) fail(b.error().message);
      write_all((out / "binding" / name).string(), binding_bytes(*b));
    }
  }

  // the hostile corpus and its originals, each in the seeds of the harnesses that read its format
  const hostile::Corpus corpus = hostile::hostile_corpus(scratch);
  for (const auto* files : {&corpus.originals, &corpus.hostile})
    for (const hostile::HostileFile& f : *files) {
      switch (f.loader) {
        case hostile::Loader::kCharacter:
          write_all((out / "gltf" / f.name).string(), f.bytes);
          write_all((out / "gltf_rig" / f.name).string(), f.bytes);
          break;
        case hostile::Loader::kMesh: {
          // fuzz_mesh's first byte picks the format: 0 OBJ, 1 OFF, 2 PLY, 3 STL
          const char format = has_extension(f.name, ".obj") ? 0 : has_extension(f.name, ".off") ? 1
                              : has_extension(f.name, ".ply")   ? 2
                                                                : 3;
          write_all((out / "mesh" / f.name).string(), std::string(1, format) + f.bytes);
          break;
        }
        case hostile::Loader::kProject:
          write_all((out / "project" / f.name).string(), f.bytes);
          break;
        case hostile::Loader::kSetEdits:
          write_all((out / "set_edits" / f.name).string(), f.bytes);
          break;
        case hostile::Loader::kPatch:
        case hostile::Loader::kPatchGltf:  // fuzz_patch reads its input both ways
          write_all((out / "patch" / f.name).string(), f.bytes);
          break;
        case hostile::Loader::kBinding:
          write_all((out / "binding" / f.name).string(), f.bytes);
          break;
      }
    }
  // FBX, Collada, DirectX, MilkShape, MD5 and SMD (fuzz_assimp): no writer of ours makes them; the small files of
  // assimp-testmodels (scripts/setup.sh installs it; $CAGEWRAP_ASSIMP_MODELS elsewhere), skinned and animated ones
  // among them, when it is there
  const char* models_env = std::getenv("CAGEWRAP_ASSIMP_MODELS");
  const fs::path models = models_env && *models_env ? models_env : "/usr/share/assimp/models";
  size_t assimp_seeds = 0;
  for (const char* f : {"FBX/box.fbx", "FBX/phong_cube.fbx", "Collada/box_nested_animation.dae", "Collada/cube_triangulate.dae",
                        "Collada/kwxport_test_vcolors.dae", "X/test_cube_text.x", "X/test_cube_binary.x", "X/test_cube_compressed.x",
                        "MS3D/twospheres.ms3d", "MD5/SimpleCube.md5mesh", "SMD/triangle.smd"}) {
    std::error_code ec;
    if (!fs::is_regular_file(models / f, ec) || fs::file_size(models / f, ec) > 65536) continue;
    fs::copy_file(models / f, out / "assimp" / fs::path(f).filename(), fs::copy_options::overwrite_existing, ec);
    assimp_seeds += !ec;
  }
  if (!assimp_seeds) std::fprintf(stderr, "note: %s is absent (assimp-testmodels): fuzz_assimp starts from no seed\n", models.string().c_str());
  fs::remove_all(scratch);
  return 0;
}
