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
#include <fstream>
#include <sstream>
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>

#include "app/editor_files.h"
#include "app/editor_scene.h"
#include "core/camera.h"
#include "core/mesh_io.h"
#include "core/picking.h"
#include "core/project_io.h"
#include "core/selection.h"
#include "core/demo_character.h"
#include "core/gltf_writer.h"
#include "render/viewport_renderer.h"

namespace cagewrap::app {

namespace {

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
  glm::dvec2 to_view(const ImVec2& p) const;
  bool in_view(const ImVec2& p) const;
  std::optional<glm::dvec3> selection_centre() const;
  bool gizmo_handles(glm::dvec2& centre, glm::dvec2 ends[3]) const;
  void apply_move(const glm::dvec3& delta);
  void begin_move();
  void end_move();
  double grid_spacing() const;
  void click_select(const ImVec2& mouse, bool add, bool remove);
  void draw_gizmo();
  void undo();
  void redo();
  void request_save();
  bool save_project_to(const std::string& path);
  bool open_path(const std::string& path);
  bool import_cage(const std::string& path);
  void browse(FilePurpose purpose, const std::string& dir = {});
  void act_on(const EditorFiles::Choice& choice);
  bool run_file_script_command(const std::string& cmd, std::istringstream& in);
  void run_script_step();
  void draw_file_popups();
  void draw_panels();
  void draw_menu();
  void draw_outliner();
  void draw_properties();
  void draw_timeline();
  void draw_log();
  void draw_stats();
  void draw_help();
  void log(std::string text, bool error = false);
  bool save_screenshot(const std::string& path, bool view_only = false);

