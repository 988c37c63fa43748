#if CAGEWRAP_GUI  // the editor's; nothing here without it

#include "app/skin_display.h"

#include "core/base/stats.h"
#include "render/headless_gl.h"

#include <imgui/imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace cagewrap::app {

namespace {

const char* const kPartNames[kFrameParts] = {"deform", "normals", "scene", "draw", "UI build", "UI draw"};

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

std::string SkinDisplay::init(Path path, bool synchronous) {
  synchronous_ = synchronous;
  unavailable_ = render::GpuDeformer::unsupported_reason();
  timer_ = std::make_unique<render::GpuTimer>(kFrameParts);
  const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string gl = std::string(renderer ? renderer : "unknown renderer") + ", OpenGL " +
                         std::to_string(epoxy_gl_version() / 10) + "." + std::to_string(epoxy_gl_version() % 10);
  // a software OpenGL runs compute shaders on the CPU, slower than the CPU path (docs/benchmarks.md)
  const bool software = render::current_context_is_software();
  use_gpu_ = path == Path::kGpu || (path == Path::kAutomatic && !software);
  if (!unavailable_.empty()) return "skin deformed on the CPU: " + unavailable_;
  if (path == Path::kCpu) return "skin deformed on the CPU (--cpu-deform); " + gl + " can do it: View > Deform on the GPU";
  if (!use_gpu_)
    return "skin deformed on the CPU: " + gl + " is software OpenGL, where the CPU path is faster (--gpu-deform or "
           "View > Deform on the GPU to use it anyway)";
  return "skin deformed on the GPU (OpenGL compute shaders, " + gl + ")";
}

std::vector<uint64_t> SkinDisplay::revisions(const Scene& scene) {
  std::vector<uint64_t> out{scene.binding_revision};
  for (const StackRig& r : scene.stack_rigs) out.push_back(r.rig ? r.revision : 0);
  return out;
}

void SkinDisplay::before_pose(Scene& scene) const {
  // a stack of cages too (Scene::gpu_frame), and the parametric drivers' displacements (made on the CPU)
  scene.skin_on_gpu = use_gpu_ && gpu_available() && (failed_revisions_.empty() || failed_revisions_ != revisions(scene));
}

std::string SkinDisplay::update(Scene& scene, render::ViewportRenderer& renderer) {
  std::string message = put_skin(scene, renderer);
  if (from_cage_) {
    if (shown_path_ >= 0 && shown_path_ != int(on_gpu_) && message.empty())
      message = std::string("skin now deformed on the ") + (on_gpu_ ? "GPU" : "CPU");
    shown_path_ = on_gpu_;
  }
  return message;
}

std::string SkinDisplay::put_skin(Scene& scene, render::ViewportRenderer& renderer) {
  std::string message;
  on_gpu_ = false;
  from_cage_ = scene.skin_from_cage;
  if (scene.skin_from_cage) add_cpu_ms(FramePart::kDeform, scene.deform_ms);  // the CPU deform, or the maps alone
  const GpuFrame& frame = scene.gpu_frame();
  if (scene.skin_on_gpu && scene.skin_from_cage && frame.built) {
    if (!gpu_) {
      // the first frame of this scene on the GPU: kernels, rest skin and topology; each deformer's
      // table comes with the first frame that has it (GpuStack::deform)
      auto g = render::GpuStack::create(scene.skin_rest, scene.skin_triangles());
      if (g) {
        gpu_ = std::move(g).value();
      } else {
        failed_revisions_ = revisions(scene);
        message = "warning: the skin is deformed on the CPU, the GPU cannot take it: " + g.error().message;
      }
    }
    if (gpu_) {
      const auto to_gpu = [](const GpuFrame::Deformed& d) {
        return render::GpuStack::Deformed{d.index, d.deformer, d.revision, d.mask, d.displacement};
      };
      std::optional<render::GpuStack::Deformed> base;
      if (frame.base) base = to_gpu(*frame.base);
      std::vector<render::GpuStack::Deformed> layers;
      for (const GpuFrame::Deformed& l : frame.layers) layers.push_back(to_gpu(l));
      begin(FramePart::kDeform);
      Status s = gpu_->deform(frame.stack, base ? &*base : nullptr, layers, renderer.skin_buffer());
      end(FramePart::kDeform);
      if (s) {
        begin(FramePart::kNormals);
        gpu_->normals(renderer.skin_buffer());
        end(FramePart::kNormals);
        on_gpu_ = true;
        return message;
      }
      gpu_.reset();
      failed_revisions_ = revisions(scene);  // the CPU deforms these bindings; tried again after a rebind
      message = "warning: the skin is deformed on the CPU, the GPU cannot take it: " + s.error().message;
    }
  }
  auto t0 = std::chrono::steady_clock::now();
  const auto& skin = scene.skin_posed();  // deformed now if the scene had left it to the GPU
  auto t1 = std::chrono::steady_clock::now();
  add_cpu_ms(FramePart::kDeform, ms_between(t0, t1));
  begin(FramePart::kNormals);
  renderer.update_skin(skin);
  end(FramePart::kNormals);
  return message;
}

void SkinDisplay::begin(FramePart part) {
  const size_t p = static_cast<size_t>(part);
  started_[p] = std::chrono::steady_clock::now();
  timer_->begin(p);
  timed_[p] = true;
}

void SkinDisplay::end(FramePart part) {
  const size_t p = static_cast<size_t>(part);
  timer_->end(p);
  if (synchronous_) glFinish();
  cpu_ms_[p] += ms_between(started_[p], std::chrono::steady_clock::now());
}

void SkinDisplay::end_frame(double frame_ms) {
  for (size_t p = 0; p < kFrameParts; ++p) gpu_ms_[p] = timed_[p] ? std::max(0.0, timer_->ms(p)) : 0.0;
  records_.push_back({frame_ms, cpu_ms_, gpu_ms_, on_gpu_, from_cage_});
  // smoothed for reading
  const double k = records_.size() == 1 ? 1.0 : 0.1;
  shown_frame_ms_ += k * (frame_ms - shown_frame_ms_);
  for (size_t p = 0; p < kFrameParts; ++p) {
    shown_cpu_[p] += k * (cpu_ms_[p] - shown_cpu_[p]);
    shown_gpu_[p] += k * (gpu_ms_[p] - shown_gpu_[p]);
  }
  cpu_ms_.fill(0.0);
  timed_.fill(false);
}

void SkinDisplay::release_gl() {
  gpu_.reset();
  timer_.reset();
}

void SkinDisplay::menu_item() {
  ImGui::MenuItem("Deform on the GPU", nullptr, &use_gpu_, gpu_available());
  if (!gpu_available() && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("%s", unavailable_.c_str());
}

void SkinDisplay::draw_stats(const Scene& scene) {
  ImGui::Text("%.0f fps, frame %.1f ms", shown_frame_ms_ > 0 ? 1000.0 / shown_frame_ms_ : 0.0, shown_frame_ms_);
  if (scene.skin_from_cage && scene.stacked()) {
    if (scene.cage_stack())
      ImGui::Text("skin: %zu deformers, %s%s", deformer_count(scene.work()), on_gpu_ ? "GPU" : "CPU",
                  scene.stack_ready() ? "" : " (binding)");
    else
      ImGui::Text("skin deformed on the CPU");
    if (scene.skin_driven()) ImGui::Text(driver_count(scene.work()) > 1 ? "+ the drivers' sculpts" : "+ the driver's sculpt");
  } else if (!scene.skin_from_cage) {
    ImGui::TextDisabled("skin: file's linear blend skinning");
  } else {
    ImGui::Text("skin deformed on the %s", on_gpu_ ? "GPU" : "CPU");
  }
  for (size_t p = 0; p < kFrameParts; ++p)
    ImGui::Text("%-8s %6.2f ms CPU %6.2f ms GPU", kPartNames[p], shown_cpu_[p], shown_gpu_[p]);
}

std::string SkinDisplay::summary() const {
  const bool any_from_cage = std::any_of(records_.begin(), records_.end(), [](const FrameRecord& r) { return r.from_cage; });
  std::vector<double> frame;
  std::array<std::vector<double>, kFrameParts> cpu, gpu;
  size_t gpu_frames = 0, n = 0, seen = 0;
  for (size_t i = 0; i < records_.size(); ++i) {
    if (records_[i].from_cage != any_from_cage || seen++ < 5) continue;
    ++n;
    frame.push_back(records_[i].frame_ms);
    for (size_t p = 0; p < kFrameParts; ++p) {
      cpu[p].push_back(records_[i].cpu[p]);
      gpu[p].push_back(records_[i].gpu[p]);
    }
    gpu_frames += records_[i].on_gpu;
  }
  char buf[512];
  int len = std::snprintf(buf, sizeof buf, "frame stats: %zu frames %s (on the GPU in %zu), median frame %.2f ms (%.1f fps)", n,
                          any_from_cage ? "with the skin deformed through the cage" : "with no cage deformation", gpu_frames,
                          median(frame), median(frame) > 0 ? 1000.0 / median(frame) : 0.0);
  std::string out(buf, static_cast<size_t>(std::max(len, 0)));
  std::vector<double> other;  // the frame's time outside the parts (events, buffer swap, the loop itself)
  for (size_t i = 0; i < frame.size(); ++i) {
    double parts = 0;
    for (size_t p = 0; p < kFrameParts; ++p) parts += cpu[p][i];
    other.push_back(std::max(0.0, frame[i] - parts));
  }
  for (size_t p = 0; p < kFrameParts; ++p) {
    len = std::snprintf(buf, sizeof buf, "; %s %.2f ms CPU %.2f ms GPU", kPartNames[p], median(cpu[p]), median(gpu[p]));
    out.append(buf, static_cast<size_t>(std::max(len, 0)));
  }
  len = std::snprintf(buf, sizeof buf, "; other %.2f ms", median(other));
  out.append(buf, static_cast<size_t>(std::max(len, 0)));
  return out;
}

}  // namespace cagewrap::app

#endif  // CAGEWRAP_GUI
