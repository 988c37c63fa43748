// Patch driver files (core/io/patch_io.h): .cwpatch and glTF extras round trips, and bad files refused
// with messages naming the file and the control point.
#include "core/io/patch_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "tests/expect_error.h"
#include "tests/gltf_validator.h"
#include "tests/patch_fixtures.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;

class PatchIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / ("cagewrap-patch_io-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  // Two grids with awkward doubles (thirds), one Bezier.
  static PatchSurface surface() {
    PatchSurface s{{test::wavy_grid(5, 6), test::wavy_grid(4, 7, PatchBasis::kBezier)}};
    for (glm::dvec3& p : s.grids[0].points) p = p / 3.0 + glm::dvec3(1e-9, -7.25, 1e5);
    return s;
  }
  fs::path dir_;
};

TEST_F(PatchIo, CwpatchRoundTripIsExact) {
  const PatchSurface s = surface();
  ASSERT_TRUE(save_patch(path("a.cwpatch"), s).ok());
  auto back = load_patch(path("a.cwpatch"));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(*back, s);
  auto any = load_patch_any(path("a.cwpatch"));
  ASSERT_TRUE(any.ok());
  EXPECT_EQ(*any, s);
}

TEST_F(PatchIo, GltfExtrasRoundTripIsExactInTextAndBinary) {
  const PatchSurface s = surface();
  for (const char* name : {"a.gltf", "a.glb"}) {
    ASSERT_TRUE(save_patch_any(path(name), s).ok()) << name;
    auto back = load_patch_any(path(name));
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(*back, s) << name;
  }
  // both are valid glTF 2.0 for the Khronos validator (a scene of one node carrying the extras)
  std::string log;
  const int status = test::run_gltf_validator({path("a.gltf"), path("a.glb")}, path("report.txt"), log);
  if (status == 2 || !test::node_available()) GTEST_SKIP() << "the glTF validator is not installed: " << log;
  EXPECT_EQ(status, 0) << log;
}

TEST_F(PatchIo, GltfDriverOnAMeshOfAnotherToolsFileIsFound) {
  // a tool's file: the driver under a mesh's extras, other extras beside it
  Json grid = patch_surface_json(PatchSurface{{test::wavy_grid(4, 4)}});
  Json doc{{"asset", {{"version", "2.0"}}},
           {"nodes", Json::array({Json{{"name", "x"}, {"extras", {{"other", 1}}}}})},
           {"meshes",
            Json::array({Json{{"primitives", Json::array()}}, Json{{"extras", {{kPatchGltfKey, grid}}}}})}};
  const std::string p = write("tool.gltf", doc.dump());
  auto back = load_patch_gltf(p);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->grids.size(), 1u);
  EXPECT_EQ(back->grids[0], test::wavy_grid(4, 4));
  // the error names where the driver was found
  doc["meshes"][1]["extras"][kPatchGltfKey]["grids"][0]["points"][2][1] = Json::array({0, nullptr, 0});
  const std::string q = write("bad.gltf", doc.dump());
  EXPECT_TRUE(Fails(load_patch_gltf(q), ErrorCode::kNonFinite,
                    {"bad.gltf", "meshes[1].extras.cagewrap_patch", "row 2 column 1", "coordinate y"}));
}