  EditorOptions options_;
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<render::ViewportRenderer> renderer_ = std::make_unique<render::ViewportRenderer>();
  render::ViewportStyle style_;
  Camera camera_;
  Selection selection_;
  // the 3-D view rectangle in window pixels (top-left origin), updated every frame
  float view_x_ = 0, view_y_ = 0, view_w_ = 1, view_h_ = 1;
  // gizmo drag: -1 none, 0..2 axis, 3 screen plane
  int drag_axis_ = -1;
  glm::dvec3 drag_total_{0.0};
  Document drag_start_;
  bool box_selecting_ = false;
  ImVec2 box_start_{0, 0};
  EditorFiles files_;  // preferences, recent files, the file browser (app/editor_files.h)
  // requests for the file browser: Save as, Open (Ctrl+O); quit once the Save as is done
  bool open_save_popup_ = false, open_open_popup_ = false, quit_requested_ = false, quit_after_save_ = false;
  bool screenshot_view_only_ = false;
  int pending_screenshot_frames_ = 0;  // frames to wait (a dialog that just closed leaves the picture)
  std::shared_ptr<const Cage> shown_cage_;  // the cage the renderer and the selection were made for
  std::vector<std::string> script_;
  size_t script_pos_ = 0;
  int script_wait_ = 0;
  std::string pending_screenshot_;
  std::string dropped_;  // a file dropped on the window, opened next frame
  std::string title_;
  std::vector<uint8_t> selected_mask_;
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
  selection_ = Selection{};
  frame_all();
}

void Editor::load_initial() {
  std::string path = options_.file;
  std::string cage = options_.cage;
  if (path.empty()) {
    path = demo_character_path();
    if (cage.empty() && !path.empty()) cage = demo_cage_path(path);  // the demo's own generated cage
    if (path.empty()) {  // not found beside the binary: make it (deterministic, about a second)
      path = "/tmp/cagewrap_demo_character.glb";
      auto st = write_glb(path, make_demo_character());
      if (!st.ok()) log("error: " + st.error().message, true);
    }
  }
  std::vector<std::string> warnings;
  auto s = has_extension(path, ".cagewrap") ? load_project_scene(path, warnings) : load_scene(path, cage);
  for (const auto& w : warnings) log("warning: " + w);
  if (!s.ok()) {
    error_modal_ = s.error().message;
    log("error: " + s.error().message, true);
    return;
  }
  log("opened " + path + (cage.empty() ? "" : " with cage " + cage));
  if (!options_.file.empty())
    if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  for (const auto& w : s.value()->doc().character->warnings) log("warning: " + w);
  set_scene(std::move(s).value());
}

void Editor::frame_all() {
  if (!scene_) return;
  Aabb box = bounding_box(scene_->skin_posed.empty() ? scene_->skin_rest : scene_->skin_posed);
  camera_.frame(box, view_w_ / std::max(1.0f, view_h_));
}

void Editor::upload_topology() {
  renderer_->set_skin_topology(scene_->skin_rest.size(), scene_->skin_topology.face_vertices.empty()
                                                           ? std::span<const Tri>()
                                                           : std::span<const Tri>(reinterpret_cast<const Tri*>(scene_->skin_topology.face_vertices.data()),
                                                                                  scene_->skin_topology.face_vertices.size() / 3));
  if (scene_->doc().cage) renderer_->set_cage_topology(scene_->doc().cage->polygons, scene_->doc().cage->elements);
  topology_dirty_ = false;
}

glm::dvec2 Editor::to_view(const ImVec2& p) const { return {p.x - view_x_, p.y - view_y_}; }

bool Editor::in_view(const ImVec2& p) const {
  return p.x >= view_x_ && p.y >= view_y_ && p.x < view_x_ + view_w_ && p.y < view_y_ + view_h_;
}

std::optional<glm::dvec3> Editor::selection_centre() const {
  if (!scene_ || !scene_->doc().cage || selection_.cage_vertices.indices().empty()) return std::nullopt;
  glm::dvec3 c(0.0);
  for (uint32_t v : selection_.cage_vertices.indices()) c += glm::dvec3(scene_->cage_posed[v]);
  return c / double(selection_.cage_vertices.indices().size());
}

// Screen-space axis handles of the move gizmo: end points in window pixels.
bool Editor::gizmo_handles(glm::dvec2& centre, glm::dvec2 ends[3]) const {
  auto c = selection_centre();
  if (!c) return false;
  Viewport vp{view_w_, view_h_};
  ScreenPoint sc = camera_.project(*c, vp.width, vp.height);
  if (!sc.in_clip_range) return false;
  centre = sc.pixel + glm::dvec2(view_x_, view_y_);
  const double len_world = 80.0 * camera_.world_per_pixel(view_h_) * (sc.view_depth / camera_.distance());
  for (int a = 0; a < 3; ++a) {
    glm::dvec3 axis(0.0);
    axis[a] = len_world;
    ends[a] = camera_.project(*c + axis, vp.width, vp.height).pixel + glm::dvec2(view_x_, view_y_);
  }
  return true;
}

void Editor::apply_move(const glm::dvec3& delta) {
  // one drag = one undo step: the document is rebuilt from the drag's start each time
  drag_total_ += delta;
  glm::dvec3 total = drag_total_;
  if (ImGui::GetIO().KeyCtrl) {  // snap the displacement to the grid
    const double g = grid_spacing();
    total = glm::round(total / g) * g;
  }
  auto verts = selection_.cage_vertices.indices();
  scene_->live = scene_->moved(drag_start_, verts, total);
}

void Editor::begin_move() {
  drag_start_ = scene_->doc();
  drag_total_ = glm::dvec3(0.0);
  scene_->history.begin(drag_start_);
}

void Editor::end_move() {
  if (scene_->live) scene_->history.commit("Move cage vertices", *scene_->live);
  else scene_->history.cancel();
  scene_->live.reset();
  drag_axis_ = -1;
}

double Editor::grid_spacing() const {
  double diag = scene_ ? bounding_box(scene_->skin_rest).diagonal() : 1.0;
  return std::pow(10.0, std::floor(std::log10(std::max(diag, 1e-6) / 10.0)));
}

void Editor::click_select(const ImVec2& mouse, bool add, bool remove) {
  Viewport vp{view_w_, view_h_};
  glm::dvec2 px = to_view(mouse);
  if (scene_->doc().cage && style_.show_cage) {
    auto v = pick_vertex(camera_, vp, px, scene_->cage_posed, 8.0);
    if (v) {
      uint32_t idx[1] = {*v};
      if (remove) selection_.cage_vertices.remove(idx);
      else if (add) selection_.cage_vertices.add(idx);
      else selection_.cage_vertices.set(idx);
      return;
    }
  }
  if (style_.show_skeleton) {
    auto j = pick_joint(camera_, vp, px, scene_->joint_heads, 8.0);
    if (j) {
      selected_joint_ = static_cast<int>(*j);
      return;
    }
  }
  if (!add && !remove) {
    selection_.cage_vertices.clear();
    selected_joint_ = -1;
  }
}

void Editor::handle_input() {
  ImGuiIO& io = ImGui::GetIO();
  const bool over_view = in_view(io.MousePos) && !io.WantCaptureMouse;
  if (scene_ && drag_axis_ >= 0) {  // a gizmo drag in progress
    if (!io.MouseDown[0]) {
      end_move();
    } else if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
      glm::dvec2 centre, ends[3];
      if (gizmo_handles(centre, ends)) {
        glm::dvec2 d(io.MouseDelta.x, io.MouseDelta.y);
        const double wpp = camera_.world_per_pixel(view_h_);
        if (drag_axis_ == 3) {
          apply_move(wpp * (d.x * camera_.right() - d.y * camera_.up()));
        } else {
          glm::dvec2 axis = ends[drag_axis_] - centre;
          double len = glm::length(axis);
          if (len > 1e-3) {
            const double world_len = 80.0 * wpp * (camera_.project(*selection_centre(), view_w_, view_h_).view_depth / camera_.distance());
            glm::dvec3 dir(0.0);
            dir[drag_axis_] = 1.0;
            apply_move(dir * (glm::dot(d, axis / len) / len * world_len));
          }
        }
      }
    }
    return;
  }
  if (over_view && scene_) {
    const bool alt = io.KeyAlt;
    const glm::dvec2 d(io.MouseDelta.x, io.MouseDelta.y);
    if (alt && io.MouseDown[1]) camera_.zoom(-0.02 * d.y);
    else if ((alt && io.MouseDown[0]) || io.MouseDown[1]) camera_.orbit(d.x, d.y);
    else if (io.MouseDown[2]) camera_.pan(d.x, d.y, view_h_);
    if (io.MouseWheel != 0) camera_.zoom(io.MouseWheel);
    if (!alt && ImGui::IsMouseClicked(0)) {
      glm::dvec2 centre, ends[3];
      int hit = -1;
      if (gizmo_handles(centre, ends)) {
        glm::dvec2 m(io.MousePos.x, io.MousePos.y);
        if (glm::length(m - centre) < 9) hit = 3;
        for (int a = 0; a < 3 && hit < 0; ++a) {
          glm::dvec2 ab = ends[a] - centre;
          double t = glm::clamp(glm::dot(m - centre, ab) / std::max(glm::dot(ab, ab), 1e-9), 0.0, 1.0);
          if (glm::length(m - (centre + t * ab)) < 6 && t > 0.15) hit = a;
        }
      }
      if (hit >= 0) {
        drag_axis_ = hit;
        begin_move();
      } else {
        box_selecting_ = true;
        box_start_ = io.MousePos;
      }
    }
  }
  if (box_selecting_ && !io.MouseDown[0]) {
    box_selecting_ = false;
    ImVec2 m = io.MousePos;
    const bool add = io.KeyShift, remove = io.KeyCtrl;
    if (std::abs(m.x - box_start_.x) < 4 && std::abs(m.y - box_start_.y) < 4) {
      click_select(m, add, remove);
    } else if (scene_ && scene_->doc().cage) {
      auto hits = box_select(camera_, Viewport{view_w_, view_h_}, to_view(box_start_), to_view(m), scene_->cage_posed);
      if (remove) selection_.cage_vertices.remove(hits);
      else if (add) selection_.cage_vertices.add(hits);
      else selection_.cage_vertices.set(hits);
    }
  }
  if (!io.WantCaptureKeyboard && scene_) {
    const bool ctrl = io.KeyCtrl, shift = io.KeyShift;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Z)) shift ? redo() : undo();
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Y)) redo();
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_S)) request_save();
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_O)) open_open_popup_ = true;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Q)) quit_requested_ = true;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_A) && scene_->doc().cage)
      selection_.cage_vertices = select_all(scene_->doc().cage->num_vertices());
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_I) && scene_->doc().cage)
      selection_.cage_vertices = invert(selection_.cage_vertices, scene_->doc().cage->num_vertices());
    if (!ctrl && ImGui::IsKeyPressed(GLFW_KEY_KP_ADD) && scene_->doc().cage)
      selection_.cage_vertices = grow_vertices(selection_.cage_vertices, scene_->doc().cage->polygons);
    if (!ctrl && ImGui::IsKeyPressed(GLFW_KEY_KP_SUBTRACT) && scene_->doc().cage)
      selection_.cage_vertices = shrink_vertices(selection_.cage_vertices, scene_->doc().cage->polygons);
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) selection_.cage_vertices.clear();
    if (!ctrl && ImGui::IsKeyPressed(GLFW_KEY_F)) frame_all();
    if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) scene_->player.playing() ? scene_->player.pause() : scene_->player.play();
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_1) || ImGui::IsKeyPressed(GLFW_KEY_1)) camera_.set_preset(ctrl ? ViewPreset::kBack : ViewPreset::kFront);
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_3) || ImGui::IsKeyPressed(GLFW_KEY_3)) camera_.set_preset(ctrl ? ViewPreset::kLeft : ViewPreset::kRight);
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_7) || ImGui::IsKeyPressed(GLFW_KEY_7)) camera_.set_preset(ctrl ? ViewPreset::kBottom : ViewPreset::kTop);
    if (ImGui::IsKeyPressed(GLFW_KEY_W) && !ctrl) style_.wireframe = !style_.wireframe;
    if (ImGui::IsKeyPressed(GLFW_KEY_X) && io.KeyAlt) style_.xray = !style_.xray;
    if (ImGui::IsKeyPressed(GLFW_KEY_F1)) show_help_ = !show_help_;
  }
}

