#include "app/editor.h"

#if CAGEWRAP_GUI
#include <epoxy/gl.h>
// epoxy first, then GLFW without its own GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui/backends/imgui_impl_glfw.h>
#include <imgui/backends/imgui_impl_opengl3.h>
#include <imgui/imgui.h>
#include <stb_image_write.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>

#include "app/editor_scene.h"
#include "core/demo_character.h"
#include "core/gltf_writer.h"
#include "render/viewport_renderer.h"

namespace cagewrap::app {

namespace {

// Orbit view (temporary until core/camera lands): target, distance, yaw, pitch.
struct OrbitView {
  glm::vec3 target{0.f};
  float distance = 3.f, yaw = 0.5f, pitch = 0.25f, fov = 0.7f;
  glm::vec3 eye() const {
    return target + distance * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
  }
  glm::mat4 view() const { return glm::lookAt(eye(), target, glm::vec3(0, 1, 0)); }
  glm::mat4 projection(float aspect) const {
    return glm::perspective(fov, aspect, std::max(0.001f, distance * 0.01f), distance * 100.f);
  }
  void frame(const Aabb& box) {
    target = glm::vec3(box.center());
    distance = static_cast<float>(0.5 * box.diagonal() / std::tan(0.5 * fov) * 0.8);
  }
};

// Fixed panel layout (pixels): the 3-D view is what the panels leave free.
constexpr float kMenuHeight = 19.0f, kLeftWidth = 260.0f, kRightWidth = 300.0f, kBottomHeight = 170.0f;

struct LogLine {
  std::string text;
  int repeats = 1;
  bool error = false;
};

class Editor {
 public:
  explicit Editor(const EditorOptions& o) : options_(o) {}
  int run();

 private:
  bool open_window();
  void load_initial();
  void set_scene(std::unique_ptr<Scene> scene);
  void upload_topology();
  void frame_all();
  void handle_input();
  void draw_panels();
  void draw_menu();
  void draw_outliner();
  void draw_properties();
  void draw_timeline();
  void draw_log();
  void draw_stats();
  void draw_help();
  void log(std::string text, bool error = false);
  bool save_screenshot(const std::string& path);