TEST_F(PatchIo, BadFilesAreRefusedNamingFileAndControlPoint) {
  auto grid_text = [](const std::string& rows_json, const std::string& extra = "") {
    return R"({"format": "cagewrap-patch", "version": 1, "grids": [{"basis": "bspline", )" + extra +
           rows_json + "}]}";
  };
  auto row = [](int n, double y = 0) {
    std::string r = "[";
    for (int c = 0; c < n; ++c)
      r += (c ? ", " : "") + std::string("[") + std::to_string(c) + ", " + std::to_string(y) + ", 0]";
    return r + "]";
  };
  // a row shorter than cols
  std::string rows = "\"rows\": 4, \"cols\": 4, \"points\": [" + row(4) + ", " + row(4) + ", " + row(3) +
                     ", " + row(4) + "]";
  EXPECT_TRUE(Fails(load_patch(write("short.cwpatch", grid_text(rows))), ErrorCode::kTopologyMismatch,
                    {"short.cwpatch", "grid 0 row 2", "3 control points", "cols is 4"}));
  // fewer rows than declared
  rows = "\"rows\": 5, \"cols\": 4, \"points\": [" + row(4) + ", " + row(4) + ", " + row(4) + ", " + row(4) +
         "]";
  EXPECT_TRUE(Fails(load_patch(write("rows.cwpatch", grid_text(rows))), ErrorCode::kTopologyMismatch,
                    {"rows.cwpatch", "4 rows", "rows is 5"}));
  // a grid too small for a bicubic
  rows = "\"rows\": 3, \"cols\": 4, \"points\": [" + row(4) + ", " + row(4) + ", " + row(4) + "]";
  EXPECT_TRUE(Fails(load_patch(write("small.cwpatch", grid_text(rows))), ErrorCode::kInvalidArgument,
                    {"small.cwpatch", "3 x 4", "at least 4 x 4"}));
  // a non-finite control point (JSON writers put null for NaN)
  rows = "\"rows\": 4, \"cols\": 4, \"points\": [" + row(4) +
         ", [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, null, 0]], " + row(4) + ", " + row(4) + "]";
  EXPECT_TRUE(Fails(load_patch(write("nan.cwpatch", grid_text(rows))), ErrorCode::kNonFinite,
                    {"nan.cwpatch", "row 1 column 3", "coordinate y"}));
  // an unknown basis, a Bezier grid of the wrong size
  rows = "\"rows\": 4, \"cols\": 4, \"points\": [" + row(4) + ", " + row(4) + ", " + row(4) + ", " + row(4) +
         "]";
  EXPECT_TRUE(
      Fails(load_patch(write("basis.cwpatch",
                             R"({"format": "cagewrap-patch", "grids": [{"basis": "nurbs", )" + rows + "}]}")),
            ErrorCode::kParse, {"basis.cwpatch", "grids[0].basis", "nurbs"}));
  rows = "\"rows\": 5, \"cols\": 4, \"points\": [" + row(4) + ", " + row(4) + ", " + row(4) + ", " + row(4) +
         ", " + row(4) + "]";
  EXPECT_TRUE(Fails(
      load_patch(write("bez.cwpatch",
                       R"({"format": "cagewrap-patch", "grids": [{"basis": "bezier", )" + rows + "}]}")),
      ErrorCode::kInvalidArgument, {"bez.cwpatch", "3 m + 1"}));
  // not a patch file, not JSON, a newer version, missing file
  EXPECT_TRUE(Fails(load_patch(write("other.cwpatch", "{\"grids\": []}")), ErrorCode::kUnsupportedFormat,
                    {"other.cwpatch", "cagewrap-patch"}));
  EXPECT_TRUE(Fails(load_patch(write("text.cwpatch", "grids")), ErrorCode::kParse, {"text.cwpatch"}));
  EXPECT_TRUE(
      Fails(load_patch(write("new.cwpatch", R"({"format": "cagewrap-patch", "version": 9, "grids": []})")),
            ErrorCode::kVersion, {"new.cwpatch", "version 9"}));
  EXPECT_TRUE(Fails(load_patch(path("missing.cwpatch")), ErrorCode::kFileNotFound, {"missing.cwpatch"}));
  // a glTF file without a driver, a truncated .glb
  EXPECT_TRUE(Fails(load_patch_gltf(write("plain.gltf", R"({"asset": {"version": "2.0"}, "nodes": [{}]})")),
                    ErrorCode::kEmpty, {"plain.gltf", "no node or mesh", "cagewrap_patch"}));
  ASSERT_TRUE(save_patch_any(path("t.glb"), surface()).ok());
  fs::resize_file(path("t.glb"), 40);
  EXPECT_TRUE(Fails(load_patch_gltf(path("t.glb")), ErrorCode::kParse, {"t.glb", "JSON chunk"}));
  // saving refuses what it could not load back
  PatchSurface nan = surface();
  nan.grids[1].points[3].z = std::nan("");
  EXPECT_TRUE(Fails(save_patch(path("x.cwpatch"), nan), ErrorCode::kNonFinite,
                    {"x.cwpatch", "grid 1", "row 0 column 3"}));
  EXPECT_FALSE(fs::exists(path("x.cwpatch")));
}

}  // namespace
}  // namespace cagewrap