void Editor::draw_gizmo() {
  ImDrawList* dl = ImGui::GetForegroundDrawList();
  if (box_selecting_) {
    ImVec2 m = ImGui::GetIO().MousePos;
    dl->AddRectFilled(box_start_, m, IM_COL32(255, 160, 40, 40));
    dl->AddRect(box_start_, m, IM_COL32(255, 160, 40, 200));
  }
  glm::dvec2 centre, ends[3];
  if (!scene_ || !gizmo_handles(centre, ends)) return;
  const ImU32 colours[3] = {IM_COL32(235, 70, 70, 255), IM_COL32(90, 220, 90, 255), IM_COL32(80, 130, 255, 255)};
  ImVec2 c(static_cast<float>(centre.x), static_cast<float>(centre.y));
  for (int a = 0; a < 3; ++a) {
    ImVec2 e(static_cast<float>(ends[a].x), static_cast<float>(ends[a].y));
    dl->AddLine(c, e, drag_axis_ == a ? IM_COL32(255, 230, 80, 255) : colours[a], 3.0f);
    dl->AddCircleFilled(e, 5.0f, drag_axis_ == a ? IM_COL32(255, 230, 80, 255) : colours[a]);
  }
  dl->AddRect(ImVec2(c.x - 6, c.y - 6), ImVec2(c.x + 6, c.y + 6), drag_axis_ == 3 ? IM_COL32(255, 230, 80, 255) : IM_COL32(230, 230, 230, 255), 0, 0, 2.0f);
}