  EditorOptions options_;
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<render::ViewportRenderer> renderer_ = std::make_unique<render::ViewportRenderer>();
  render::ViewportStyle style_;
  OrbitView camera_;
  std::unique_ptr<Scene> scene_;
  std::deque<LogLine> log_;
  std::string error_modal_;
  bool show_help_ = false;
  bool topology_dirty_ = true;
  int selected_joint_ = -1;
  double fps_ = 0.0;
};

void Editor::log(std::string text, bool error) {
  if (!log_.empty() && log_.back().text == text) {
    log_.back().repeats++;
    return;
  }
  std::fprintf(error ? stderr : stdout, "%s\n", text.c_str());
  log_.push_back({std::move(text), 1, error});
  if (log_.size() > 500) log_.pop_front();
}

bool Editor::open_window() {
  glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "glfw error %d: %s\n", code, text); });
  if (!glfwInit()) {
    std::fprintf(stderr, "error: cannot open a window (no display? run under Xvfb for headless use)\n");
    return false;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  window_ = glfwCreateWindow(options_.width, options_.height, "cagewrap", nullptr, nullptr);
  if (!window_) {
    std::fprintf(stderr, "error: cannot create an OpenGL 3.3 window\n");
    glfwTerminate();
    return false;
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(options_.screenshot.empty() ? 1 : 0);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // layout is fixed; preferences live elsewhere
  ImGui::StyleColorsDark();
  ImGui::GetStyle().WindowRounding = 3.0f;
  ImGui_ImplGlfw_InitForOpenGL(window_, true);
  ImGui_ImplOpenGL3_Init("#version 330");
  std::string err;
  if (!renderer_->init(err)) {
    std::fprintf(stderr, "error: %s\n", err.c_str());
    return false;
  }
  return true;
}

void Editor::set_scene(std::unique_ptr<Scene> scene) {
  scene_ = std::move(scene);
  topology_dirty_ = true;
  selected_joint_ = -1;
  if (options_.play && scene_->clip >= 0) scene_->player.play();
  if (scene_->cage) scene_->start_bind();
  frame_all();
}

void Editor::load_initial() {
  std::string path = options_.file;
  if (path.empty()) {
    path = demo_character_path();
    if (path.empty()) {  // not found beside the binary: make it (deterministic, about a second)
      path = "/tmp/cagewrap_demo_character.glb";
      auto st = write_glb(path, make_demo_character());
      if (!st.ok()) log("error: " + st.error().message, true);
    }
  }
  auto s = load_scene(path, options_.cage);
  if (!s.ok()) {
    error_modal_ = s.error().message;
    log("error: " + s.error().message, true);
    return;
  }
  log("opened " + path + (options_.cage.empty() ? "" : " with cage " + options_.cage));
  for (const auto& w : s.value()->character->warnings) log("warning: " + w);
  set_scene(std::move(s).value());
}

void Editor::frame_all() {
  if (!scene_) return;
  Aabb box = bounding_box(scene_->skin_posed.empty() ? scene_->skin_rest : scene_->skin_posed);
  camera_.frame(box);
}

void Editor::upload_topology() {
  renderer_->set_skin_topology(scene_->skin_rest.size(), scene_->skin_topology.face_vertices.empty()
                                                           ? std::span<const Tri>()
                                                           : std::span<const Tri>(reinterpret_cast<const Tri*>(scene_->skin_topology.face_vertices.data()),
                                                                                  scene_->skin_topology.face_vertices.size() / 3));
  if (scene_->cage) renderer_->set_cage_topology(scene_->cage->polygons, scene_->cage->elements);
  topology_dirty_ = false;
}

void Editor::handle_input() {
  ImGuiIO& io = ImGui::GetIO();
  if (!io.WantCaptureMouse) {
    const bool alt = io.KeyAlt;
    const glm::vec2 d(io.MouseDelta.x, io.MouseDelta.y);
    if ((alt && io.MouseDown[0]) || io.MouseDown[1]) {  // orbit: Alt+LMB or RMB
      if (alt && io.MouseDown[1]) {
        camera_.distance *= std::exp(0.01f * d.y);  // Alt+RMB: dolly
      } else {
        camera_.yaw -= 0.008f * d.x;
        camera_.pitch = std::clamp(camera_.pitch + 0.008f * d.y, -1.5f, 1.5f);
      }
    } else if (io.MouseDown[2]) {  // pan: MMB (with or without Alt)
      glm::mat4 inv = glm::inverse(camera_.view());
      float scale = 2.0f * camera_.distance * std::tan(0.5f * camera_.fov) / std::max(1.0f, io.DisplaySize.y);
      camera_.target += glm::vec3(inv * glm::vec4(-d.x * scale, d.y * scale, 0, 0));
    }
    if (io.MouseWheel != 0) camera_.distance *= std::pow(0.88f, io.MouseWheel);
  }
  if (!io.WantCaptureKeyboard) {
    if (ImGui::IsKeyPressed(GLFW_KEY_F)) frame_all();
    if (ImGui::IsKeyPressed(GLFW_KEY_SPACE) && scene_) {
      if (scene_->player.playing()) scene_->player.pause();
      else scene_->player.play();
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_1) || ImGui::IsKeyPressed(GLFW_KEY_1)) camera_.yaw = 0, camera_.pitch = 0;
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_3) || ImGui::IsKeyPressed(GLFW_KEY_3)) camera_.yaw = 1.5708f, camera_.pitch = 0;
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_7) || ImGui::IsKeyPressed(GLFW_KEY_7)) camera_.pitch = 1.5f;
    if (ImGui::IsKeyPressed(GLFW_KEY_W) && !io.KeyCtrl) style_.wireframe = !style_.wireframe;
    if (ImGui::IsKeyPressed(GLFW_KEY_X) && io.KeyAlt) style_.xray = !style_.xray;
    if (ImGui::IsKeyPressed(GLFW_KEY_F1)) show_help_ = !show_help_;
  }
}

