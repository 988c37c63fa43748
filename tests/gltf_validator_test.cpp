// Runs the Khronos glTF validator (npm package gltf-validator, installed by scripts/setup.sh into
// tests/gltf_validate) over the files the project writes and the tests' hand-built files.
// Skips only when node itself is unavailable.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/character/demo_character.h"
#include "core/io/gltf_writer.h"
#include "tests/gltf_samples.h"
#include "tests/gltf_validator.h"

namespace cagewrap {
namespace {

using test::node_available;

// Exit status of validate.js over `files`; its report goes to `log`.
int validate(const std::vector<std::string>& files, const std::string& dir, std::string& log) {
  return test::run_gltf_validator(files, dir + "/report.txt", log);
}

TEST(GltfValidator, WrittenAndHandBuiltFilesHaveNoErrors) {
  if (!node_available()) GTEST_SKIP() << "node is not installed (scripts/setup.sh installs nodejs)";
  auto dir = test::temp_dir("validator");
  std::vector<std::string> files = {dir + "/demo.glb", dir + "/sample.glb",
                                    test::write_two_joint_file("validator_two_joint"),
                                    test::write_interpolation_file("validator_interp")};
  ASSERT_TRUE(write_glb(files[0], make_demo_character()).ok());
  ASSERT_TRUE(write_glb(files[1], test::sample_character()).ok());
  files.push_back(std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb");
  // quantized (KHR_mesh_quantization): SHORT positions and targets, BYTE normals, UNSIGNED_SHORT weights
  for (const auto& [name, c] : {std::pair{"sample_q.glb", test::sample_character()}, std::pair{"demo_q.glb", make_demo_character()}}) {
    const GlbQuantization q = plan_glb_quantization(c);
    files.push_back(dir + "/" + name);
    ASSERT_TRUE(write_glb(files.back(), c, "test", &q).ok());
  }
  std::string log;
  int rc = validate(files, dir, log);
  ASSERT_NE(rc, 2) << "gltf-validator is not installed: run scripts/setup.sh\n" << log;
  EXPECT_EQ(rc, 0) << log;
  // The report names every file with its counts.
  for (const auto& f : files) EXPECT_NE(log.find(f + ": 0 errors"), std::string::npos) << log;
  std::printf("%s", log.c_str());
}

TEST(GltfValidator, ReportsErrorsInABrokenFile) {
  if (!node_available()) GTEST_SKIP() << "node is not installed (scripts/setup.sh installs nodejs)";
  auto dir = test::temp_dir("validator_broken");
  test::GltfBuilder b;
  int pos = b.add_floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", true);
  b.doc["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}});
  b.set_scene({b.add_node({{"mesh", 0}})});
  b.doc["accessors"][0]["count"] = 30;  // past its buffer view
  b.write_embedded(dir + "/broken.gltf");
  std::string log;
  int rc = validate({dir + "/broken.gltf"}, dir, log);
  ASSERT_NE(rc, 2) << "gltf-validator is not installed: run scripts/setup.sh\n" << log;
  EXPECT_EQ(rc, 1) << log;
  EXPECT_EQ(log.find("broken.gltf: 0 errors"), std::string::npos) << log;
}

}  // namespace
}  // namespace cagewrap
