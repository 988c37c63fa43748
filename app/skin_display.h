// How the editor's skin gets from the deformer to the screen, and where the frame's time goes.
//
// With OpenGL 4.3 (and unless turned off: View > Deform on the GPU, `--cpu-deform`) the skin is
// deformed and its normals recomputed by compute shaders straight into the vertex buffers that are
// drawn (render/gpu_deformer.h); the scene then builds only the cage-sized maps on the CPU, and a
// CPU copy of the skin is made only when picking or a brush asks for one (Scene::skin_posed).
// A stack of deformers (docs/deformer-stack.md) runs there too: every deformer that moves the skin
// deforms on the GPU from its own maps (the scene poses each one's cage), one pass combines them as
// the project's stack says, then the normals (render/gpu_deformer.h GpuStack). The parametric drivers'
// displacements are made on the CPU (about 2 ms each on the demo) and go up each frame, added by the same
// combine pass where each sits.
// Otherwise the CPU deforms, combines, computes normals and uploads them (the renderer's update_skin).
// The stats overlay shows the frame split into deform, normals, draw and UI: CPU time, and GPU time
// from timer queries (read a few frames late, so the GPU never waits for the CPU).
#pragma once

#if CAGEWRAP_GUI

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <algorithm>
#include <vector>

#include "app/workspace/scene.h"
#include "render/gpu_deformer.h"
#include "render/gpu_timer.h"
#include "render/viewport_renderer.h"

namespace cagewrap::app {

// Where a frame's time goes (--frame-stats, the stats overlay): the skin's deform and normals; the
// rest of the scene update on the CPU (clip, skeleton, cage, simulation, display buffers); drawing
// the viewport; building the panels (ImGui, CPU only); drawing them.
enum class FramePart : uint8_t { kDeform, kNormals, kScene, kDraw, kUiBuild, kUiDraw };
constexpr size_t kFrameParts = 6;

class SkinDisplay {
 public:
  // kAutomatic: the GPU where OpenGL 4.3 is there and is not software (Mesa's llvmpipe runs
  // compute shaders slower than the CPU path); kCpu: --cpu-deform; kGpu: --gpu-deform.
  enum class Path { kAutomatic, kCpu, kGpu };
  // Once the GL context is current. `synchronous`: finish the GL's work at each part's end so that
  // CPU times include it (for --frame-stats on software OpenGL, where the "GPU" is the CPU);
  // slower. Returns a log line.
  std::string init(Path path, bool synchronous);

  bool gpu_available() const { return unavailable_.empty(); }
  // Whether this frame's skin was deformed on the GPU.
  bool on_gpu() const { return on_gpu_; }
  // The user's choice (View > Deform on the GPU; script `toggle gpu_deform`).
  bool& use_gpu() { return use_gpu_; }

  // A new scene (another character): the GPU copy of the old skin goes.
  void scene_changed() { gpu_.reset(); }
  // Before Scene::update_pose: whether the scene should leave the skin to the GPU.
  void before_pose(Scene& scene) const;
  // After update_pose (and the renderer's topology upload): puts the frame's skin into the
  // renderer's buffers, on the GPU when it can. Returns a line to log (a warning once when the GPU
  // cannot take a binding, or the path changing), or empty.
  std::string update(Scene& scene, render::ViewportRenderer& renderer);

  // Time a part of the frame the editor runs itself (draw, UI); CPU time is added to the part.
  void begin(FramePart part);
  void end(FramePart part);
  void add_cpu_ms(FramePart part, double ms) { cpu_ms_[static_cast<size_t>(part)] += ms; }
  // The scene update's wall time, which includes update(): the part that is not deform or normals.
  void add_scene_ms(double ms) {
    cpu_ms_[static_cast<size_t>(FramePart::kScene)] += std::max(
        0.0, ms - cpu_ms_[static_cast<size_t>(FramePart::kDeform)] - cpu_ms_[static_cast<size_t>(FramePart::kNormals)]);
  }
  // At the end of each frame, with its wall time.
  void end_frame(double frame_ms);

  // Deletes the GL objects (timers, the GPU table) while the context is still current.
  void release_gl();

  void menu_item();                       // View > Deform on the GPU
  void draw_stats(const Scene& scene);    // lines for the stats overlay
  // Medians over the frames so far whose skin was deformed through the cage (the first 5 of them
  // left out: kernels compile, buffers fill), or over all frames when none was: for --frame-stats.
  std::string summary() const;

 private:
  std::string put_skin(Scene& scene, render::ViewportRenderer& renderer);

  // The revisions of the scene's deformers: the active one's binding and each other's rig.
  static std::vector<uint64_t> revisions(const Scene& scene);

  std::unique_ptr<render::GpuStack> gpu_;  // every deformer's table, kept while the scene is the same
  std::unique_ptr<render::GpuTimer> timer_;
  // the scene's deformers' revisions when the GPU could not take them (logged once; the CPU deforms
  // until one of them changes: a rebind)
  std::vector<uint64_t> failed_revisions_;
  std::string unavailable_;  // why there is no GPU path (empty: there is)
  bool use_gpu_ = true, synchronous_ = false, on_gpu_ = false, from_cage_ = false;
  int shown_path_ = -1;  // the path of the last frame deformed through the cage: 1 GPU, 0 CPU, -1 none yet
  std::array<double, kFrameParts> cpu_ms_{}, gpu_ms_{};  // this frame's, then shown
  std::array<double, kFrameParts> shown_cpu_{}, shown_gpu_{};
  double shown_frame_ms_ = 0;
  std::array<bool, kFrameParts> timed_{};  // whether the GPU timer ran for the part this frame
  struct FrameRecord {
    double frame_ms;
    std::array<double, kFrameParts> cpu, gpu;
    bool on_gpu, from_cage;
  };
  std::vector<FrameRecord> records_;
  std::chrono::steady_clock::time_point started_[kFrameParts];
};

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