void Editor::draw_menu() {
  if (!ImGui::BeginMainMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("Screenshot", "F12")) save_screenshot("cagewrap_screenshot.png");
    ImGui::Separator();
    if (ImGui::MenuItem("Quit", "Ctrl+Q")) glfwSetWindowShouldClose(window_, 1);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("View")) {
    ImGui::MenuItem("Skin", nullptr, &style_.show_skin);
    ImGui::MenuItem("Cage", nullptr, &style_.show_cage);
    ImGui::MenuItem("Skeleton", nullptr, &style_.show_skeleton);
    ImGui::MenuItem("Grid", nullptr, &style_.show_grid);
    ImGui::Separator();
    ImGui::MenuItem("Wireframe", "W", &style_.wireframe);
    ImGui::MenuItem("X-ray", "Alt+X", &style_.xray);
    ImGui::Separator();
    if (ImGui::MenuItem("Frame all", "F")) frame_all();
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Help")) {
    ImGui::MenuItem("Shortcuts", "F1", &show_help_);
    ImGui::EndMenu();
  }
  ImGui::EndMainMenuBar();
}

void Editor::draw_outliner() {
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(0, kMenuHeight), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(kLeftWidth, io.DisplaySize.y - kMenuHeight - kBottomHeight), ImGuiCond_Always);
  ImGui::Begin("Outliner", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  if (scene_) {
    const Character& ch = *scene_->character;
    if (ImGui::TreeNodeEx("Character", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::TextDisabled("%s", std::filesystem::path(ch.source).filename().string().c_str());
      for (const auto& p : ch.primitives) ImGui::BulletText("%s: %zu vertices", p.label().c_str(), p.num_vertices());
      ImGui::TreePop();
    }
    if (ImGui::TreeNodeEx("Skeleton", ImGuiTreeNodeFlags_DefaultOpen, "Skeleton (%zu nodes, %zu joints)", ch.skeleton.size(), ch.num_joints())) {
      for (size_t i = 0; i < ch.skeleton.size(); ++i) {
        int depth = 0;
        for (int32_t p = ch.skeleton.node(i).parent; p >= 0; p = ch.skeleton.node(static_cast<size_t>(p)).parent) ++depth;
        ImGui::Indent(depth * 8.0f);
        if (ImGui::Selectable(ch.skeleton.node(i).name.c_str(), selected_joint_ == static_cast<int>(i)))
          selected_joint_ = static_cast<int>(i);
        ImGui::Unindent(depth * 8.0f);
      }
      ImGui::TreePop();
    }
    if (ImGui::TreeNodeEx("Cage", ImGuiTreeNodeFlags_DefaultOpen)) {
      if (scene_->cage) {
        ImGui::Text("%zu vertices, %zu faces", scene_->cage->num_vertices(), scene_->cage->polygons.num_faces());
        ImGui::TextDisabled("%zu control elements", scene_->cage->num_elements());
      } else {
        ImGui::TextDisabled("no cage");
      }
      ImGui::TreePop();
    }
    if (ImGui::TreeNodeEx("Binding", ImGuiTreeNodeFlags_DefaultOpen)) {
      if (scene_->binding) ImGui::Text("%s, %u points", variant_name(scene_->binding->params.variant), scene_->binding->num_points);
      else ImGui::TextDisabled(scene_->job ? "binding..." : "not bound");
      ImGui::TreePop();
    }
  }
  ImGui::End();
}

void Editor::draw_properties() {
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - kRightWidth, kMenuHeight), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(kRightWidth, io.DisplaySize.y - kMenuHeight - kBottomHeight), ImGuiCond_Always);
  ImGui::Begin("Properties", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  if (scene_ && scene_->cage) {
    BindParams& p = scene_->params;
    ImGui::TextUnformatted("Binding");
    ImGui::Separator();
    int variant = static_cast<int>(p.variant);
    const char* variants[] = {"basic", "clamped", "extended"};
    if (ImGui::Combo("variant", &variant, variants, 3)) p.variant = static_cast<Variant>(variant);
    float local = static_cast<float>(p.local), eps = static_cast<float>(p.epsilon), scale = static_cast<float>(p.scale),
          maxd = static_cast<float>(p.max_distance);
    int k = static_cast<int>(p.max_elements);
    if (ImGui::SliderFloat("local", &local, 0.5f, 12.0f, "%.2f")) p.local = local;
    if (ImGui::SliderFloat("epsilon", &eps, 0.005f, 1.0f, "%.3f", ImGuiSliderFlags_Logarithmic)) p.epsilon = eps;
    if (ImGui::SliderInt("K (max elements)", &k, 1, 32)) p.max_elements = static_cast<uint32_t>(k);
    if (ImGui::DragFloat("scale h (0 = auto)", &scale, 0.001f, 0.0f, 100.0f, "%.4f")) p.scale = std::max(0.f, scale);
    if (ImGui::DragFloat("max distance (0 = none)", &maxd, 0.001f, 0.0f, 100.0f, "%.4f")) p.max_distance = std::max(0.f, maxd);
    if (scene_->job) {
      ImGui::ProgressBar(static_cast<float>(scene_->job->progress()), ImVec2(-70, 0), "binding");
      ImGui::SameLine();
      if (ImGui::Button("Cancel")) scene_->job->cancel();
    } else {
      if (scene_->needs_rebind()) {
        ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.2f, 1), "Parameters changed: rebind to apply");
      }
      if (ImGui::Button(scene_->binding ? "Rebind" : "Bind", ImVec2(-1, 0))) scene_->start_bind();
    }
    if (scene_->binding) {
      const Binding& b = *scene_->binding;
      ImGui::Spacing();
      ImGui::TextUnformatted("Result");
      ImGui::Separator();
      ImGui::Text("mean set %.2f, max %u", b.num_points ? double(b.total_set_size) / b.num_points : 0.0, b.max_set_size);
      ImGui::Text("%.1f bytes per skin vertex", double(b.bytes()) / std::max(1u, b.num_points));
      ImGui::Text("cage quality %.1f%%", 100.0 * b.quality());
      if (!b.invalid_elements.empty())
        ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "%zu elements skipped (see log)", b.invalid_elements.size());
      if (!b.rigid_points.empty())
        ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "%zu points follow their nearest element", b.rigid_points.size());
      ImGui::Text("bound in %.2f s", b.seconds);
    }
  } else if (scene_) {
    ImGui::TextWrapped("No cage: the skin shows the file's own linear blend skinning. Open with --cage to bind a cage.");
  }
  ImGui::End();
}

