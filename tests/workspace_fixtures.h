// A workspace on the demo character and its cage, for the in-process editor tests
// (tests/workspace_*_test.cpp): errors the artist would see in the modal are collected, and the
// background work (bind, automatic cage, export) is polled as the editor's frame loop polls it.
#pragma once

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/workspace/workspace.h"
#include "core/rig/rig.h"

namespace cagewrap::app {

class DemoWorkspaceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string assets = std::string(CAGEWRAP_SOURCE_DIR) + "/assets/";
    auto scene = load_scene(assets + "demo_character.glb", assets + "demo_cage.obj");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ws.set_scene(std::move(scene).value());
    ws.show_error = [this](const std::string& m) { errors.push_back(m); };
  }
  const Document& doc() const { return ws.scene()->doc(); }
  size_t undo_steps() const { return ws.scene()->history().undo_steps(); }
  bool logged(const std::string& text) const {
    for (const auto& l : ws.log_lines())
      if (l.text.find(text) != std::string::npos) return true;
    return false;
  }
  // The workspace's background jobs (automatic cage, export), polled until `busy` is false.
  template <class Busy>
  void poll_while(Busy busy) {
    for (int i = 0; i < 60000 && busy(); ++i) {
      ws.poll_jobs();
      if (busy()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_FALSE(busy()) << "the background work did not end";
  }
  // Waits for the scene's background bind, as the editor's frame loop polls it.
  void finish_bind() {
    Scene& s = *ws.scene();
    for (int i = 0; i < 6000 && s.job; ++i) {
      s.poll_bind();
      if (s.job) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_FALSE(s.job) << "the bind did not finish";
    ASSERT_TRUE(s.binding) << "no binding after the bind";
  }
  // The current frame's largest distance from the skin a Rig made from the whole document poses at the same
  // clip, time and overrides (what pose and the exports make), relative to the skin's diagonal; 1 when the
  // rig cannot be made (a failure is reported).
  double rig_gap() {
    const Document& w = ws.scene()->work();
    const std::vector<glm::vec3> shown = ws.scene()->skin_posed();
    auto rig = Rig::create(w);
    EXPECT_TRUE(rig.ok()) << rig.error().message;
    if (!rig) return 1.0;
    std::vector<glm::vec3> expected(rig->num_skin_points());
    PosedCage cage;
    const auto& pb = ws.view.playback;
    EXPECT_TRUE(rig->pose_clip(w, pb.clip, pb.player.time(), pb.pose_override, cage, expected).ok());
    double gap = 0.0;
    for (size_t i = 0; i < expected.size() && i < shown.size(); ++i) gap = std::max(gap, double(glm::distance(expected[i], shown[i])));
    return gap / ws.scene()->skin_diagonal;
  }
  // The node of the skeleton named `name` (-1 when there is none).
  int node(const std::string& name) const {
    const Skeleton& sk = doc().character->skeleton;
    for (uint32_t i = 0; i < sk.size(); ++i)
      if (sk.node(i).name == name) return static_cast<int>(i);
    return -1;
  }
  Workspace ws;
  std::vector<std::string> errors;
};

}  // namespace cagewrap::app
