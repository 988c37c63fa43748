// The GPU half of `cagewrap bench --gpu`: times the compute-shader deformer (render/gpu_deformer.h)
// with GL timer queries in a headless context, over the same cage states as the CPU figures.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/deform/deformer.h"
#include "core/geometry/mesh.h"
#include "core/base/result.h"

namespace cagewrap::app {

struct GpuBenchFigures {
  double deform_ms = 0, normals_ms = 0;  // GPU time (GL_TIME_ELAPSED), medians over the states
  double total_ms = 0, total_min_ms = 0;  // deform + normals per state: median and minimum
  // Wall-clock medians, each pass followed by glFinish: what software OpenGL is measured by (its
  // timer queries do not see compute work), and an upper bound on a GPU (submission included).
  double wall_deform_ms = 0, wall_normals_ms = 0;  // upload + deform pass; normals passes
  double maps_ms = 0;         // building the maps on the CPU (Deformer::update_maps), median
  double cpu_normals_ms = 0;  // the CPU path's normals (core/geometry/mesh_normals.h), median, for comparison
  double max_distance = 0;    // last state: largest |GPU - CPU| position, relative to the diagonal
  double max_normal_degrees = 0;  // last state: largest angle between GPU and CPU normals
  size_t gpu_bytes = 0, upload_bytes = 0;  // resident on the GPU; uploaded per cage change
};

// A headless GL context for the whole run (opened once, before the first variant).
class GpuBench {
 public:
  // Fails with a message when no OpenGL 4.3 context can be had (or the build has no GL).
  static Result<std::unique_ptr<GpuBench>> create();
  ~GpuBench();
  std::string device() const;
  bool software() const;

  // `deformer` as bound; `states` the cage states to time (after a warm-up with the first);
  // `cpu_last` the CPU path's result for the last state, `diagonal` the skin's bounding-box diagonal.
  Result<GpuBenchFigures> run(Deformer& deformer, std::span<const Tri> triangles,
                              const std::vector<std::vector<glm::vec3>>& states, std::span<const glm::vec3> cpu_last,
                              double diagonal);

 private:
  GpuBench() = default;
  struct Context;
  std::unique_ptr<Context> context_;
};

}  // namespace cagewrap::app
