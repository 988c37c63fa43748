#include "app/bench_gpu.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/base/stats.h"
#include "core/geometry/mesh_normals.h"
#include "core/deform/twist.h"

#if CAGEWRAP_GUI
#include "render/gpu_deformer.h"
#include "render/gpu_timer.h"
#include "render/headless_gl.h"
#endif

namespace cagewrap::app {

#if CAGEWRAP_GUI

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

struct GpuBench::Context {
  std::unique_ptr<render::HeadlessGl> gl;
};

Result<std::unique_ptr<GpuBench>> GpuBench::create() {
  auto gl = render::HeadlessGl::create();
  if (!gl) return gl.error();
  if (auto why = render::GpuDeformer::unsupported_reason(); !why.empty()) return make_error(ErrorCode::kUnsupportedFormat, why);
  std::unique_ptr<GpuBench> b(new GpuBench());
  b->context_ = std::make_unique<Context>();
  b->context_->gl = std::move(gl).value();
  return b;
}

GpuBench::~GpuBench() = default;
std::string GpuBench::device() const { return context_->gl->description(); }
bool GpuBench::software() const { return context_->gl->software(); }

Result<GpuBenchFigures> GpuBench::run(Deformer& deformer, std::span<const Tri> triangles,
                                      const std::vector<std::vector<glm::vec3>>& states, std::span<const glm::vec3> cpu_last,
                                      double diagonal) {
  const size_t n = deformer.binding().num_points;
  render::TriangleBuffer skin;
  skin.upload_indices(triangles);
  auto gpu = render::GpuDeformer::create(deformer, triangles);
  if (!gpu) return gpu.error();
  render::GpuTimer timer(2, 1);
  enum { kDeform, kNormals };
  std::vector<double> deform, normals, total, wall_deform, wall_normals, maps;
  // one pass under the timer query of `section`, then to the end (glFinish) for its wall time
  auto pass = [&](size_t section, auto&& work, std::vector<double>& wall) {
    auto t0 = std::chrono::steady_clock::now();
    timer.begin(section);
    work();
    timer.end(section);
    glFinish();
    wall.push_back(ms_since(t0));
  };
  auto one_change = [&](const std::vector<glm::vec3>& state) -> Status {
    auto t0 = std::chrono::steady_clock::now();
    if (auto s = deformer.update_maps(state); !s) return s;
    maps.push_back(ms_since(t0));
    pass(kDeform, [&] { (*gpu)->deform(skin); }, wall_deform);
    pass(kNormals, [&] { (*gpu)->normals(skin); }, wall_normals);
    return Ok{};
  };
  if (auto s = one_change(states.front()); !s) return s.error();  // warm-up: kernels, first touch
  maps.clear(), wall_deform.clear(), wall_normals.clear();
  for (const auto& state : states) {
    if (auto s = one_change(state); !s) return s.error();
    deform.push_back(timer.wait_ms(kDeform));
    normals.push_back(timer.wait_ms(kNormals));
    total.push_back(deform.back() + normals.back());
  }
  GpuBenchFigures f;
  f.deform_ms = median(deform);
  f.normals_ms = median(normals);
  f.total_ms = median(total);
  f.total_min_ms = *std::min_element(total.begin(), total.end());
  f.wall_deform_ms = median(wall_deform);
  f.wall_normals_ms = median(wall_normals);
  f.maps_ms = median(maps);
  f.gpu_bytes = (*gpu)->gpu_bytes() + skin.num_vertices() * 2 * sizeof(glm::vec3) + triangles.size_bytes();
  f.upload_bytes = (*gpu)->bytes_uploaded_per_change();

  // agreement with the CPU path on the last state (the caller's CPU result)
  std::vector<glm::vec3> gpu_positions(n), gpu_normals(n), cpu_normals(n);
  skin.read_positions(gpu_positions);
  skin.read_normals(gpu_normals);
  f.max_distance = relative_distance(gpu_positions, cpu_last, diagonal).max;
  NormalComputer cpu(n, triangles);
  std::vector<double> cpu_ms;
  for (int k = 0; k < 5; ++k) {
    auto t0 = std::chrono::steady_clock::now();
    cpu.compute(cpu_last, cpu_normals);
    cpu_ms.push_back(ms_since(t0));
  }
  f.cpu_normals_ms = median(cpu_ms);
  f.max_normal_degrees = max_normal_angle(gpu_normals, cpu_normals) * 180.0 / M_PI;
  return f;
}

#else  // built without GL

struct GpuBench::Context {};
Result<std::unique_ptr<GpuBench>> GpuBench::create() {
  return make_error(ErrorCode::kUnsupportedFormat, "this cagewrap was built without OpenGL (CAGEWRAP_GUI=OFF): no --gpu");
}
GpuBench::~GpuBench() = default;
std::string GpuBench::device() const { return {}; }
bool GpuBench::software() const { return false; }
Result<GpuBenchFigures> GpuBench::run(Deformer&, std::span<const Tri>, const std::vector<std::vector<glm::vec3>>&,
                                      std::span<const glm::vec3>, double) {
  return make_error(ErrorCode::kUnsupportedFormat, "no OpenGL in this build");
}

#endif

}  // namespace cagewrap::app