void Editor::draw_timeline() {
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(0, io.DisplaySize.y - kBottomHeight), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(io.DisplaySize.x * 0.6f, kBottomHeight), ImGuiCond_Always);
  ImGui::Begin("Timeline", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  if (scene_ && !scene_->character->clips.empty()) {
    const auto& clips = scene_->character->clips;
    if (ImGui::BeginCombo("clip", scene_->clip >= 0 ? clips[static_cast<size_t>(scene_->clip)].name.c_str() : "(rest pose)")) {
      if (ImGui::Selectable("(rest pose)", scene_->clip < 0)) {
        scene_->clip = -1;
        scene_->player = ClipPlayer(0.0);
      }
      for (size_t i = 0; i < clips.size(); ++i)
        if (ImGui::Selectable(clips[i].name.c_str(), scene_->clip == static_cast<int>(i))) {
          bool playing = scene_->player.playing();
          scene_->clip = static_cast<int32_t>(i);
          scene_->player = ClipPlayer(clips[i].duration);
          if (playing) scene_->player.play();
        }
      ImGui::EndCombo();
    }
    ClipPlayer& pl = scene_->player;
    if (ImGui::Button("|<")) pl.scrub(0);
    ImGui::SameLine();
    if (ImGui::Button("<")) pl.scrub(pl.time() - 1.0 / 30.0);
    ImGui::SameLine();
    if (ImGui::Button(pl.playing() ? "Pause" : "Play", ImVec2(60, 0))) pl.playing() ? pl.pause() : pl.play();
    ImGui::SameLine();
    if (ImGui::Button(">")) pl.scrub(pl.time() + 1.0 / 30.0);
    ImGui::SameLine();
    bool loop = pl.looping();
    if (ImGui::Checkbox("loop", &loop)) pl.set_loop(loop);
    float t = static_cast<float>(pl.time());
    if (ImGui::SliderFloat("time", &t, 0.0f, static_cast<float>(std::max(pl.duration(), 1e-3)), "%.3f s")) pl.scrub(t);
  } else {
    ImGui::TextDisabled("no clips");
  }
  ImGui::End();
}