void Editor::undo() {
  if (!scene_ || !scene_->history.can_undo()) return;
  std::string label = scene_->history.undo_label();
  scene_->history.undo();
  scene_->document_changed();
  log(label);
}

void Editor::redo() {
  if (!scene_ || !scene_->history.can_redo()) return;
  std::string label = scene_->history.redo_label();
  scene_->history.redo();
  scene_->document_changed();
  log(label);
}

void Editor::request_save() {
  if (!scene_) return;
  if (scene_->doc().project_path.empty()) open_save_popup_ = true;
  else save_project_to(scene_->doc().project_path);
}

bool Editor::save_project_to(const std::string& path) {
  auto st = save_project(path, scene_->doc());
  if (!st.ok()) {
    error_modal_ = st.error().message;
    log("error: " + st.error().message, true);
    return false;
  }
  scene_->history.mark_saved(path);
  log("saved " + path);
  if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  return true;
}

bool Editor::open_path(const std::string& path) {
  std::vector<std::string> warnings;
  auto s = has_extension(path, ".cagewrap") ? load_project_scene(path, warnings) : load_scene(path, "");
  if (!s.ok()) {  // the current document stays as it is
    error_modal_ = s.error().message;
    log("error: " + s.error().message, true);
    return false;
  }
  for (const auto& w : warnings) log("warning: " + w);
  log("opened " + path);
  set_scene(std::move(s).value());
  if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  return true;
}

