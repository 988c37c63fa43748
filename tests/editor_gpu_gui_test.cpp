// The editor's two skin paths (app/skin_display.h) under Xvfb: the GPU path (compute shaders on
// Mesa's llvmpipe, OpenGL 4.5) and the CPU path (--cpu-deform) draw the same posed character, with
// a skin vertex picked by a real click (picking reads the CPU copy the GPU path makes on demand).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/io/gltf_loader.h"
#include "tests/gui_harness.h"

namespace {

namespace fs = std::filesystem;
using namespace cagewrap::test;

std::string read_log(const std::string& name) {
  std::ifstream log((gui_test_dir() / (name + ".log")).string());
  return std::string((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
}

// Pixels of the selected skin points' colour (render/viewport_renderer.cpp kSkinPointColor, lit
// flat: 255, 89, 140) in the view.
size_t skin_point_pixels(const Image& img) {
  size_t n = 0;
  for (int y = kTop; y < img.h - kBottom; ++y)
    for (int x = kLeft; x < img.w - kRight; ++x) {
      const unsigned char* p = img.at(x, y);
      if (p[0] > 230 && p[1] > 60 && p[1] < 120 && p[2] > 110 && p[2] < 170) ++n;
    }
  return n;
}

TEST(EditorGpuGui, GpuAndCpuPathsDrawTheSamePosedSkin) {
  std::string why;
  if (!gui_available(why)) GTEST_SKIP() << why;
  // the front-most skin vertex at rest (the character faces +Z, the default view looks at its front)
  auto ch = cagewrap::load_character(std::string(CAGEWRAP_SOURCE_DIR) + "/assets/demo_character.glb");
  ASSERT_TRUE(ch.ok());
  uint32_t front = 0, index = 0;
  float best = -1e30f;
  for (const auto& prim : ch->primitives)
    for (const auto& p : prim.positions) {
      if (p.z > best) best = p.z, front = index;
      ++index;
    }
  const fs::path dir = gui_test_dir();
  const fs::path posed = dir / "gpu_posed.script", rest = dir / "gpu_rest.script", toggled = dir / "gpu_toggled.script";
  const std::string pose_and_pick = "clip arm_raise\ntime 1.2\nclick_skin_vertex " + std::to_string(front) + "\nwait 2\n";
  {
    std::ofstream(posed) << pose_and_pick;
    std::ofstream(rest) << "clip rest\nwait 2\n";
    // View > Deform on the GPU switched off, then on again, while the pose stays
    std::ofstream(toggled) << pose_and_pick << "toggle gpu_deform\nwait 2\ntoggle gpu_deform\nwait 2\n";
  }
  Image gpu = screenshot("--frames 3 --gpu-deform --script " + posed.string(), "gpu_path");
  Image cpu = screenshot("--frames 3 --cpu-deform --script " + posed.string(), "cpu_path");
  Image gpu_rest = screenshot("--frames 3 --gpu-deform --script " + rest.string(), "gpu_path_rest");
  Image back = screenshot("--frames 3 --gpu-deform --script " + toggled.string(), "gpu_path_toggled");
  const std::string gpu_log = read_log("gpu_path"), cpu_log = read_log("cpu_path"), toggled_log = read_log("gpu_path_toggled");
  if (gpu_log.find("skin deformed on the CPU: ") != std::string::npos)
    GTEST_SKIP() << "this OpenGL has no compute shaders, only the CPU path runs: " << gpu_log;
  ASSERT_NE(gpu_log.find("skin deformed on the GPU"), std::string::npos) << gpu_log;
  ASSERT_NE(cpu_log.find("skin deformed on the CPU (--cpu-deform)"), std::string::npos) << cpu_log;
  EXPECT_EQ(gpu_log.find("error"), std::string::npos) << gpu_log;

  // the same picture: positions agree to ~1e-7 of the diagonal, so only a rare edge pixel may flip
  EXPECT_LT(share_differing(gpu, cpu, 8), 0.0005);
  // and it is the posed skin, not the rest skin: the arms are raised
  EXPECT_GT(share_differing(gpu, gpu_rest, 24), 0.01);
  EXPECT_GT(skin_share(gpu), 0.02);
  // switching the path in the middle of a session: CPU then GPU again, the same picture
  const size_t to_cpu = toggled_log.find("skin now deformed on the CPU");
  EXPECT_NE(to_cpu, std::string::npos) << toggled_log;
  EXPECT_NE(toggled_log.find("skin now deformed on the GPU", to_cpu), std::string::npos) << toggled_log;
  EXPECT_LT(share_differing(back, gpu, 8), 0.0005);
  // the click picked the skin vertex in both paths: its point is drawn over the skin
  EXPECT_GT(skin_point_pixels(gpu), 8u);
  EXPECT_GT(skin_point_pixels(cpu), 8u);
  // without a flag a software OpenGL (llvmpipe, slower than the CPU path) gets the CPU path
  if (gpu_log.find("llvmpipe") != std::string::npos) {
    screenshot("--frames 3 --script " + rest.string(), "automatic_path");
    const std::string automatic = read_log("automatic_path");
    EXPECT_NE(automatic.find("skin deformed on the CPU: llvmpipe"), std::string::npos) << automatic;
    EXPECT_NE(automatic.find("is software OpenGL"), std::string::npos) << automatic;
  }
}

}  // namespace