void Editor::draw_log() {
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.6f, io.DisplaySize.y - kBottomHeight), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(io.DisplaySize.x * 0.4f, kBottomHeight), ImGuiCond_Always);
  ImGui::Begin("Log", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  for (const auto& l : log_) {
    ImVec4 c = l.error ? ImVec4(1, 0.4f, 0.35f, 1) : (l.text.rfind("warning", 0) == 0 ? ImVec4(1, 0.8f, 0.3f, 1) : ImVec4(0.85f, 0.85f, 0.85f, 1));
    if (l.repeats > 1) ImGui::TextColored(c, "%s (and %d similar)", l.text.c_str(), l.repeats - 1);
    else ImGui::TextColored(c, "%s", l.text.c_str());
  }
  if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);
  ImGui::End();
  if (!error_modal_.empty()) {
    ImGui::OpenPopup("Error");
    if (ImGui::BeginPopupModal("Error", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
      ImGui::TextUnformatted(error_modal_.c_str());
      ImGui::TextDisabled("The current document is unchanged.");
      if (ImGui::Button("OK", ImVec2(120, 0))) {
        error_modal_.clear();
        ImGui::CloseCurrentPopup();
      }
      ImGui::EndPopup();
    }
  }
}

void Editor::draw_stats() {
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(kLeftWidth + 10, kMenuHeight + 10), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.35f);
  ImGui::Begin("stats", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
  ImGui::Text("%.0f fps", fps_);
  if (scene_) {
    ImGui::Text("skin %zu vertices", scene_->skin_rest.size());
    if (scene_->cage) ImGui::Text("cage %zu vertices, %zu faces", scene_->cage->num_vertices(), scene_->cage->polygons.num_faces());
    if (scene_->skin_from_cage) ImGui::Text("deform %.2f ms", scene_->deform_ms);
    else ImGui::TextDisabled("skin: file's linear blend skinning");
  }
  (void)io;
  ImGui::End();
}