void Editor::draw_menu() {
  if (!ImGui::BeginMainMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("Open...", "Ctrl+O")) open_open_popup_ = true;
    if (ImGui::BeginMenu("Open Recent")) {
      std::string message;
      auto recent = files_.draw_recent_menu(message);
      if (!message.empty()) log(message);
      if (recent && !open_path(*recent) && !std::filesystem::exists(*recent)) log(files_.forget_recent(*recent));
      ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Save", "Ctrl+S", false, scene_ != nullptr)) request_save();
    if (ImGui::MenuItem("Save as...", nullptr, false, scene_ != nullptr)) open_save_popup_ = true;
    ImGui::Separator();
    if (ImGui::MenuItem("Import cage...", nullptr, false, scene_ != nullptr)) browse(FilePurpose::kImportCage);
    ImGui::Separator();
    if (ImGui::MenuItem("Screenshot...", "F12")) browse(FilePurpose::kScreenshot);
    if (ImGui::MenuItem("Screenshot of the 3-D view...")) {
      browse(FilePurpose::kScreenshot);
      screenshot_view_only_ = true;
    }
    ImGui::Separator();
    if (ImGui::MenuItem("Quit", "Ctrl+Q")) quit_requested_ = true;
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Edit")) {
    const bool u = scene_ && scene_->history.can_undo(), r = scene_ && scene_->history.can_redo();
    if (ImGui::MenuItem(u ? scene_->history.undo_label().c_str() : "Undo", "Ctrl+Z", false, u)) undo();
    if (ImGui::MenuItem(r ? scene_->history.redo_label().c_str() : "Redo", "Ctrl+Shift+Z", false, r)) redo();
    ImGui::Separator();
    const bool cage = scene_ && scene_->doc().cage;
    if (ImGui::MenuItem("Select all", "Ctrl+A", false, cage)) selection_.cage_vertices = select_all(scene_->doc().cage->num_vertices());
    if (ImGui::MenuItem("Select none", "Esc", false, cage)) selection_.cage_vertices.clear();
    if (ImGui::MenuItem("Invert selection", "Ctrl+I", false, cage))
      selection_.cage_vertices = invert(selection_.cage_vertices, scene_->doc().cage->num_vertices());
    if (ImGui::MenuItem("Grow selection", "Num+", false, cage))
      selection_.cage_vertices = grow_vertices(selection_.cage_vertices, scene_->doc().cage->polygons);
    if (ImGui::MenuItem("Shrink selection", "Num-", false, cage))
      selection_.cage_vertices = shrink_vertices(selection_.cage_vertices, scene_->doc().cage->polygons);
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
    const Character& ch = *scene_->doc().character;
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
      if (scene_->doc().cage) {
        ImGui::Text("%zu vertices, %zu faces", scene_->doc().cage->num_vertices(), scene_->doc().cage->polygons.num_faces());
        ImGui::TextDisabled("%zu control elements", scene_->doc().cage->num_elements());
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
  if (scene_ && scene_->doc().cage) {
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
  if (scene_ && !scene_->doc().character->clips.empty()) {
    const auto& clips = scene_->doc().character->clips;
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
    if (scene_->doc().cage) ImGui::Text("cage %zu vertices, %zu faces", scene_->doc().cage->num_vertices(), scene_->doc().cage->polygons.num_faces());
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
                           {"Alt+X", "X-ray"},                   {"F1", "this window"},
                           {"Ctrl+O / Ctrl+S", "open / save"},    {"F12", "screenshot"}};
  for (auto& r : rows) {
    ImGui::TextUnformatted(r[0]);
    ImGui::SameLine(210);
    ImGui::TextDisabled("%s", r[1]);
  }
  ImGui::End();
}

// Opens the file browser in `dir`, else near the project, else in the last folder browsed.
void Editor::browse(FilePurpose purpose, const std::string& dir) {
  std::string near, name;
  if (purpose == FilePurpose::kSaveProject && scene_) {
    near = scene_->doc().project_path;
    name = near.empty() ? std::filesystem::path(scene_->doc().character_path).stem().string() + ".cagewrap"
                        : std::filesystem::path(near).filename().string();
  } else if (purpose == FilePurpose::kScreenshot) {
    name = "cagewrap_screenshot.png";
  }
  screenshot_view_only_ = false;
  if (!dir.empty()) files_.browser().open(purpose, dir, name);
  else files_.browse(purpose, near, name);
}

// Script commands for files (see run_script_step; PATH and NAME are the rest of the line):
// open PATH | import_cage PATH |
// browse open|save|import_cage|screenshot [DIR] | browser_select NAME | browser_name NAME |
// browser_confirm | browser_cancel | toggle wireframe|xray|skin|cage|skeleton|grid
bool Editor::run_file_script_command(const std::string& cmd, std::istringstream& in) {
  // the argument is the rest of the line (names may hold spaces); `browse` splits off its first word
  std::string arg, rest;
  std::getline(in >> std::ws, arg);
  arg.erase(arg.find_last_not_of(" \t\r") + 1);
  if (cmd == "browse") {
    const size_t space = arg.find(' ');
    if (space != std::string::npos) rest = arg.substr(arg.find_first_not_of(' ', space));
    arg.resize(std::min(space, arg.size()));
  }
  if (cmd == "open") open_path(arg);
  else if (cmd == "import_cage") import_cage(arg);
  else if (cmd == "browse") {
    const std::pair<const char*, FilePurpose> purposes[] = {{"open", FilePurpose::kOpen}, {"save", FilePurpose::kSaveProject},
                                                            {"import_cage", FilePurpose::kImportCage}, {"screenshot", FilePurpose::kScreenshot}};
    auto it = std::find_if(std::begin(purposes), std::end(purposes), [&](const auto& p) { return arg == p.first; });
    if (it == std::end(purposes)) return false;
    browse(it->second, rest);
  } else if (cmd == "browser_select") {
    if (!files_.browser().select(arg)) log("error: script: no " + arg + " in " + files_.browser().directory(), true);
  } else if (cmd == "browser_name") files_.browser().set_file_name(arg);
  else if (cmd == "browser_confirm") files_.browser().confirm();
  else if (cmd == "browser_cancel") files_.browser().cancel();
  else if (cmd == "toggle") {
    bool* flags[] = {&style_.wireframe, &style_.xray, &style_.show_skin, &style_.show_cage, &style_.show_skeleton, &style_.show_grid};
    const char* names[] = {"wireframe", "xray", "skin", "cage", "skeleton", "grid"};
    auto it = std::find(std::begin(names), std::end(names), arg);
    if (it == std::end(names)) return false;
    bool* f = flags[it - std::begin(names)];
    *f = !*f;
  } else return false;
  return true;
}

void Editor::act_on(const EditorFiles::Choice& choice) {
  switch (choice.purpose) {
    case FilePurpose::kOpen: open_path(choice.path); break;
    case FilePurpose::kImportCage: import_cage(choice.path); break;
    case FilePurpose::kSaveProject:
      if (scene_ && save_project_to(choice.path) && quit_after_save_) glfwSetWindowShouldClose(window_, 1);
      break;
    case FilePurpose::kScreenshot:
      pending_screenshot_ = choice.path;
      pending_screenshot_frames_ = 2;  // the dialog leaves the picture first
      break;
  }
  quit_after_save_ = false;
}

bool Editor::import_cage(const std::string& path) {
  if (!scene_) return false;
  auto imported = scene_->import_cage(path);
  if (!imported) {
    error_modal_ = imported.error().message;
    log("error: " + imported.error().message, true);
    return false;
  }
  log(*imported);
  return true;
}

void Editor::draw_file_popups() {
  if (!ImGui::GetIO().WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_F12)) browse(FilePurpose::kScreenshot);
  if (open_save_popup_ && scene_) browse(FilePurpose::kSaveProject);
  if (open_open_popup_) browse(FilePurpose::kOpen);
  open_save_popup_ = open_open_popup_ = false;
  if (auto choice = files_.draw_browser()) act_on(*choice);
  else if (!files_.browsing()) quit_after_save_ = false;  // the Save as was cancelled
  if (quit_requested_) {
    if (scene_ && scene_->history.dirty()) ImGui::OpenPopup("Save changes?");
    else glfwSetWindowShouldClose(window_, 1);
    quit_requested_ = false;
  }
  if (ImGui::BeginPopupModal("Save changes?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextUnformatted("The project has unsaved changes.");
    if (ImGui::Button("Save", ImVec2(100, 0))) {
      if (scene_->doc().project_path.empty()) {
        open_save_popup_ = quit_after_save_ = true;
      } else if (save_project_to(scene_->doc().project_path)) {
        glfwSetWindowShouldClose(window_, 1);
      }
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Discard", ImVec2(100, 0))) glfwSetWindowShouldClose(window_, 1);
    ImGui::SameLine();
    if (ImGui::Button("Cancel", ImVec2(100, 0))) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
}

// Scripted editor actions, one per line, for tests (`--script file`):
//   wait N | select_cage_vertex I [add] | select_cage_vertices_all | move DX DY DZ | undo | redo
//   save PATH | screenshot PATH | play | pause | time T, and those of run_file_script_command
// `move` goes through the gizmo's own path: one drag, one undo step.
void Editor::run_script_step() {
  if (script_wait_ > 0) {
    --script_wait_;
    return;
  }
  while (script_pos_ < script_.size() && script_wait_ == 0) {
    std::istringstream in(script_[script_pos_++]);
    std::string cmd;
    in >> cmd;
    if (cmd.empty() || cmd[0] == '#') continue;
    if (!scene_) break;
    if (cmd == "wait") in >> script_wait_;
    else if (cmd == "select_cage_vertex") {
      uint32_t i;
      std::string mode;
      in >> i >> mode;
      uint32_t idx[1] = {i};
      if (mode == "add") selection_.cage_vertices.add(idx);
      else selection_.cage_vertices.set(idx);
    } else if (cmd == "select_cage_vertices_all" && scene_->doc().cage) {
      selection_.cage_vertices = select_all(scene_->doc().cage->num_vertices());
    } else if (cmd == "move") {
      glm::dvec3 d;
      in >> d.x >> d.y >> d.z;
      begin_move();
      apply_move(d);
      end_move();
    } else if (cmd == "undo") undo();
    else if (cmd == "redo") redo();
    else if (cmd == "save") {
      std::string p;
      in >> p;
      save_project_to(p);
    } else if (cmd == "screenshot") {
      in >> pending_screenshot_;
      script_wait_ = 1;  // taken after this frame renders
    } else if (cmd == "play") scene_->player.play();
    else if (cmd == "pause") scene_->player.pause();
    else if (cmd == "time") {
      double t;
      in >> t;
      scene_->player.scrub(t);
    } else if (!run_file_script_command(cmd, in))
      log("error: script line " + std::to_string(script_pos_) + ": unknown command '" + cmd + "'", true);
  }
}

void Editor::draw_panels() {
  draw_menu();
  draw_file_popups();
  draw_gizmo();
  draw_outliner();
  draw_properties();
  draw_timeline();
  draw_log();
  draw_stats();
  draw_help();
}

bool Editor::save_screenshot(const std::string& path, bool view_only) {
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
  int x0 = 0, y0 = 0, cw = w, ch = h;  // the whole window, or only the 3-D view
  if (view_only) {
    x0 = std::clamp(static_cast<int>(view_x_), 0, w - 1);
    y0 = std::clamp(static_cast<int>(view_y_), 0, h - 1);
    cw = std::min(static_cast<int>(view_w_), w - x0);
    ch = std::min(static_cast<int>(view_h_), h - y0);
  }
  if (!stbi_write_png(path.c_str(), cw, ch, 4, flipped.data() + (static_cast<size_t>(y0) * w + x0) * 4, w * 4)) {
    log("error: " + path + ": cannot write the screenshot", true);
    return false;
  }
  log("saved screenshot " + path);
  return true;
}

int Editor::run() {
  for (const auto& w : files_.load()) log("warning: " + w);
  if (options_.width <= 0 || options_.height <= 0) {  // not given: the size the window was left at
    options_.width = files_.prefs().window_width;
    options_.height = files_.prefs().window_height;
  }
  files_.apply(style_);
  if (!open_window()) return 1;
  glfwSetWindowUserPointer(window_, this);
  glfwSetDropCallback(window_, [](GLFWwindow* w, int count, const char** paths) {
    auto* self = static_cast<Editor*>(glfwGetWindowUserPointer(w));
    if (count > 0) self->dropped_ = paths[0];
  });
  if (!options_.script.empty()) {
    std::ifstream in(options_.script);
    if (!in) {
      std::fprintf(stderr, "error: %s: cannot open the script\n", options_.script.c_str());
      return 1;
    }
    for (std::string line; std::getline(in, line);) script_.push_back(line);
  }
  load_initial();
  int frame = 0;
  int exit_code = 0;
  auto last = std::chrono::steady_clock::now();
  const bool scripted = !options_.screenshot.empty() || !script_.empty();
  while (!glfwWindowShouldClose(window_)) {
    glfwPollEvents();
    auto now = std::chrono::steady_clock::now();
    double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    fps_ = 0.9 * fps_ + 0.1 * (dt > 0 ? 1.0 / dt : 0.0);
    int w, h;
    glfwGetFramebufferSize(window_, &w, &h);
    view_x_ = kLeftWidth;
    view_y_ = kMenuHeight;
    view_w_ = std::max(1.0f, w - kLeftWidth - kRightWidth);
    view_h_ = std::max(1.0f, h - kMenuHeight - kBottomHeight);
    if (!dropped_.empty()) {
      open_path(dropped_);
      dropped_.clear();
    }
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    handle_input();
    // a scripted run waits for the first bind so that the steps act on the deformed skin
    if (!script_.empty() && !(scene_ && scene_->job)) run_script_step();

    if (scene_) {
      if (scene_->doc().cage != shown_cage_) {  // a cage imported, or undo/redo across an import
        if (!scene_->doc().cage || !shown_cage_ || scene_->doc().cage->num_vertices() != shown_cage_->num_vertices())
          selection_.cage_vertices.clear();
        shown_cage_ = scene_->doc().cage;
        topology_dirty_ = true;
      }
      if (auto msg = scene_->poll_bind()) {
        log(*msg, msg->rfind("error", 0) == 0);
        if (scene_->binding && !scene_->binding->invalid_elements.empty())
          log("warning: " + std::to_string(scene_->binding->invalid_elements.size()) + " cage elements skipped (zero area, non-finite or duplicate)");
      }
      // scripted runs advance a fixed 1/30 s per frame so they are reproducible
      scene_->player.advance(scripted ? 1.0 / 30.0 : dt);
      scene_->update_pose();
      if (topology_dirty_) upload_topology();
      renderer_->update_skin(scene_->skin_posed);
      if (scene_->doc().cage) {
        selected_mask_.assign(scene_->doc().cage->num_vertices(), 0);
        for (uint32_t v : selection_.cage_vertices.indices())
          if (v < selected_mask_.size()) selected_mask_[v] = 1;
        renderer_->update_cage(scene_->cage_posed, selected_mask_);
      }
      renderer_->update_skeleton(scene_->joint_heads, scene_->bones, selected_joint_);
      std::string title = "cagewrap - " + (scene_->doc().project_path.empty() ? std::string("untitled") : scene_->doc().project_path) +
                          (scene_->history.dirty(scene_->doc()) ? " *" : "");
      if (title != title_) glfwSetWindowTitle(window_, (title_ = title).c_str());
    }
    draw_panels();
    ImGui::Render();

    glViewport(0, 0, w, h);
    glClearColor(0.16f, 0.17f, 0.19f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (scene_) {
      render::ViewParams v;
      v.x = static_cast<int>(kLeftWidth);
      v.y = static_cast<int>(kBottomHeight);
      v.width = static_cast<int>(view_w_);
      v.height = static_cast<int>(view_h_);
      v.view = glm::mat4(camera_.view());
      v.projection = glm::mat4(camera_.projection(double(v.width) / double(v.height)));
      v.grid_spacing = static_cast<float>(grid_spacing());
      renderer_->draw(v, style_);
    }
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++frame;
    if (!pending_screenshot_.empty() && pending_screenshot_frames_-- <= 0) {
      save_screenshot(pending_screenshot_, screenshot_view_only_);
      pending_screenshot_.clear();
      screenshot_view_only_ = false;
    }
    const bool script_done = script_pos_ >= script_.size() && script_wait_ == 0;
    if (!options_.screenshot.empty() && frame >= options_.frames && script_done && !(scene_ && scene_->job)) {
      exit_code = save_screenshot(options_.screenshot) ? 0 : 1;
      break;
    }
    if (options_.screenshot.empty() && !script_.empty() && script_done && frame > 1) break;
    glfwSwapBuffers(window_);
  }
  int window_w = 0, window_h = 0;
  glfwGetWindowSize(window_, &window_w, &window_h);
  files_.remember(style_, window_w, window_h);
  if (auto e = files_.save(); !e.empty()) log("warning: " + e);
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
