// Small files for the document, history and project tests: a tiny character (.gltf written by the
// tests' own GltfBuilder), cages as OBJ, and a temporary folder per test.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/geometry/mesh_io.h"
#include "tests/fixtures.h"
#include "tests/gltf_builder.h"

namespace cagewrap::test {

// A tetrahedron with 4 vertices and 4 triangles, one unskinned node; `shift` moves it (a different
// file with the same structure).
inline void write_tiny_character(const std::string& path, float shift = 0.0f) {
  GltfBuilder b;
  std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (float& x : positions) x += shift;
  std::vector<uint16_t> indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  int pos = b.add_floats(positions, "VEC3", true);
  nlohmann::json prim = {{"attributes", {{"POSITION", pos}}},
                         {"indices", b.add_accessor(indices, "SCALAR", kUnsignedShort)}};
  b.doc["meshes"].push_back({{"name", "tet"}, {"primitives", {prim}}});
  b.set_scene({b.add_node({{"name", "tet_node"}, {"mesh", 0}})});
  b.write_embedded(path);
}

inline void write_box_cage(const std::string& path, double size = 2.0, int n = 2) {
  Cage cage = fixtures::box_cage(size, n);
  ASSERT_TRUE(save_obj(path, cage.polygons.positions, cage.polygons).ok());
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// A fresh folder named after the running test, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("cagewrap-" + std::string(info->test_suite_name()) + "-" + info->name() + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

}  // namespace cagewrap::test