void Editor::draw_help() {
  if (!show_help_) return;
  ImGui::Begin("Shortcuts", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
  const char* rows[][2] = {{"Alt+LMB drag / RMB drag", "orbit"}, {"MMB drag (Alt optional)", "pan"},
                           {"wheel / Alt+RMB drag", "zoom"},     {"F", "frame everything"},
                           {"1 / 3 / 7 (numpad too)", "front / side / top view"},
                           {"Space", "play / pause"},            {"W", "wireframe"},
                           {"Alt+X", "X-ray"},                   {"F1", "this window"}};
  for (auto& r : rows) {
    ImGui::TextUnformatted(r[0]);
    ImGui::SameLine(210);
    ImGui::TextDisabled("%s", r[1]);
  }
  ImGui::End();
}

void Editor::draw_panels() {
  draw_menu();
  draw_outliner();
  draw_properties();
  draw_timeline();
  draw_log();
  draw_stats();
  draw_help();
}

bool Editor::save_screenshot(const std::string& path) {
  int w, h;
  glfwGetFramebufferSize(window_, &w, &h);
  std::vector<unsigned char> pixels(static_cast<size_t>(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  std::vector<unsigned char> flipped(pixels.size());
  for (int y = 0; y < h; ++y)
    std::copy_n(&pixels[static_cast<size_t>(h - 1 - y) * w * 4], static_cast<size_t>(w) * 4, &flipped[static_cast<size_t>(y) * w * 4]);
  for (size_t i = 3; i < flipped.size(); i += 4) flipped[i] = 255;
  if (!stbi_write_png(path.c_str(), w, h, 4, flipped.data(), w * 4)) {
    log("error: " + path + ": cannot write the screenshot", true);
    return false;
  }
  log("saved screenshot " + path);
  return true;
}

int Editor::run() {
  if (!open_window()) return 1;
  load_initial();
  int frame = 0;
  int exit_code = 0;
  auto last = std::chrono::steady_clock::now();
  const bool screenshot_mode = !options_.screenshot.empty();
  while (!glfwWindowShouldClose(window_)) {
    glfwPollEvents();
    auto now = std::chrono::steady_clock::now();
    double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    fps_ = 0.9 * fps_ + 0.1 * (dt > 0 ? 1.0 / dt : 0.0);
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    handle_input();

    if (scene_) {
      if (auto msg = scene_->poll_bind()) {
        log(*msg, msg->rfind("error", 0) == 0);
        if (scene_->binding && !scene_->binding->invalid_elements.empty())
          log("warning: " + std::to_string(scene_->binding->invalid_elements.size()) + " cage elements skipped (zero area, non-finite or duplicate)");
      }
      // screenshots advance a fixed 1/30 s per frame so they are reproducible
      scene_->player.advance(screenshot_mode ? 1.0 / 30.0 : dt);
      scene_->update_pose();
      if (topology_dirty_) upload_topology();
      renderer_->update_skin(scene_->skin_posed);
      if (scene_->cage) renderer_->update_cage(scene_->cage_posed, {});
      renderer_->update_skeleton(scene_->joint_heads, scene_->bones, selected_joint_);
    }
    draw_panels();
    ImGui::Render();

    int w, h;
    glfwGetFramebufferSize(window_, &w, &h);
    glViewport(0, 0, w, h);
    glClearColor(0.16f, 0.17f, 0.19f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (scene_) {
      render::ViewParams v;
      v.x = static_cast<int>(kLeftWidth);
      v.y = static_cast<int>(kBottomHeight);
      v.width = std::max(1, w - static_cast<int>(kLeftWidth + kRightWidth));
      v.height = std::max(1, h - static_cast<int>(kMenuHeight + kBottomHeight));
      v.view = camera_.view();
      v.projection = camera_.projection(float(v.width) / float(v.height));
      double diag = bounding_box(scene_->skin_rest).diagonal();
      v.grid_spacing = static_cast<float>(std::pow(10.0, std::floor(std::log10(std::max(diag, 1e-6) / 10.0))));
      renderer_->draw(v, style_);
    }
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++frame;
    if (screenshot_mode && frame >= options_.frames && !(scene_ && scene_->job)) {
      exit_code = save_screenshot(options_.screenshot) ? 0 : 1;
      break;
    }
    glfwSwapBuffers(window_);
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  scene_.reset();
  renderer_.reset();  // GL objects go while the context is current
  glfwDestroyWindow(window_);
  // No glfwTerminate(): with Mesa's software rasterizer it unloads swrast_dri.so, whose LLVM static
  // destructors crash in __cxa_finalize. The process is about to exit; the OS reclaims the display.
  return exit_code;
}

}  // namespace

int run_editor(const EditorOptions& options) { return Editor(options).run(); }

}  // namespace cagewrap::app

#else  // built without the GUI

#include <cstdio>

namespace cagewrap::app {
int run_editor(const EditorOptions&) {
  std::fprintf(stderr, "error: this cagewrap was built without the editor (CAGEWRAP_GUI=OFF)\n");
  return 1;
}
}  // namespace cagewrap::app

#endif
