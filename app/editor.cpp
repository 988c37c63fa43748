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
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <functional>
#include <sstream>
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>

#include "app/cage_tools.h"
#include "app/export_panel.h"
#include "app/fidelity_panel.h"
#include "app/offscreen_surface.h"
#include "app/patch_panel.h"
#include "app/rig_panel.h"
#include "app/sets_panel.h"
#include "app/sim_panel.h"
#include "app/skin_display.h"
#include "app/editor_files.h"
#include "app/editor_scene.h"
#include "app/project_dialogs.h"
#include "app/workspace/autosave.h"
#include "core/deform/binding_cache.h"
#include "app/workspace/camera.h"
#include "core/io/mesh_io.h"
#include "app/workspace/move_gizmo.h"
#include "app/workspace/rotate_gizmo.h"
#include "app/workspace/soft_selection.h"
#include "core/geometry/triangle_bvh.h"
#include "app/workspace/picking.h"
#include "core/io/project_io.h"
#include "core/geometry/selection.h"
#include "core/rig/demo_character.h"
#include "core/io/gltf_writer.h"
#include "render/viewport_renderer.h"

namespace cagewrap::app {

namespace {

// Fixed panel layout (pixels): the 3-D view is what the panels leave free.
constexpr float kMenuHeight = 19.0f, kLeftWidth = 260.0f, kRightWidth = 300.0f, kBottomHeight = 170.0f;

enum class SelectMode : uint8_t { kCageVertices, kCageFaces, kSkinVertices, kJoints };  // F5..F8
enum class SelectOp : uint8_t { kAll, kNone, kInvert, kGrow, kShrink, kMirror };

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
  bool open_glfw_window();
  void framebuffer_size(int& w, int& h) const;  // of the window, or of the offscreen frame
  void load_initial();
  void set_scene(std::unique_ptr<Scene> scene);
  void upload_topology();
  void frame_all();
  void handle_input();
  glm::dvec2 to_view(const ImVec2& p) const;
  bool in_view(const ImVec2& p) const;
  static const char* mode_name(SelectMode m);
  IndexSet& active_set();
  uint32_t active_count() const;
  void edit_selection(SelectOp op);
  std::vector<glm::vec3> face_centroids(std::span<const glm::vec3> positions) const;
  double scene_size() const;
  double mirror_tolerance() const;
  double rig_mirror_tolerance() const;
  IndexSet move_set() const;
  Result<MoveWeights> move_weights_now() const;
  // The selected cage vertices with their soft-selection shares, for the Simulation window.
  std::vector<std::pair<uint32_t, float>> sim_paint_weights() const;
  std::optional<glm::dvec3> selection_centre() const;
  GizmoLayout gizmo() const;
  void apply_move(const glm::dvec3& total);
  bool begin_move(GizmoHandle handle, glm::dvec2 from);
  void end_move();
  double grid_spacing() const;
  const TriangleBvh& skin_occluder();
  void click_select(const ImVec2& mouse, bool add, bool remove);
  void box_select_in_mode(const ImVec2& a, const ImVec2& b, bool add, bool remove);
  void draw_toolbar();
  void draw_move_tool();
  void draw_pose_panel();
  void paint_dab(const ImVec2& mouse);
  int posed_joint() const;
  RotateGizmoLayout rotate_gizmo() const;
  void begin_rotate(RotateHandle handle, glm::dvec2 from);
  void apply_rotate(double angle);
  void set_override(uint32_t node, const glm::quat& q);
  void update_selection_display();
  void draw_gizmo();
  void undo();
  void redo();
  void request_save();
  bool save_project_to(const std::string& path);
  bool open_path(const std::string& path);
  bool open_project(const std::string& path, const std::string& character_override = {});
  void act_on(const ProjectDialogs::Request& request);
  bool import_cage(const std::string& path);
  void guard_unsaved(std::function<void()> action);
  void browse(FilePurpose purpose, const std::string& dir = {});
  void act_on(const EditorFiles::Choice& choice);
  bool run_file_script_command(const std::string& cmd, std::istringstream& in);
  void run_script_step();
  void script_gizmo_drag(std::istringstream& in);
  void script_rotate_drag(std::istringstream& in);
  void script_export(std::istringstream& in);
  void script_bind_param(std::istringstream& in);
  void script_memory(std::istringstream& in);
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
  std::unique_ptr<OffscreenSurface> offscreen_;  // --offscreen: no window, an EGL context and a framebuffer
  bool close_ = false;                          // quit chosen (offscreen runs end with their script)
  std::unique_ptr<render::ViewportRenderer> renderer_ = std::make_unique<render::ViewportRenderer>();
  render::ViewportStyle style_;
  Camera camera_;
  Selection selection_;
  // the 3-D view rectangle in window pixels (top-left origin), updated every frame
  float view_x_ = 0, view_y_ = 0, view_w_ = 1, view_h_ = 1;
  SelectMode mode_ = SelectMode::kCageVertices;
  SoftSelectionParams soft_;
  MirrorParams mirror_;                   // tolerance set from mirror_tolerance_share_ when used
  // Moves edit the reference (rest) cage instead of adding pose offsets: the skin stays and only the
  // skin points near the moved vertices are registered again (Scene::moved_rest).
  bool move_rest_ = false;
  double mirror_tolerance_share_ = 1e-3;  // of the skin's bounding-box diagonal
  // gizmo drag
  GizmoHandle drag_handle_ = GizmoHandle::kNone;
  glm::dvec2 drag_from_{0.0};    // view pixels where it began
  glm::dvec3 drag_centre_{0.0};  // gizmo centre when it began
  bool drag_patch_ = false;      // the drag moves the parametric driver's selected control point
  glm::dvec3 drag_total_{0.0};   // displacement so far (snapped)
  MoveWeights drag_weights_;
  Document drag_start_;
  // joint rotation drag (posing is view state: not undone, never saved)
  RotateHandle rot_handle_ = RotateHandle::kNone;
  glm::dvec2 rot_from_{0.0};
  RotateGizmoLayout rot_layout_;  // at the drag's start
  glm::quat rot_start_{1, 0, 0, 0};
  glm::vec3 rot_local_axis_{1, 0, 0};
  double rot_angle_ = 0.0;
  PolygonPicker cage_picker_;
  TriangleBvh skin_bvh_;
  bool skin_bvh_built_ = false;
  // what the viewport shows of the selection, rebuilt when the selection or the tool changes
  std::vector<float> cage_weights_;
  std::vector<uint8_t> face_mask_, joint_mask_;
  std::vector<glm::vec4> bone_colors_;  // per cage vertex, when colouring the cage by bone
  bool color_by_bone_ = false;
  std::string display_key_;
  bool box_selecting_ = false;
  ImVec2 box_start_{0, 0};
  EditorFiles files_;  // preferences, recent files, the file browser (app/editor_files.h)
  ProjectDialogs dialogs_;  // locate a moved character, recover unsaved work, embed/cache (app/project_dialogs.h)
  std::unique_ptr<Autosave> autosave_;  // the recovery file of unsaved work (app/workspace/autosave.h)
  bool recovered_ = false;  // the document came from a recovery file and was not saved since
  // requests for the file browser: Save as, Open (Ctrl+O); quit once the Save as is done
  bool open_save_popup_ = false, open_open_popup_ = false, quit_requested_ = false;
  // "Save changes?": what to do once the unsaved work is saved or discarded (quit, open, new), and
  // what to do after a Save as that the prompt started
  std::function<void()> pending_action_, after_save_;
  bool open_prompt_ = false;
  std::string script_answer_;  // a scripted press of the prompt's Save / Discard / Cancel
  bool script_error_ok_ = false;  // a scripted press of the Error dialog's OK
  bool screenshot_view_only_ = false;
  int pending_screenshot_frames_ = 0;  // frames to wait (a dialog that just closed leaves the picture)
  std::shared_ptr<const Cage> shown_cage_;  // the cage the renderer and the selection were made for
  std::vector<std::string> script_;
  size_t script_pos_ = 0;
  int script_wait_ = 0;
  std::string pending_screenshot_;
  std::string dropped_;  // a file dropped on the window, opened next frame
  std::string title_;
  std::unique_ptr<Scene> scene_;
  CageTools cage_tools_;
  ExportPanel export_panel_;
  FidelityPanel fidelity_panel_;
  bool script_waits_for_export_ = true;    // false after `export_nowait`: the script goes on meanwhile
  bool script_waits_for_fidelity_ = true;  // false after `fidelity_check_nowait`
  SkinDisplay skin_display_;  // the skin on the GPU or the CPU, and the frame-time split
  RigPanel rig_panel_;
  SetsPanel sets_panel_;
  SimPanel sim_panel_;
  PatchPanel patch_panel_;
  bool painting_ = false;  // a set-edit brush stroke in progress
  bool skin_colored_ = false;
  EditorHooks hooks_;
  std::deque<LogLine> log_;
  std::string error_modal_;
  bool show_help_ = false;
  bool topology_dirty_ = true;
  double fps_ = 0.0;
};

void Editor::log(std::string text, bool error) {
  if (!log_.empty() && log_.back().text == text) {
    log_.back().repeats++;
    return;
  }
  std::fprintf(error ? stderr : stdout, "%s\n", text.c_str());
  std::fflush(error ? stderr : stdout);  // the log survives a crash or a kill
  log_.push_back({std::move(text), 1, error});
  if (log_.size() > 500) log_.pop_front();
}

bool Editor::open_window() {
  if (options_.offscreen) {
    auto surface = OffscreenSurface::create(options_.width, options_.height, 4);
    if (!surface) {
      std::fprintf(stderr, "error: --offscreen: %s\n", surface.error().message.c_str());
      return false;
    }
    offscreen_ = std::move(*surface);
    std::printf("offscreen %d x %d: %s\n", offscreen_->width(), offscreen_->height(), offscreen_->description().c_str());
  } else if (!open_glfw_window()) {
    return false;
  }
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // layout is fixed; preferences live elsewhere
  ImGui::StyleColorsDark();
  ImGui::GetStyle().WindowRounding = 3.0f;
  if (window_) ImGui_ImplGlfw_InitForOpenGL(window_, true);
  ImGui_ImplOpenGL3_Init("#version 330");
  std::string err;
  if (!renderer_->init(err)) {
    std::fprintf(stderr, "error: %s\n", err.c_str());
    return false;
  }
  return true;
}

bool Editor::open_glfw_window() {
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
  return true;
}

void Editor::framebuffer_size(int& w, int& h) const {
  if (offscreen_) {
    w = offscreen_->width();
    h = offscreen_->height();
  } else {
    glfwGetFramebufferSize(window_, &w, &h);
  }
}

void Editor::set_scene(std::unique_ptr<Scene> scene) {
  scene_ = std::move(scene);
  if (autosave_) autosave_->discard();  // the work it held was saved or discarded (guard_unsaved)
  recovered_ = false;
  skin_display_.scene_changed();
  fidelity_panel_.scene_changed();
  topology_dirty_ = true;
  skin_bvh_built_ = false;
  display_key_.clear();
  soft_.radius = 0.1 * scene_size();
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
  if (has_extension(path, ".cagewrap")) {  // the project's own messages, prompts and recent files
    open_project(path);
    return;
  }
  auto s = load_scene(path, cage);
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
  Aabb box = bounding_box(scene_->skin_posed().empty() ? scene_->skin_rest : scene_->skin_posed());
  camera_.frame(box, view_w_ / std::max(1.0f, view_h_));
}

void Editor::upload_topology() {
  renderer_->set_skin_topology(scene_->skin_rest.size(), scene_->skin_triangles());
  if (const Cage* cage = scene_->doc().cage.get()) {
    renderer_->set_cage_topology(cage->polygons, cage->elements, cage->element_face);
    cage_picker_ = PolygonPicker(cage->polygons);
  }
  skin_bvh_built_ = false;
  display_key_.clear();
  topology_dirty_ = false;
}

// Rebuilds the per-vertex display of the selection (soft weights, face and joint masks) when the
// selection, the tool settings or the cage changed.
void Editor::update_selection_display() {
  const Cage* cage = scene_->doc().cage.get();
  std::string key = std::to_string(reinterpret_cast<uintptr_t>(cage)) + "/" + std::to_string(static_cast<int>(mode_)) + "/" +
                    std::to_string(soft_.enabled) + std::to_string(soft_.radius) + std::to_string(static_cast<int>(soft_.falloff)) +
                    std::to_string(static_cast<int>(soft_.distance)) + "/" + std::to_string(mirror_.enabled) +
                    std::to_string(mirror_tolerance_share_) + "/";
  for (const IndexSet* set : {&selection_.cage_vertices, &selection_.cage_faces, &selection_.joints}) {
    key += std::to_string(set->size()) + ":";
    for (uint32_t i : *set) key += std::to_string(i) + ",";
  }
  if (sim_panel_.visible()) key += "/sim" + std::to_string(scene_->doc().revision);
  key += "/bones" + std::to_string(color_by_bone_) + std::to_string(reinterpret_cast<uintptr_t>(scene_->attachment ? scene_->attachment->joint.data() : nullptr));
  if (key == display_key_) return;
  display_key_ = std::move(key);
  // the cage coloured by the bone each vertex follows; in joint mode the selected joints' vertices
  // are highlighted
  bone_colors_.clear();
  if (cage && scene_->attachment && scene_->attachment->joint.size() == cage->num_vertices()) {
    const Character& ch = *scene_->doc().character;
    const auto& joints = ch.skins[scene_->attachment->skin].joints;
    if (color_by_bone_) {
      bone_colors_.resize(cage->num_vertices());
      for (size_t v = 0; v < bone_colors_.size(); ++v) {
        const double hue = std::fmod(0.618033988749895 * scene_->attachment->joint[v], 1.0) * 6.0;
        const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
        glm::vec3 rgb = hue < 1 ? glm::vec3(1, x, 0) : hue < 2 ? glm::vec3(x, 1, 0) : hue < 3 ? glm::vec3(0, 1, x)
                      : hue < 4 ? glm::vec3(0, x, 1) : hue < 5 ? glm::vec3(x, 0, 1) : glm::vec3(1, 0, x);
        bone_colors_[v] = glm::vec4(0.25f + 0.7f * rgb, 1.0f);
      }
    }
    if (sim_panel_.visible()) bone_colors_ = SimPanel::vertex_colors(scene_->doc().sim, cage->num_vertices());
    if (mode_ == SelectMode::kJoints && !selection_.joints.empty()) {
      cage_weights_.assign(cage->num_vertices(), 0.0f);
      for (size_t v = 0; v < cage_weights_.size(); ++v) {
        const uint32_t j = scene_->attachment->joint[v];
        if (j < joints.size() && selection_.joints.contains(joints[j])) cage_weights_[v] = 1.0f;
      }
    }
  }
  if (mode_ == SelectMode::kJoints && !selection_.joints.empty() && !cage_weights_.empty()) {
    face_mask_.clear();
    joint_mask_.assign(scene_->joint_heads.size(), 0);
    for (uint32_t j : selection_.joints)
      if (j < joint_mask_.size()) joint_mask_[j] = 1;
    return;
  }
  cage_weights_.clear();
  face_mask_.clear();
  if (cage) {
    auto w = move_weights_now();
    if (w.ok()) cage_weights_ = w.value().dense(cage->num_vertices());
    if (mode_ != SelectMode::kCageFaces)  // the vertex selection stays visible in the other modes
      for (uint32_t v : selection_.cage_vertices)
        if (v < cage_weights_.size()) cage_weights_[v] = std::max(cage_weights_[v], 1.0f);
    face_mask_.assign(cage->polygons.num_faces(), 0);
    for (uint32_t f : selection_.cage_faces)
      if (f < face_mask_.size()) face_mask_[f] = 1;
  }
  joint_mask_.assign(scene_->joint_heads.size(), 0);
  for (uint32_t j : selection_.joints)
    if (j < joint_mask_.size()) joint_mask_[j] = 1;
}

glm::dvec2 Editor::to_view(const ImVec2& p) const { return {p.x - view_x_, p.y - view_y_}; }

bool Editor::in_view(const ImVec2& p) const {
  return p.x >= view_x_ && p.y >= view_y_ && p.x < view_x_ + view_w_ && p.y < view_y_ + view_h_;
}

const char* Editor::mode_name(SelectMode m) {
  switch (m) {
    case SelectMode::kCageVertices: return "cage vertices";
    case SelectMode::kCageFaces: return "cage faces";
    case SelectMode::kSkinVertices: return "skin vertices";
    case SelectMode::kJoints: return "joints";
  }
  return "?";
}

IndexSet& Editor::active_set() {
  switch (mode_) {
    case SelectMode::kCageFaces: return selection_.cage_faces;
    case SelectMode::kSkinVertices: return selection_.skin_vertices;
    case SelectMode::kJoints: return selection_.joints;
    case SelectMode::kCageVertices: break;
  }
  return selection_.cage_vertices;
}

uint32_t Editor::active_count() const {
  if (!scene_) return 0;
  const Cage* cage = scene_->doc().cage.get();
  switch (mode_) {
    case SelectMode::kCageVertices: return cage ? static_cast<uint32_t>(cage->num_vertices()) : 0;
    case SelectMode::kCageFaces: return cage ? static_cast<uint32_t>(cage->polygons.num_faces()) : 0;
    case SelectMode::kSkinVertices: return static_cast<uint32_t>(scene_->skin_rest.size());
    case SelectMode::kJoints: return static_cast<uint32_t>(scene_->joint_heads.size());
  }
  return 0;
}

// Select menu operations on the active mode's set.
void Editor::edit_selection(SelectOp op) {
  if (!scene_) return;
  IndexSet& s = active_set();
  const uint32_t n = active_count();
  const Cage* cage = scene_->doc().cage.get();
  const bool cage_mode = mode_ == SelectMode::kCageVertices || mode_ == SelectMode::kCageFaces;
  if (cage_mode && !cage) return;
  switch (op) {
    case SelectOp::kAll: s = select_all(n); break;
    case SelectOp::kNone: s.clear(); break;
    case SelectOp::kInvert: s = invert(s, n); break;
    case SelectOp::kGrow:
    case SelectOp::kShrink: {
      const bool grow = op == SelectOp::kGrow;
      if (mode_ == SelectMode::kCageVertices) s = grow ? grow_vertices(s, cage->polygons) : shrink_vertices(s, cage->polygons);
      else if (mode_ == SelectMode::kCageFaces) s = grow ? grow_faces(s, cage->polygons) : shrink_faces(s, cage->polygons);
      else if (mode_ == SelectMode::kSkinVertices) s = grow ? grow_vertices(s, scene_->skin_topology) : shrink_vertices(s, scene_->skin_topology);
      break;
    }
    case SelectOp::kMirror: {
      const double tol = mirror_tolerance();
      if (mode_ == SelectMode::kCageVertices) s.add(mirror_x(s, cage->polygons.positions, tol).mirrored.indices());
      else if (mode_ == SelectMode::kSkinVertices) s.add(mirror_x(s, scene_->skin_rest, tol).mirrored.indices());
      else if (mode_ == SelectMode::kJoints) s.add(mirror_x(s, scene_->joint_heads, tol).mirrored.indices());
      else if (mode_ == SelectMode::kCageFaces) {
        std::vector<glm::vec3> centroids = face_centroids(cage->polygons.positions);
        s.add(mirror_x(s, centroids, tol).mirrored.indices());
      }
      break;
    }
  }
}

std::vector<glm::vec3> Editor::face_centroids(std::span<const glm::vec3> positions) const {
  std::vector<glm::vec3> c;
  if (!scene_ || !scene_->doc().cage) return c;
  const PolyMesh& m = scene_->doc().cage->polygons;
  c.reserve(m.num_faces());
  for (size_t f = 0; f < m.num_faces(); ++f) {
    glm::dvec3 sum(0.0);
    for (uint32_t v : m.face(f)) sum += glm::dvec3(positions[v]);
    c.emplace_back(sum / double(std::max<size_t>(1, m.face(f).size())));
  }
  return c;
}

// Asked several times a frame (grid, tolerances, panels): the scene computes it once.
double Editor::scene_size() const { return scene_ ? scene_->skin_diagonal : 1.0; }
double Editor::mirror_tolerance() const { return mirror_tolerance_share_ * scene_size(); }
// Keys and assignments go to the vertex nearest each mirror image: a cage that is only nearly
// symmetric (a decimated one) needs about an edge length (core/rig/keyposes.h mirror_keypose_set).
double Editor::rig_mirror_tolerance() const {
  return scene_ && scene_->doc().cage ? std::max(mirror_tolerance(), mean_edge_length(scene_->doc().cage->polygons)) : mirror_tolerance();
}

// The cage vertices a move acts on: the selected vertices, or the corners of the selected faces.
IndexSet Editor::move_set() const {
  if (!scene_ || !scene_->doc().cage) return {};
  if (mode_ == SelectMode::kCageVertices) return selection_.cage_vertices;
  if (mode_ == SelectMode::kCageFaces) return face_vertices(selection_.cage_faces, scene_->doc().cage->polygons);
  return {};
}

// Soft-selection and mirror shares of the move set, measured on the rest cage (so a pose or an
// earlier sculpt does not change which vertices follow).
Result<MoveWeights> Editor::move_weights_now() const {
  const Cage& cage = *scene_->doc().cage;
  MirrorParams mirror = mirror_;
  mirror.tolerance = mirror_tolerance();
  return move_weights(move_set(), cage.polygons.positions, cage.polygons, soft_, mirror);
}

std::vector<std::pair<uint32_t, float>> Editor::sim_paint_weights() const {
  std::vector<std::pair<uint32_t, float>> out;
  if (!scene_ || !scene_->doc().cage || move_set().empty()) return out;
  auto w = move_weights_now();
  if (!w) return out;
  for (size_t i = 0; i < w->vertices.size(); ++i)
    out.emplace_back(w->vertices[i], std::max(w->direct[i], w->mirrored[i]));
  return out;
}

std::optional<glm::dvec3> Editor::selection_centre() const {
  if (auto p = patch_panel_.selected_position(*scene_)) return p;  // a parametric driver's control point
  IndexSet s = move_set();
  if (s.empty()) return std::nullopt;
  glm::dvec3 c(0.0);
  for (uint32_t v : s) c += glm::dvec3(scene_->cage_posed[v]);
  return c / double(s.size());
}

GizmoLayout Editor::gizmo() const {
  auto c = selection_centre();
  if (!c) return {};
  GizmoLayout g = gizmo_layout(camera_, Viewport{view_w_, view_h_}, drag_handle_ != GizmoHandle::kNone ? drag_centre_ + drag_total_ : *c);
  return g;
}

// One drag = one undo step: the document is rebuilt from the drag's start with the drag's total
// displacement each time, so nothing accumulates rounding and undo restores the start exactly.
void Editor::apply_move(const glm::dvec3& total) {
  drag_total_ = ImGui::GetIO().KeyCtrl ? snap_displacement(total, grid_spacing()) : total;
  scene_->live = drag_patch_  ? patch_panel_.moved(drag_start_, drag_total_)
                 : move_rest_ ? scene_->moved_rest(drag_start_, drag_weights_, drag_total_)
                              : scene_->moved(drag_start_, drag_weights_, drag_total_);
}

bool Editor::begin_move(GizmoHandle handle, glm::dvec2 from) {
  drag_patch_ = patch_panel_.selected_position(*scene_).has_value();  // moves a control point, not the cage
  if (!drag_patch_) {
    auto w = move_weights_now();
    if (!w.ok()) {
      log("error: " + w.error().message, true);
      return false;
    }
    drag_weights_ = std::move(w).value();
    if (!drag_weights_.unmatched.empty())
      log("warning: X-mirror: " + std::to_string(drag_weights_.unmatched.size()) + " selected vertices have no counterpart (first: vertex " +
          std::to_string(drag_weights_.unmatched.front()) + ")");
  }
  drag_start_ = scene_->doc();
  drag_total_ = glm::dvec3(0.0);
  drag_handle_ = handle;
  drag_from_ = from;
  drag_centre_ = selection_centre().value_or(glm::dvec3(0.0));
  scene_->history.begin(drag_start_);
  return true;
}

void Editor::end_move() {
  const bool changed = scene_->live.has_value();
  if (changed)
    scene_->history.commit(drag_patch_  ? "Move control point " + std::to_string(patch_panel_.selected())
                           : move_rest_ ? "Move rest cage vertices"
                                        : "Move cage vertices",
                           *scene_->live);
  else scene_->history.cancel();
  scene_->live.reset();
  drag_handle_ = GizmoHandle::kNone;
  if (changed && move_rest_) scene_->document_changed();  // re-attach, and register the reachable points again
}

double Editor::grid_spacing() const {
  return std::pow(10.0, std::floor(std::log10(scene_size() / 10.0)));
}

const TriangleBvh& Editor::skin_occluder() {
  if (!skin_bvh_built_) {
    skin_bvh_ = TriangleBvh(scene_->skin_posed(), scene_->skin_triangles());
    skin_bvh_built_ = true;
  } else {
    skin_bvh_.refit(scene_->skin_posed());
  }
  return skin_bvh_;
}

// Click: replace, shift adds, ctrl removes. In cage-vertex mode a click that misses every vertex
// may still pick a joint (the skeleton is drawn on top).
void Editor::click_select(const ImVec2& mouse, bool add, bool remove) {
  Viewport vp{view_w_, view_h_};
  glm::dvec2 px = to_view(mouse);
  std::optional<uint32_t> hit;
  if (patch_panel_.pick(*scene_, camera_, vp, px)) return;  // a parametric driver's control point, while its window is open
  if (!add && !remove) patch_panel_.deselect();
  IndexSet* set = &active_set();
  switch (mode_) {
    case SelectMode::kCageVertices:
      if (scene_->doc().cage && style_.show_cage) hit = pick_vertex(camera_, vp, px, scene_->cage_posed, 8.0);
      if (!hit && style_.show_skeleton && (hit = pick_joint(camera_, vp, px, scene_->joint_heads, 8.0))) set = &selection_.joints;
      break;
    case SelectMode::kCageFaces:
      if (scene_->doc().cage && style_.show_cage) {
        cage_picker_.refit(scene_->cage_posed);
        if (auto f = cage_picker_.pick(camera_.ray(px.x, px.y, vp.width, vp.height))) hit = f->face;
      }
      break;
    case SelectMode::kSkinVertices:
      if (style_.show_skin) hit = pick_vertex(camera_, vp, px, scene_->skin_posed(), 8.0, style_.xray ? nullptr : &skin_occluder());
      break;
    case SelectMode::kJoints:
      if (style_.show_skeleton) hit = pick_joint(camera_, vp, px, scene_->joint_heads, 8.0);
      break;
  }
  if (hit) {
    uint32_t idx[1] = {*hit};
    if (remove) set->remove(idx);
    else if (add) set->add(idx);
    else {
      if (set != &active_set()) active_set().clear();
      set->set(idx);
    }
    return;
  }
  if (!add && !remove) {
    active_set().clear();
    if (mode_ == SelectMode::kCageVertices) selection_.joints.clear();
  }
}

void Editor::box_select_in_mode(const ImVec2& a, const ImVec2& b, bool add, bool remove) {
  Viewport vp{view_w_, view_h_};
  std::vector<uint32_t> hits;
  switch (mode_) {
    case SelectMode::kCageVertices:
      if (scene_->doc().cage) hits = box_select(camera_, vp, to_view(a), to_view(b), scene_->cage_posed);
      break;
    case SelectMode::kCageFaces:
      if (scene_->doc().cage) hits = box_select(camera_, vp, to_view(a), to_view(b), face_centroids(scene_->cage_posed));
      break;
    case SelectMode::kSkinVertices:
      hits = box_select(camera_, vp, to_view(a), to_view(b), scene_->skin_posed(), style_.xray ? nullptr : &skin_occluder());
      break;
    case SelectMode::kJoints:
      hits = box_select(camera_, vp, to_view(a), to_view(b), scene_->joint_heads);
      break;
  }
  IndexSet& s = active_set();
  if (remove) s.remove(hits);
  else if (add) s.add(hits);
  else s.set(hits);
}

void Editor::handle_input() {
  ImGuiIO& io = ImGui::GetIO();
  const bool over_view = in_view(io.MousePos) && !io.WantCaptureMouse;
  if (scene_ && painting_) {  // a set-edit brush stroke in progress
    if (!io.MouseDown[0]) {
      sets_panel_.end_stroke(*scene_);
      painting_ = false;
    } else if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
      paint_dab(io.MousePos);
    }
    return;
  }
  if (scene_ && over_view && !io.KeyAlt && ImGui::IsMouseClicked(0) && sets_panel_.painting() && mode_ == SelectMode::kSkinVertices) {
    sets_panel_.begin_stroke(*scene_);
    painting_ = true;
    paint_dab(io.MousePos);
    return;
  }
  if (scene_ && rot_handle_ != RotateHandle::kNone) {  // a joint rotation in progress
    if (!io.MouseDown[0]) {
      rot_handle_ = RotateHandle::kNone;
    } else if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
      auto a = rotate_gizmo_angle(camera_, Viewport{view_w_, view_h_}, rot_layout_, rot_handle_, rot_from_, to_view(io.MousePos));
      if (a) apply_rotate(*a);
    }
    return;
  }
  if (scene_ && drag_handle_ != GizmoHandle::kNone) {  // a gizmo drag in progress
    if (!io.MouseDown[0]) {
      end_move();
    } else if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
      auto d = gizmo_drag(camera_, Viewport{view_w_, view_h_}, drag_handle_, drag_centre_, drag_from_, to_view(io.MousePos));
      if (d) apply_move(*d);
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
      const GizmoHandle hit = gizmo_hit(gizmo(), to_view(io.MousePos));
      const RotateHandle ring = rotate_gizmo_hit(rotate_gizmo(), to_view(io.MousePos));
      if (ring != RotateHandle::kNone) {
        begin_rotate(ring, to_view(io.MousePos));
      } else if (hit != GizmoHandle::kNone) {
        begin_move(hit, to_view(io.MousePos));
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
    if (!scene_) return;
    if (std::abs(m.x - box_start_.x) < 4 && std::abs(m.y - box_start_.y) < 4) click_select(m, add, remove);
    else box_select_in_mode(box_start_, m, add, remove);
  }
  if (!io.WantCaptureKeyboard && scene_) {
    const bool ctrl = io.KeyCtrl, shift = io.KeyShift;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Z)) shift ? redo() : undo();
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Y)) redo();
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_S)) request_save();
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_O)) open_open_popup_ = true;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Q)) quit_requested_ = true;
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_A)) edit_selection(SelectOp::kAll);
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_I)) edit_selection(SelectOp::kInvert);
    if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_M)) edit_selection(SelectOp::kMirror);
    if (!ctrl && (ImGui::IsKeyPressed(GLFW_KEY_KP_ADD) || ImGui::IsKeyPressed(GLFW_KEY_PERIOD))) edit_selection(SelectOp::kGrow);
    if (!ctrl && (ImGui::IsKeyPressed(GLFW_KEY_KP_SUBTRACT) || ImGui::IsKeyPressed(GLFW_KEY_COMMA))) edit_selection(SelectOp::kShrink);
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) edit_selection(SelectOp::kNone);
    for (int k = 0; k < 4; ++k)
      if (ImGui::IsKeyPressed(GLFW_KEY_F5 + k)) mode_ = static_cast<SelectMode>(k);
    if (!ctrl && ImGui::IsKeyPressed(GLFW_KEY_B)) soft_.enabled = !soft_.enabled;
    if (ImGui::IsKeyPressed(GLFW_KEY_LEFT_BRACKET)) soft_.radius = std::max(soft_.radius / 1.25, 1e-4 * scene_size());
    if (ImGui::IsKeyPressed(GLFW_KEY_RIGHT_BRACKET)) soft_.radius = std::min(soft_.radius * 1.25, 2.0 * scene_size());
    if (shift && !ctrl && ImGui::IsKeyPressed(GLFW_KEY_X)) mirror_.enabled = !mirror_.enabled;
    if (!ctrl && ImGui::IsKeyPressed(GLFW_KEY_F)) frame_all();
    if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) scene_->player.playing() ? scene_->player.pause() : scene_->player.play();
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_1) || ImGui::IsKeyPressed(GLFW_KEY_1)) camera_.set_preset(ctrl ? ViewPreset::kBack : ViewPreset::kFront);
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_3) || ImGui::IsKeyPressed(GLFW_KEY_3)) camera_.set_preset(ctrl ? ViewPreset::kLeft : ViewPreset::kRight);
    if (ImGui::IsKeyPressed(GLFW_KEY_KP_7) || ImGui::IsKeyPressed(GLFW_KEY_7)) camera_.set_preset(ctrl ? ViewPreset::kBottom : ViewPreset::kTop);
    if (ImGui::IsKeyPressed(GLFW_KEY_L) && !ctrl) scene_->show_file_skinning = !scene_->show_file_skinning;
    if (ImGui::IsKeyPressed(GLFW_KEY_C) && !ctrl) color_by_bone_ = !color_by_bone_;
    if (ImGui::IsKeyPressed(GLFW_KEY_K) && !ctrl) rig_panel_.visible() = !rig_panel_.visible();
    if (ImGui::IsKeyPressed(GLFW_KEY_J) && !ctrl) sets_panel_.visible() = !sets_panel_.visible();
    if (ImGui::IsKeyPressed(GLFW_KEY_W) && !ctrl) style_.wireframe = !style_.wireframe;
    if (ImGui::IsKeyPressed(GLFW_KEY_X) && io.KeyAlt) style_.xray = !style_.xray;
    if (ImGui::IsKeyPressed(GLFW_KEY_F1)) show_help_ = !show_help_;
  }
}

// One brush dab where the mouse ray meets the skin.
void Editor::paint_dab(const ImVec2& mouse) {
  const glm::dvec2 px = to_view(mouse);
  const Ray ray = camera_.ray(px.x, px.y, view_w_, view_h_);
  if (auto hit = pick_triangle(ray, skin_occluder())) {
    const glm::dvec3 at = ray.at(hit->t);
    if (sets_panel_.screen_radius()) {  // pixels -> scene units at the hit's depth
      const ScreenPoint sp = camera_.project(at, view_w_, view_h_);
      const double depth = camera_.mode() == ProjectionMode::kPerspective ? sp.view_depth / camera_.distance() : 1.0;
      sets_panel_.set_brush_radius(sets_panel_.radius_pixels() * camera_.world_per_pixel(view_h_) * depth);
    }
    sets_panel_.dab(*scene_, selection_, hit->triangle, at, hooks_);
  }
}

// The joint the rotation gizmo acts on: the one selected joint in joint mode.
int Editor::posed_joint() const {
  if (!scene_ || mode_ != SelectMode::kJoints || selection_.joints.size() != 1) return -1;
  const uint32_t j = selection_.joints.indices()[0];
  return j < scene_->joint_globals.size() ? static_cast<int>(j) : -1;
}

RotateGizmoLayout Editor::rotate_gizmo() const {
  const int j = posed_joint();
  if (j < 0) return {};
  if (rot_handle_ != RotateHandle::kNone) return rot_layout_;
  const glm::mat4& g = scene_->joint_globals[static_cast<size_t>(j)];
  const glm::dmat3 axes{glm::dvec3(g[0]), glm::dvec3(g[1]), glm::dvec3(g[2])};
  return rotate_gizmo_layout(camera_, Viewport{view_w_, view_h_}, glm::dvec3(g[3]), axes);
}

void Editor::set_override(uint32_t node, const glm::quat& q) {
  auto& o = scene_->pose_override;
  if (o.size() < scene_->joint_globals.size()) o.resize(scene_->joint_globals.size(), glm::quat(1, 0, 0, 0));
  if (node < o.size()) o[node] = glm::normalize(q);
}

void Editor::begin_rotate(RotateHandle handle, glm::dvec2 from) {
  const int j = posed_joint();
  if (j < 0) return;
  rot_layout_ = rotate_gizmo();
  rot_handle_ = handle;
  rot_from_ = from;
  rot_angle_ = 0.0;
  const auto& o = scene_->pose_override;
  rot_start_ = static_cast<size_t>(j) < o.size() ? o[static_cast<size_t>(j)] : glm::quat(1, 0, 0, 0);
  // local = clip * override and global = parent * local: turning the joint by angle a about a world
  // axis w is override' = override * angleAxis(a, inverse(global rotation) * w)
  const glm::mat4& g = scene_->joint_globals[static_cast<size_t>(j)];
  const glm::mat3 rot(glm::normalize(glm::vec3(g[0])), glm::normalize(glm::vec3(g[1])), glm::normalize(glm::vec3(g[2])));
  const glm::vec3 w(rotate_handle_axis(camera_, rot_layout_, handle));
  rot_local_axis_ = glm::normalize(glm::transpose(rot) * w);
}

void Editor::apply_rotate(double angle) {
  const int j = posed_joint();
  if (j < 0) return;
  if (ImGui::GetIO().KeyCtrl) angle = snap_angle(angle, glm::radians(5.0));
  rot_angle_ = angle;
  set_override(static_cast<uint32_t>(j), rot_start_ * glm::angleAxis(static_cast<float>(angle), rot_local_axis_));
}

void Editor::draw_gizmo() {
  ImDrawList* dl = ImGui::GetForegroundDrawList();
  if (box_selecting_) {
    ImVec2 m = ImGui::GetIO().MousePos;
    dl->AddRectFilled(box_start_, m, IM_COL32(255, 160, 40, 40));
    dl->AddRect(box_start_, m, IM_COL32(255, 160, 40, 200));
  }
  if (!scene_) return;
  if (scene_->doc().cage) {  // a selected skin point's member faces, labelled with their weights
    const PolyMesh& m = scene_->doc().cage->polygons;
    for (auto [f, w] : sets_panel_.member_face_weights(*scene_, selection_)) {
      if (f >= m.num_faces()) continue;
      glm::dvec3 c(0.0);
      for (uint32_t v : m.face(f)) c += glm::dvec3(scene_->cage_posed[v]);
      const ScreenPoint sp = camera_.project(c / double(m.face(f).size()), view_w_, view_h_);
      if (!sp.in_clip_range) continue;
      char buf[16];
      std::snprintf(buf, sizeof buf, "%.2f", w);
      const ImVec2 at(view_x_ + static_cast<float>(sp.pixel.x) - 12, view_y_ + static_cast<float>(sp.pixel.y) - 7);
      dl->AddRectFilled(ImVec2(at.x - 2, at.y - 1), ImVec2(at.x + 30, at.y + 14), IM_COL32(20, 20, 20, 170), 3.0f);
      dl->AddText(at, IM_COL32(255, 220, 120, 255), buf);
    }
  }
  if (const RotateGizmoLayout r = rotate_gizmo(); r.visible) {
    const ImVec2 o(view_x_, view_y_);
    auto at = [&](glm::dvec2 p) { return ImVec2(o.x + static_cast<float>(p.x), o.y + static_cast<float>(p.y)); };
    const ImU32 colours[3] = {IM_COL32(235, 70, 70, 255), IM_COL32(90, 220, 90, 255), IM_COL32(80, 130, 255, 255)};
    for (int k = 0; k < 3; ++k) {
      const bool on = static_cast<int>(rot_handle_) == k;
      const size_t n = r.rings[k].size();
      for (size_t i = 0; i < n; ++i) {
        const size_t i2 = (i + 1) % n;
        const bool front = r.front[k][i] && r.front[k][i2];
        const ImU32 c = on ? IM_COL32(255, 230, 80, 255) : (front ? colours[k] : (colours[k] & 0x00FFFFFF) | 0x50000000);
        dl->AddLine(at(r.rings[k][i]), at(r.rings[k][i2]), c, front ? 2.5f : 1.0f);
      }
    }
    for (size_t i = 0; i < r.view_ring.size(); ++i)
      dl->AddLine(at(r.view_ring[i]), at(r.view_ring[(i + 1) % r.view_ring.size()]),
                  rot_handle_ == RotateHandle::kView ? IM_COL32(255, 230, 80, 255) : IM_COL32(220, 220, 220, 160), 1.5f);
    if (rot_handle_ != RotateHandle::kNone) {
      char buf[48];
      std::snprintf(buf, sizeof buf, "%+.1f deg", glm::degrees(rot_angle_));
      dl->AddText(ImVec2(at(r.centre).x + 14, at(r.centre).y + 12), IM_COL32(255, 255, 255, 230), buf);
    }
    return;
  }
  const GizmoLayout g = gizmo();
  if (!g.visible) return;
  const ImU32 active = IM_COL32(255, 230, 80, 255);
  const ImU32 colours[3] = {IM_COL32(235, 70, 70, 255), IM_COL32(90, 220, 90, 255), IM_COL32(80, 130, 255, 255)};
  const ImVec2 o(view_x_, view_y_);
  auto at = [&](glm::dvec2 p) { return ImVec2(o.x + static_cast<float>(p.x), o.y + static_cast<float>(p.y)); };
  for (int p = 0; p < 3; ++p) {  // plane squares, coloured by their normal axis
    const bool on = static_cast<int>(drag_handle_) == 3 + p;
    ImVec2 q[4];
    for (int k = 0; k < 4; ++k) q[k] = at(g.plane[p][k]);
    dl->AddConvexPolyFilled(q, 4, on ? IM_COL32(255, 230, 80, 150) : (colours[p] & 0x00FFFFFF) | 0x60000000);
    dl->AddPolyline(q, 4, on ? active : colours[p], ImDrawFlags_Closed, 1.5f);
  }
  for (int a = 0; a < 3; ++a) {
    const bool on = static_cast<int>(drag_handle_) == a;
    dl->AddLine(at(g.centre), at(g.axis_end[a]), on ? active : colours[a], 3.0f);
    dl->AddCircleFilled(at(g.axis_end[a]), 5.0f, on ? active : colours[a]);
  }
  const ImVec2 c = at(g.centre);
  dl->AddRect(ImVec2(c.x - 6, c.y - 6), ImVec2(c.x + 6, c.y + 6), drag_handle_ == GizmoHandle::kScreen ? active : IM_COL32(230, 230, 230, 255), 0, 0, 2.0f);
  if (drag_handle_ != GizmoHandle::kNone) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%+.4f %+.4f %+.4f", drag_total_.x, drag_total_.y, drag_total_.z);
    dl->AddText(ImVec2(c.x + 12, c.y + 10), IM_COL32(255, 255, 255, 230), buf);
  }
  if (soft_.enabled) {  // the soft radius as a circle at the centre's depth
    const double px = soft_.radius / std::max(g.world_length / kGizmoAxisPixels, 1e-12);
    dl->AddCircle(c, static_cast<float>(px), IM_COL32(255, 240, 90, 110), 64, 1.0f);
  }
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
  SaveOptions options;  // the binding goes beside the project when it is cached and up to date
  if (scene_->doc().cache_binding && scene_->binding && !scene_->job && !scene_->needs_rebind() &&
      binding_fits(*scene_->binding, scene_->doc()))
    options.binding = scene_->binding.get();
  auto st = save_project(path, scene_->doc(), options);
  if (!st.ok()) {
    error_modal_ = st.error().message;
    log("error: " + st.error().message, true);
    return false;
  }
  scene_->history.mark_saved(path);
  if (autosave_) autosave_->discard();
  recovered_ = false;
  log("saved " + path + (options.binding ? " (and its binding, " + binding_cache_path(path) + ")" : ""));
  if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  return true;
}

// Opens a project (or a recovery file); a missing character asks to be located, a recovery file
// becomes the unsaved work of the project it names. The current document stays on any error.
bool Editor::open_project(const std::string& path, const std::string& character_override) {
  ProjectOpen opened;
  auto s = load_project_scene(path, opened, character_override);
  for (const auto& w : opened.warnings) log("warning: " + w);
  if (!s.ok()) {
    log("error: " + s.error().message, true);
    if (!opened.missing_character.empty()) dialogs_.character_missing(path, opened.missing_character);
    else error_modal_ = s.error().message;
    return false;
  }
  for (const auto& n : opened.notes) log(n);
  set_scene(std::move(s).value());
  if (opened.recovery) {  // the work belongs to its project, not to the recovery file; not saved
    std::error_code ec;
    const int64_t when = modified_seconds(path).value_or(0);
    scene_->history.mark_saved(opened.recovery->project);
    scene_->history.mark_unsaved();
    recovered_ = true;
    if (autosave_ && autosave_->enabled()) {  // protected again at once, under this editor's name
      if (auto w = autosave_->write(scene_->doc()); !w) log("error: autosave failed: " + w.error().message, true);
    }
    std::filesystem::remove(path, ec);
    log("recovered the unsaved work" + (opened.recovery->project.empty() ? std::string(" (untitled)") : " of " + opened.recovery->project) +
        (when ? " from " + format_local_time(when) : std::string()) + "; save to keep it");
    return true;
  }
  if (!character_override.empty()) {
    scene_->history.mark_unsaved();
    log("located the character at " + character_override + "; save the project to remember the new place");
  }
  log("opened " + path);
  if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  return true;
}

bool Editor::open_path(const std::string& path) {
  if (has_extension(path, ".cagewrap")) return open_project(path);
  auto s = load_scene(path, "");
  if (!s.ok()) {  // the current document stays as it is
    error_modal_ = s.error().message;
    log("error: " + s.error().message, true);
    return false;
  }
  log("opened " + path);
  set_scene(std::move(s).value());
  if (auto e = files_.add_recent(path); !e.empty()) log("warning: " + e);
  return true;
}

void Editor::draw_menu() {
  if (!ImGui::BeginMainMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("New from character...")) browse(FilePurpose::kNewFromCharacter);
    if (ImGui::MenuItem("New on the demo character")) guard_unsaved([this] {
        const std::string demo = demo_character_path();
        if (!demo.empty()) open_path(demo);
        else log("error: the demo character is not installed beside the program", true);
      });
    if (ImGui::MenuItem("Open...", "Ctrl+O")) open_open_popup_ = true;
    if (ImGui::BeginMenu("Open Recent")) {
      std::string message;
      auto recent = files_.draw_recent_menu(message);
      if (!message.empty()) log(message);
      if (recent) {
        const std::string path = *recent;
        if (!std::filesystem::exists(path)) log(files_.forget_recent(path));
        else guard_unsaved([this, path] { open_path(path); });
      }
      ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Save", "Ctrl+S", false, scene_ != nullptr)) request_save();
    if (ImGui::MenuItem("Save as...", nullptr, false, scene_ != nullptr)) open_save_popup_ = true;
    if (scene_) act_on(dialogs_.menu_items(*scene_, hooks_));
    if (ImGui::BeginMenu("Autosave every")) {  // the recovery file of unsaved work (app/workspace/autosave.h)
      const std::pair<const char*, double> choices[] = {{"1 minute", 60}, {"3 minutes", 180}, {"10 minutes", 600}, {"never", 0}};
      for (const auto& [label, seconds] : choices)
        if (ImGui::MenuItem(label, nullptr, autosave_->interval_seconds() == seconds)) {
          autosave_->set_interval_seconds(seconds);
          if (auto e = files_.set_autosave_seconds(seconds); !e.empty()) log("warning: " + e);
          log(seconds > 0 ? std::string("autosave every ") + label : std::string("autosave off"));
        }
      ImGui::EndMenu();
    }
    ImGui::Separator();
    if (ImGui::MenuItem("Import cage...", nullptr, false, scene_ != nullptr)) browse(FilePurpose::kImportCage);
    if (ImGui::MenuItem("Export...", nullptr, false, scene_ != nullptr)) export_panel_.open(*scene_);
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
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Select")) {
    const char* keys[] = {"F5", "F6", "F7", "F8"};
    for (int k = 0; k < 4; ++k)
      if (ImGui::MenuItem(mode_name(static_cast<SelectMode>(k)), keys[k], mode_ == static_cast<SelectMode>(k)))
        mode_ = static_cast<SelectMode>(k);
    ImGui::Separator();
    const bool any = active_count() > 0;
    const bool meshy = mode_ != SelectMode::kJoints;
    if (ImGui::MenuItem("All", "Ctrl+A", false, any)) edit_selection(SelectOp::kAll);
    if (ImGui::MenuItem("None", "Esc", false, any)) edit_selection(SelectOp::kNone);
    if (ImGui::MenuItem("Invert", "Ctrl+I", false, any)) edit_selection(SelectOp::kInvert);
    if (ImGui::MenuItem("Grow", "Num+ or .", false, any && meshy)) edit_selection(SelectOp::kGrow);
    if (ImGui::MenuItem("Shrink", "Num- or ,", false, any && meshy)) edit_selection(SelectOp::kShrink);
    if (ImGui::MenuItem("Add mirror (X)", "Ctrl+M", false, any)) edit_selection(SelectOp::kMirror);
    ImGui::Separator();
    ImGui::MenuItem("Soft selection", "B", &soft_.enabled);
    ImGui::MenuItem("X-mirror editing", "Shift+X", &mirror_.enabled);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Cage", scene_ != nullptr)) {
    cage_tools_.menu_items(*scene_, selection_, hooks_);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Rig", scene_ != nullptr)) {
    ImGui::MenuItem("Attachment and keyposes...", "K", &rig_panel_.visible());
    ImGui::MenuItem("Contributing sets...", "J", &sets_panel_.visible());
    ImGui::MenuItem("Simulation...", nullptr, &sim_panel_.visible());
    ImGui::MenuItem("Parametric driver...", nullptr, &patch_panel_.visible());
    if (ImGui::MenuItem("Reset pose")) scene_->pose_override.clear();
    ImGui::MenuItem("Show the file's own skinning", "L", &scene_->show_file_skinning);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("View")) {
    ImGui::MenuItem("Skin", nullptr, &style_.show_skin);
    ImGui::MenuItem("Cage", nullptr, &style_.show_cage);
    ImGui::MenuItem("Skeleton", nullptr, &style_.show_skeleton);
    ImGui::MenuItem("Grid", nullptr, &style_.show_grid);
    ImGui::Separator();
    ImGui::MenuItem("Cage coloured by bone", "C", &color_by_bone_);
    ImGui::MenuItem("Wireframe", "W", &style_.wireframe);
    ImGui::MenuItem("X-ray", "Alt+X", &style_.xray);
    skin_display_.menu_item();
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
        if (ImGui::Selectable(ch.skeleton.node(i).name.c_str(), selection_.joints.contains(static_cast<uint32_t>(i)))) {
          uint32_t idx[1] = {static_cast<uint32_t>(i)};
          if (ImGui::GetIO().KeyCtrl) selection_.joints.toggle(idx);
          else selection_.joints.set(idx);
        }
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
  draw_move_tool();
  draw_pose_panel();
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
    ImGui::Checkbox("separate unrelated parts", &p.separate);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("An element drives a point only when the bones they follow are the same or neighbours\n"
                        "(within the steps below): the right thigh's cage does not pull the left thigh");
    int steps = static_cast<int>(p.separation_steps);
    ImGui::BeginDisabled(!p.separate);
    if (ImGui::SliderInt("separation steps", &steps, 0, 4)) p.separation_steps = static_cast<uint32_t>(steps);
    ImGui::EndDisabled();
    if (scene_->job) {
      ImGui::ProgressBar(static_cast<float>(scene_->job->progress()), ImVec2(-70, 0), "binding");
      ImGui::SameLine();
      if (ImGui::Button("Cancel")) scene_->job->cancel();
    } else {
      if (scene_->needs_rebind()) {
        ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.2f, 1), "Parameters changed: rebind to apply");
      }
      if (ImGui::Button(scene_->binding ? "Rebind" : "Bind", ImVec2(-1, 0))) scene_->rebind();
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
      if (b.separation_applied) ImGui::Text("separation kept %zu element-point pairs apart", static_cast<size_t>(b.total_separated));
      ImGui::Text("bound in %.2f s", b.seconds);
      fidelity_panel_.draw(*scene_, hooks_);
    }
  } else if (scene_) {
    ImGui::TextWrapped("No cage: the skin shows the file's own linear blend skinning. Open with --cage to bind a cage.");
  }
  ImGui::End();
}

// Selection mode buttons along the top of the 3-D view.
void Editor::draw_toolbar() {
  ImGui::SetNextWindowPos(ImVec2(view_x_ + view_w_ - 10, view_y_ + 10), ImGuiCond_Always, ImVec2(1, 0));
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("toolbar", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                                       ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
  const char* labels[] = {"Vertices", "Faces", "Skin", "Joints"};
  const char* tips[] = {"Select cage vertices (F5)", "Select cage faces (F6)", "Select skin vertices (F7)", "Select joints (F8)"};
  for (int k = 0; k < 4; ++k) {
    if (k) ImGui::SameLine();
    const bool on = mode_ == static_cast<SelectMode>(k);
    if (on) ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.85f, 0.5f, 0.1f, 1));
    if (ImGui::Button(labels[k])) mode_ = static_cast<SelectMode>(k);
    if (on) ImGui::PopStyleColor();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tips[k]);
  }
  ImGui::SameLine();
  ImGui::TextDisabled("|");
  ImGui::SameLine();
  ImGui::Checkbox("Soft", &soft_.enabled);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Soft selection (B); radius with [ and ]");
  ImGui::SameLine();
  ImGui::Checkbox("Mirror X", &mirror_.enabled);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("X-mirror editing (Shift+X)");
  ImGui::SameLine();
  ImGui::Checkbox("Edit rest", &move_rest_);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Moves edit the reference (rest) cage: the skin stays, and only the skin points\n"
                      "near the moved vertices are registered again");
  if (scene_) {
    const IndexSet& s = active_set();
    ImGui::TextDisabled("%zu %s selected", s.size(), mode_name(mode_));
  }
  ImGui::End();
}

// Posing: the selected joint's rotation on top of the clip as angles, reset buttons, comparison.
void Editor::draw_pose_panel() {
  if (!scene_) return;
  if (!ImGui::CollapsingHeader("Pose", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const Character& ch = *scene_->doc().character;
  if (selection_.joints.size() == 1 && selection_.joints.indices()[0] < ch.skeleton.size()) {
    const uint32_t j = selection_.joints.indices()[0];
    ImGui::Text("%s", ch.skeleton.node(j).name.c_str());
    const auto& o = scene_->pose_override;
    const glm::quat q = j < o.size() ? o[j] : glm::quat(1, 0, 0, 0);
    glm::vec3 euler = glm::degrees(glm::eulerAngles(q));
    if (ImGui::DragFloat3("rotate (deg)", &euler.x, 0.5f, -180.0f, 180.0f, "%.1f")) set_override(j, glm::quat(glm::radians(euler)));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("About the joint's local X, Y, Z, on top of the clip");
    if (ImGui::Button("Reset joint")) set_override(j, glm::quat(1, 0, 0, 0));
    ImGui::SameLine();
  } else {
    ImGui::TextDisabled("select one joint (F8) to pose it with the rings or here");
  }
  if (ImGui::Button("Reset pose")) scene_->pose_override.clear();
  ImGui::Checkbox("show the file's own skinning (L)", &scene_->show_file_skinning);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Compare the cage deformation with the character's linear blend skinning");
  ImGui::Spacing();
}

// Settings of the move tool: soft selection and X-mirror.
void Editor::draw_move_tool() {
  if (!scene_ || !scene_->doc().cage) return;
  if (!ImGui::CollapsingHeader("Move tool", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::Checkbox("soft selection (B)", &soft_.enabled);
  ImGui::BeginDisabled(!soft_.enabled);
  float r = static_cast<float>(soft_.radius);
  const float size = static_cast<float>(scene_size());
  if (ImGui::SliderFloat("radius", &r, 1e-3f * size, size, "%.4f", ImGuiSliderFlags_Logarithmic)) soft_.radius = r;
  int falloff = static_cast<int>(soft_.falloff);
  const char* falloffs[] = {"smooth", "linear", "sharp", "constant"};
  if (ImGui::Combo("falloff", &falloff, falloffs, 4)) soft_.falloff = static_cast<Falloff>(falloff);
  int dist = static_cast<int>(soft_.distance);
  const char* dists[] = {"volume (straight line)", "surface (along edges)"};
  if (ImGui::Combo("distance", &dist, dists, 2)) soft_.distance = static_cast<FalloffDistance>(dist);
  ImGui::EndDisabled();
  ImGui::Checkbox("X-mirror editing (Shift+X)", &mirror_.enabled);
  ImGui::BeginDisabled(!mirror_.enabled);
  float tol = static_cast<float>(mirror_tolerance_share_ * 100.0);
  if (ImGui::SliderFloat("tolerance % of size", &tol, 0.01f, 2.0f, "%.2f", ImGuiSliderFlags_Logarithmic))
    mirror_tolerance_share_ = tol / 100.0;
  ImGui::EndDisabled();
  ImGui::TextDisabled("snap step (Ctrl while dragging): %g", grid_spacing());
  ImGui::Spacing();
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
  ImGui::PushTextWrapPos(0.0f);  // long paths wrap instead of running off the panel
  for (const auto& l : log_) {
    ImVec4 c = l.error ? ImVec4(1, 0.4f, 0.35f, 1) : (l.text.rfind("warning", 0) == 0 ? ImVec4(1, 0.8f, 0.3f, 1) : ImVec4(0.85f, 0.85f, 0.85f, 1));
    if (l.repeats > 1) ImGui::TextColored(c, "%s (and %d similar)", l.text.c_str(), l.repeats - 1);
    else ImGui::TextColored(c, "%s", l.text.c_str());
  }
  ImGui::PopTextWrapPos();
  if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);
  ImGui::End();
  if (!error_modal_.empty()) {
    ImGui::OpenPopup("Error");
    if (ImGui::BeginPopupModal("Error", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
      ImGui::TextUnformatted(error_modal_.c_str());
      ImGui::TextDisabled("The current document is unchanged.");
      if (ImGui::Button("OK", ImVec2(120, 0)) || std::exchange(script_error_ok_, false)) {
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
  if (!scene_) ImGui::Text("%.0f fps", fps_);
  if (scene_) {
    ImGui::Text("skin %zu vertices", scene_->skin_rest.size());
    if (scene_->doc().cage) ImGui::Text("cage %zu vertices, %zu faces", scene_->doc().cage->num_vertices(), scene_->doc().cage->polygons.num_faces());
    skin_display_.draw_stats(*scene_);
  }
  (void)io;
  ImGui::End();
}

void Editor::draw_help() {
  if (!show_help_) return;
  ImGui::Begin("Shortcuts", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
  const char* rows[][2] = {{"Alt+LMB drag / RMB drag", "orbit"},
                           {"MMB drag (Alt optional)", "pan"},
                           {"wheel / Alt+RMB drag", "zoom"},
                           {"F", "frame everything"},
                           {"1 / 3 / 7 (numpad too)", "front / side / top view (Ctrl: opposite)"},
                           {"F5 F6 F7 F8", "select cage vertices / cage faces / skin vertices / joints"},
                           {"click, drag a box", "select (Shift adds, Ctrl removes)"},
                           {"Ctrl+A / Esc / Ctrl+I", "select all / none / invert"},
                           {"Num+ Num- (or . ,)", "grow / shrink selection"},
                           {"Ctrl+M", "add the mirror (X) of the selection"},
                           {"gizmo: arrow / square / centre", "move along an axis / in a plane / in the view"},
                           {"Ctrl while dragging", "snap to the grid"},
                           {"B, [ ]", "soft selection on/off, smaller/larger radius"},
                           {"Shift+X", "X-mirror editing on/off"},
                           {"Ctrl+Z / Ctrl+Shift+Z, Ctrl+Y", "undo / redo"},
                           {"Ctrl+O / Ctrl+S / Ctrl+Q", "open / save / quit"},
                           {"F12", "screenshot"},                           {"L", "show the file's own skinning"},                   {"C", "colour the cage by bone (joint mode: the selected joints' vertices light up)"},
                           {"Space", "play / pause"},
                           {"W", "wireframe"},
                           {"Alt+X", "X-ray"},
                           {"F1", "this window"}};
  for (auto& r : rows) {
    ImGui::TextUnformatted(r[0]);
    ImGui::SameLine(250);
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
// browser_confirm | browser_cancel | toggle wireframe|xray|skin|cage|skeleton|grid|gpu_deform
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
    bool* flags[] = {&style_.wireframe, &style_.xray, &style_.show_skin, &style_.show_cage, &style_.show_skeleton, &style_.show_grid,
                     &skin_display_.use_gpu()};
    const char* names[] = {"wireframe", "xray", "skin", "cage", "skeleton", "grid", "gpu_deform"};
    auto it = std::find(std::begin(names), std::end(names), arg);
    if (it == std::end(names)) return false;
    bool* f = flags[it - std::begin(names)];
    *f = !*f;
  } else return false;
  return true;
}

void Editor::act_on(const EditorFiles::Choice& choice) {
  switch (choice.purpose) {
    case FilePurpose::kOpen:
    case FilePurpose::kNewFromCharacter: {
      const std::string path = choice.path;
      guard_unsaved([this, path] { open_path(path); });
      break;
    }
    case FilePurpose::kImportCage: import_cage(choice.path); break;
    case FilePurpose::kSaveProject:
      if (scene_ && save_project_to(choice.path) && after_save_) after_save_();
      after_save_ = nullptr;
      break;
    case FilePurpose::kScreenshot:
      pending_screenshot_ = choice.path;
      pending_screenshot_frames_ = 2;  // the dialog leaves the picture first
      break;
    case FilePurpose::kExportGlb:
    case FilePurpose::kExportObj:
    case FilePurpose::kExportJson: export_panel_.set_output(choice.path); break;
    case FilePurpose::kLocateCharacter: {
      const std::string project = dialogs_.locating_project();
      dialogs_.located();
      if (!project.empty()) open_project(project, choice.path);
      break;
    }
    case FilePurpose::kSaveCharacter:
      if (scene_) dialogs_.unembed_to(*scene_, choice.path, hooks_);
      break;
  }
}

void Editor::act_on(const ProjectDialogs::Request& request) {
  using Kind = ProjectDialogs::Request::Kind;
  switch (request.kind) {
    case Kind::kNone: break;
    case Kind::kLocate: files_.browser().open(FilePurpose::kLocateCharacter, request.directory); break;
    case Kind::kSaveCharacter: files_.browser().open(FilePurpose::kSaveCharacter, request.directory, request.character); break;
    case Kind::kRecover: {
      const std::string path = request.recovery.path;
      guard_unsaved([this, path] { open_project(path); });
      break;
    }
    case Kind::kDiscardRecovery: log("discarded the recovery file " + request.recovery.path); break;
  }
}

bool Editor::import_cage(const std::string& path) {
  return scene_ && cage_tools_.import_cage(*scene_, path, hooks_);
}

void Editor::draw_file_popups() {
  if (!ImGui::GetIO().WantCaptureKeyboard && ImGui::IsKeyPressed(GLFW_KEY_F12)) browse(FilePurpose::kScreenshot);
  if (open_save_popup_ && scene_) browse(FilePurpose::kSaveProject);
  if (open_open_popup_) browse(FilePurpose::kOpen);
  if (cage_tools_.take_import_request()) browse(FilePurpose::kImportCage);
  if (auto b = export_panel_.take_browse_request()) files_.browse(b->purpose, b->near_path, b->file_name);
  open_save_popup_ = open_open_popup_ = false;
  if (auto choice = files_.draw_browser()) act_on(*choice);
  else if (!files_.browsing()) after_save_ = nullptr;  // the Save as was cancelled
  if (quit_requested_) {
    quit_requested_ = false;
    guard_unsaved([this] { close_ = true; });
  }
  if (open_prompt_) ImGui::OpenPopup("Save changes?");
  open_prompt_ = false;
  if (ImGui::BeginPopupModal("Save changes?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextUnformatted("The project has unsaved changes.");
    const std::string answer = std::exchange(script_answer_, std::string());
    if (ImGui::Button("Save", ImVec2(100, 0)) || answer == "save") {
      auto action = std::move(pending_action_);
      pending_action_ = nullptr;
      if (scene_->doc().project_path.empty()) {
        open_save_popup_ = true;
        after_save_ = std::move(action);
      } else if (save_project_to(scene_->doc().project_path) && action) {
        action();
      }
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Discard", ImVec2(100, 0)) || answer == "discard") {
      auto action = std::move(pending_action_);
      pending_action_ = nullptr;
      ImGui::CloseCurrentPopup();
      if (action) action();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel", ImVec2(100, 0)) || answer == "cancel") {
      pending_action_ = nullptr;
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
}

// Runs `action` now, or after the artist saved or discarded the unsaved changes (Cancel drops it).
void Editor::guard_unsaved(std::function<void()> action) {
  if (scene_ && scene_->history.dirty(scene_->doc())) {
    pending_action_ = std::move(action);
    open_prompt_ = true;
  } else {
    action();
  }
}

// Scripted editor actions, one per line, for tests (`--script file`):
//   wait N | select_cage_vertex I [add] | select_cage_vertices_all | move DX DY DZ | undo | redo
//   save PATH | screenshot PATH | play | pause | time T
//   mode cage_vertices|cage_faces|skin_vertices|joints | select_cage_face I [add]
//   select_skin_vertex I [add] | select_joint I [add] | click_cage_vertex I | click_skin_vertex I
//   click_patch_point I (the parametric driver's control point I; `move` then moves it)
//   select all|none|invert|grow|shrink|mirror | soft on|off [R] [FALLOFF] [volume|surface]
//   mirror on|off | view front|right|top | camera YAW PITCH DIST [TX TY TZ] | clip NAME|rest | gizmo_drag x|y|z|yz|xz|xy|screen DX DY
//   auto_cage [FACES] | cage_op merge|weld D|flip|flip_all|linear [N]|loop [N]|refine|triangulate
//   open_asking PATH | answer save|discard|cancel | import_cage PATH | pose NODE X Y Z | reset_pose | compare on|off
//   rotate_drag x|y|z|view DEGREES | attach rigid|smooth [W]|skin_weights|joint|auto | keyset x|y|z | key
//   mirror_keyset | rig_panel | sets_panel [MAP] | set_edit remove|add|only|reset [mirror]
//   sim_panel | sim on|off | sim_weights pin|free [MASS STIFFNESS] (the selected cage vertices) |
//   sim_param gravity|damping|goal_frequency|iterations|substeps|preroll|margin|skeleton|edges VALUE |
//   sim_collider plane|sphere|capsule AX AY AZ BX BY BZ R | sim_remove_collider I (the Simulation window)
//   paint_at_skin_vertex I [RADIUS] | select_limb_faces | select_set_faces (the faces driving the
//   selected skin vertices) | log_set I (logs skin vertex I's elements) | export_window | export_cancel
//   export_browse | export_press (the window's Browse... and Export buttons)
//   bind_param local|epsilon|max_elements|scale|max_distance|separation_steps|variant VALUE (the
//   Binding panel's fields) | rebind (its Rebind button: changed parameters become an undo step)
//   memory PATH [LABEL] (appends the resident memory and the undo history's size to PATH: the soak test)
//   export glb|obj|json MODE|- FPS all|CLIP[,CLIP] PATH (File > Export: runs in the background; the
//   script waits for it; export_nowait: the script goes on) | heatmap on|off (the fidelity heat map)
//   | fidelity_check (Check all clips; the script waits for it; fidelity_check_nowait: it goes on) |
//   fidelity_cancel | fidelity_frame (logs
//   this frame's fidelity figures) | file_skinning on|off (L), and those of run_file_script_command
// `move` goes through the gizmo's own path: one drag, one undo step. `gizmo_drag` grabs a handle
// where a person would (hit-tested like a click) and drags it DX, DY pixels.
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
    ProjectDialogs::Request request;
    if (dialogs_.script_command(cmd, in, scene_.get(), hooks_, request)) {  // the prompts work without a document
      act_on(request);
      script_wait_ = 1;
      continue;
    }
    if (cmd == "wait") {
      in >> script_wait_;
      continue;
    }
    if (cmd == "screenshot") {
      in >> pending_screenshot_;
      script_wait_ = 1;  // taken after this frame renders
      continue;
    }
    if (cmd == "memory") {
      script_memory(in);
      continue;
    }
    if (!scene_) {
      if (!run_file_script_command(cmd, in))
        log("error: script line " + std::to_string(script_pos_) + ": '" + cmd + "' needs an open document", true);
      continue;
    }
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
      if (begin_move(GizmoHandle::kScreen, glm::dvec2(0.0))) {
        apply_move(d);
        end_move();
      }
    } else if (cmd == "gizmo_drag") {
      script_gizmo_drag(in);
    } else if (cmd == "mode") {
      std::string m;
      in >> m;
      bool found = false;
      for (int k = 0; k < 4; ++k) {
        std::string name = mode_name(static_cast<SelectMode>(k));
        std::replace(name.begin(), name.end(), ' ', '_');
        if (name == m) mode_ = static_cast<SelectMode>(k), found = true;
      }
      if (!found) log("error: script line " + std::to_string(script_pos_) + ": unknown mode '" + m + "'", true);
    } else if (cmd == "select_cage_face" || cmd == "select_skin_vertex" || cmd == "select_joint") {
      uint32_t i;
      std::string mode;
      in >> i >> mode;
      uint32_t idx[1] = {i};
      IndexSet& set = cmd == "select_cage_face" ? selection_.cage_faces
                      : cmd == "select_skin_vertex" ? selection_.skin_vertices : selection_.joints;
      if (mode == "add") set.add(idx);
      else set.set(idx);
    } else if (cmd == "click_cage_vertex" || cmd == "click_skin_vertex") {  // a real click at the vertex's projection: exercises picking
      uint32_t i;
      in >> i;
      const bool skin = cmd == "click_skin_vertex";
      if (skin) mode_ = SelectMode::kSkinVertices;
      const std::vector<glm::vec3>& points = skin ? scene_->skin_posed() : scene_->cage_posed;
      if (i < points.size()) {
        glm::dvec2 p = camera_.project(glm::dvec3(points[i]), view_w_, view_h_).pixel;
        click_select(ImVec2(view_x_ + static_cast<float>(p.x), view_y_ + static_cast<float>(p.y)), false, false);
      }
    } else if (cmd == "click_patch_point") {  // I: a real click at the parametric driver's control point I
      uint32_t i = 0;
      in >> i;
      const auto& driver = scene_->doc().patch_driver;
      if (driver && i < driver->posed.num_control_points()) {
        glm::dvec2 p = camera_.project(driver->posed.control_points()[i], view_w_, view_h_).pixel;
        click_select(ImVec2(view_x_ + static_cast<float>(p.x), view_y_ + static_cast<float>(p.y)), false, false);
      }
    } else if (cmd == "select") {
      std::string op;
      in >> op;
      const char* names[] = {"all", "none", "invert", "grow", "shrink", "mirror"};
      for (int k = 0; k < 6; ++k)
        if (op == names[k]) edit_selection(static_cast<SelectOp>(k));
    } else if (cmd == "soft") {  // soft on|off [radius] [smooth|linear|sharp|constant] [volume|surface]
      std::string on, word;
      in >> on;
      soft_.enabled = on == "on";
      double r;
      if (in >> r) soft_.radius = r;
      while (in >> word) {
        for (int k = 0; k < 4; ++k)
          if (word == falloff_name(static_cast<Falloff>(k))) soft_.falloff = static_cast<Falloff>(k);
        if (word == "surface") soft_.distance = FalloffDistance::kSurface;
        if (word == "volume") soft_.distance = FalloffDistance::kVolume;
      }
    } else if (cmd == "mirror") {
      std::string on;
      in >> on;
      mirror_.enabled = on == "on";
    } else if (cmd == "move_target") {  // rest | pose
      std::string t;
      in >> t;
      if (t != "rest" && t != "pose") log("error: script line " + std::to_string(script_pos_) + ": move_target rest|pose", true);
      else move_rest_ = t == "rest";
    } else if (cmd == "clip") {  // NAME, or "rest" for the bind pose
      std::string name;
      in >> name;
      const auto& clips = scene_->doc().character->clips;
      scene_->clip = -1;
      scene_->player = ClipPlayer(0.0);
      for (size_t i = 0; i < clips.size(); ++i)
        if (clips[i].name == name) {
          scene_->clip = static_cast<int32_t>(i);
          scene_->player = ClipPlayer(clips[i].duration);
        }
      if (name != "rest" && scene_->clip < 0) log("error: script line " + std::to_string(script_pos_) + ": no clip '" + name + "'", true);
    } else if (cmd == "auto_cage") {  // [FACES]: builds in the background; the script waits for it
      uint32_t faces;
      if (in >> faces) cage_tools_.auto_params().target_faces = faces;
      cage_tools_.open_auto_cage_dialog();
      cage_tools_.start_auto_cage(*scene_);
      script_wait_ = 1;  // the next steps run once it is done
    } else if (cmd == "export_window") {
      export_panel_.open(*scene_);
    } else if (cmd == "export" || cmd == "export_nowait") {
      script_waits_for_export_ = cmd == "export";
      script_export(in);
    } else if (cmd == "file_skinning" || cmd == "compare") {  // on | off: show the file's own skinning (L)
      std::string v;
      in >> v;
      scene_->show_file_skinning = v != "off";
    } else if (cmd == "heatmap") {  // on | off: the fidelity heat map
      std::string v;
      in >> v;
      fidelity_panel_.heat_map = v != "off";
    } else if (cmd == "fidelity_check" || cmd == "fidelity_check_nowait") {  // Check all clips; the script waits for it
      script_waits_for_fidelity_ = cmd == "fidelity_check";
      fidelity_panel_.start_check(*scene_, hooks_);
    } else if (cmd == "fidelity_cancel") {
      fidelity_panel_.cancel();
    } else if (cmd == "fidelity_frame") {  // logs the current frame's figures
      fidelity_panel_.update(*scene_);
      if (const auto& f = fidelity_panel_.frame()) {
        char buf[256];
        const Skeleton& sk = scene_->doc().character->skeleton;
        std::snprintf(buf, sizeof buf, "fidelity, this frame: worst %.4f%% (vertex %u, joint '%s'), RMS %.4f%%, stretch %.3fx",
                      100 * f->worst, f->worst_vertex,
                      f->worst_joint >= 0 ? sk.node(static_cast<size_t>(f->worst_joint)).name.c_str() : "-", 100 * f->rms,
                      f->stretch);
        log(buf);
      } else {
        log("fidelity, this frame: not measured (no binding, or the file's skinning is shown)");
      }
    } else if (cmd == "export_cancel") {
      export_panel_.cancel();
    } else if (cmd == "export_browse") {
      export_panel_.press_browse();
    } else if (cmd == "export_press") {
      script_waits_for_export_ = true;
      export_panel_.press_export(*scene_, hooks_);
    } else if (cmd == "cage_op") {  // merge | weld D | flip | flip_all | linear [N] | loop [N] | refine | triangulate
      std::string op;
      double arg = 0.0;
      in >> op >> arg;
      cage_tools_.run_operation(*scene_, selection_, op, arg, hooks_);
    } else if (cmd == "open_asking") {  // PATH: as File > Open does, asking first when there are unsaved changes
      std::string p;
      std::getline(in >> std::ws, p);
      guard_unsaved([this, p] { open_path(p); });
      script_wait_ = 1;
    } else if (cmd == "error_ok") {  // presses OK on the open Error dialog (nothing when there is none)
      script_error_ok_ = !error_modal_.empty();
      script_wait_ = 1;
    } else if (cmd == "answer") {  // save | discard | cancel: presses the button of the open "Save changes?"
      in >> script_answer_;
      script_wait_ = 1;
    } else if (cmd == "attach") {  // rigid | smooth [WIDTH] | skin_weights | joint (selected vertices -> the selected joint) | auto
      std::string what;
      in >> what;
      AttachmentMode mode;
      if (parse_attachment_mode(what, mode)) {
        double width = scene_->doc().attachment.smooth_width;
        in >> width;
        rig_panel_.set_attachment_mode(*scene_, mode, width, hooks_);
      } else {
        rig_panel_.assign(*scene_, selection_, what == "auto", mirror_.enabled, rig_mirror_tolerance(), hooks_);
      }
    } else if (cmd == "keyset") {  // x|y|z: a keypose set driven by the selected joint's rotation
      std::string axis;
      in >> axis;
      rig_panel_.add_set(*scene_, selection_, axis == "y" ? 1 : axis == "z" ? 2 : 0, hooks_);
    } else if (cmd == "key") {
      scene_->update_pose();
      rig_panel_.key(*scene_, hooks_);
    } else if (cmd == "mirror_keyset") {
      rig_panel_.mirror_set(*scene_, rig_mirror_tolerance(), hooks_);
    } else if (cmd == "sim_panel") {
      sim_panel_.visible() = true;
    } else if (cmd == "sim") {
      std::string what;
      in >> what;
      sim_panel_.set_enabled(*scene_, what != "off", hooks_);
    } else if (cmd == "sim_weights") {
      std::string what;
      float mass = 1.0f, stiffness = 0.3f;
      in >> what >> mass >> stiffness;
      sim_panel_.set_weights(*scene_, sim_paint_weights(), what == "pin", mass, stiffness, hooks_);
    } else if (cmd == "sim_param") {
      std::string name;
      double value = 0.0;
      in >> name >> value;
      SimParams p = scene_->doc().sim.params;
      if (name == "gravity") p.gravity.y = value;
      else if (name == "damping") p.damping = value;
      else if (name == "goal_frequency") p.goal_frequency = value;
      else if (name == "iterations") p.iterations = static_cast<int>(value);
      else if (name == "substeps") p.substeps = static_cast<int>(value);
      else if (name == "preroll") p.preroll = value;
      else if (name == "margin") p.collision_margin = value;
      else if (name == "skeleton") p.skeleton_colliders = value != 0.0;
      else if (name == "edges") p.edges = value != 0.0;
      else log("error: script: unknown simulation parameter '" + name + "'", true);
      sim_panel_.set_params(*scene_, p, hooks_);
    } else if (cmd == "sim_collider") {
      std::string kind;
      Collider c;
      in >> kind >> c.a.x >> c.a.y >> c.a.z >> c.b.x >> c.b.y >> c.b.z >> c.radius;
      if (!parse_collider_kind(kind, c.kind)) log("error: script: unknown collider kind '" + kind + "'", true);
      else sim_panel_.add_collider(*scene_, c, hooks_);
    } else if (cmd == "sim_remove_collider") {
      size_t i = 0;
      in >> i;
      sim_panel_.remove_collider(*scene_, i, hooks_);
    } else if (cmd == "rig_panel") {
      rig_panel_.visible() = true;
    } else if (cmd == "sets_panel") {  // [none|influence|size|flags|separated]: opens it with that map
      std::string m;
      in >> m;
      sets_panel_.visible() = true;
      const char* maps[] = {"none", "influence", "size", "flags", "separated"};
      for (int k = 0; k < 5; ++k)
        if (m == maps[k]) sets_panel_.map() = static_cast<SetMap>(k);
    } else if (cmd == "set_edit") {  // remove|add|only|reset [mirror]: on the selected skin vertices, with the selected faces
      std::string m, mirror;
      in >> m >> mirror;
      SetEditMode mode;
      if (parse_set_edit_mode(m, mode)) {
        sets_panel_.mode() = mode;
        sets_panel_.mirror() = mirror == "mirror";
        sets_panel_.apply(*scene_, selection_, selection_.skin_vertices, hooks_);
      } else {
        log("error: script line " + std::to_string(script_pos_) + ": unknown set edit mode '" + m + "'", true);
      }
    } else if (cmd == "select_set_faces") {  // the cage faces whose elements drive the selected skin vertices
      std::vector<uint32_t> faces;
      if (scene_->binding && scene_->doc().cage && scene_->binding->has_sets())
        for (uint32_t p : selection_.skin_vertices)
          if (p < scene_->binding->num_points)
            for (uint32_t e : scene_->binding->sets().of(p)) faces.push_back(scene_->doc().cage->element_face[e]);
      selection_.cage_faces = IndexSet(std::move(faces));
    } else if (cmd == "log_set") {  // I: logs the elements that drive skin vertex I now
      uint32_t p = 0;
      in >> p;
      std::string text = "set of skin vertex " + std::to_string(p) + ":";
      if (scene_->binding && p < scene_->binding->num_points && scene_->binding->has_sets())
        for (uint32_t e : scene_->binding->sets().of(p)) text += " " + std::to_string(e);
      else text += " (not bound)";
      log(text);
    } else if (cmd == "select_limb_faces") {  // the cage faces following the selected joints
      selection_.cage_faces = SetsPanel::limb_faces(*scene_, selection_.joints);
    } else if (cmd == "paint_at_skin_vertex") {  // I [RADIUS]: one brush stroke of one dab at skin vertex I
      uint32_t i;
      double r = 0.0;
      in >> i >> r;
      if (r > 0) sets_panel_.set_brush_radius(r);
      if (i < scene_->skin_posed().size()) {
        const auto& fv = scene_->skin_topology.face_vertices;
        uint32_t tri = 0;
        for (size_t k = 0; k < fv.size(); ++k)
          if (fv[k] == i) {
            tri = static_cast<uint32_t>(k / 3);
            break;
          }
        sets_panel_.begin_stroke(*scene_);
        sets_panel_.dab(*scene_, selection_, tri, glm::dvec3(scene_->skin_posed()[i]), hooks_);
        sets_panel_.end_stroke(*scene_);
      }
    } else if (cmd == "pose") {  // NODE X Y Z: the joint's rotation on top of the clip, degrees
      uint32_t node;
      glm::vec3 deg(0.f);
      in >> node >> deg.x >> deg.y >> deg.z;
      if (scene_->joint_globals.empty()) scene_->update_pose();
      set_override(node, glm::quat(glm::radians(deg)));
    } else if (cmd == "reset_pose") {
      scene_->pose_override.clear();
    } else if (cmd == "rotate_drag") {  // x|y|z|view DEGREES: grabs the ring where a person would
      script_rotate_drag(in);
    } else if (cmd == "view") {  // front | right | top
      std::string v;
      in >> v;
      camera_.set_preset(v == "right" ? ViewPreset::kRight : v == "top" ? ViewPreset::kTop : ViewPreset::kFront);
    } else if (cmd == "camera") {  // YAW PITCH DISTANCE [TX TY TZ]: degrees, scene units (a close-up)
      double yaw = 0, pitch = 0, dist = 0;
      in >> yaw >> pitch >> dist;
      camera_.set_angles(glm::radians(yaw), glm::radians(pitch));
      camera_.set_distance(dist);
      glm::dvec3 t;
      if (in >> t.x >> t.y >> t.z) camera_.set_target(t);
    } else if (cmd == "bind_param") {
      script_bind_param(in);
    } else if (cmd == "rebind") {
      scene_->rebind();
    } else if (cmd == "undo") undo();
    else if (cmd == "redo") redo();
    else if (cmd == "save") {
      std::string p;
      in >> p;
      save_project_to(p);
    } else if (cmd == "play") scene_->player.play();
    else if (cmd == "pause") scene_->player.pause();
    else if (cmd == "time") {
      double t;
      in >> t;
      scene_->player.scrub(t);
    } else if (patch_panel_.script_command(cmd, in, *scene_, selection_, hooks_)) {
      script_wait_ = 1;  // drawn before the next step
    } else if (!run_file_script_command(cmd, in))
      log("error: script line " + std::to_string(script_pos_) + ": unknown command '" + cmd + "'", true);
  }
}

void Editor::script_gizmo_drag(std::istringstream& in) {
  std::string name;
  glm::dvec2 d(0.0);
  in >> name >> d.x >> d.y;
  const char* names[] = {"x", "y", "z", "yz", "xz", "xy", "screen"};
  int h = -1;
  for (int k = 0; k < 7; ++k)
    if (name == names[k]) h = k;
  const GizmoLayout g = gizmo();
  if (h < 0 || !g.visible) {
    log("error: script line " + std::to_string(script_pos_) + ": no gizmo handle '" + name + "' to drag", true);
    return;
  }
  glm::dvec2 grab = g.centre;  // where a person grabs each handle
  if (h < 3) grab = g.centre + 0.75 * (g.axis_end[h] - g.centre);
  else if (h < 6) grab = 0.25 * (g.plane[h - 3][0] + g.plane[h - 3][1] + g.plane[h - 3][2] + g.plane[h - 3][3]);
  const GizmoHandle hit = gizmo_hit(g, grab);
  if (hit != static_cast<GizmoHandle>(h)) {
    log("error: script line " + std::to_string(script_pos_) + ": the click meant for handle '" + name + "' hit another", true);
    return;
  }
  if (!begin_move(hit, grab)) return;
  for (int step = 1; step <= 4; ++step) {  // a few mouse-move events, as a real drag sends
    auto total = gizmo_drag(camera_, Viewport{view_w_, view_h_}, hit, drag_centre_, grab, grab + d * (step / 4.0));
    if (total) apply_move(*total);
  }
  end_move();
}

// Grabs a ring at its point nearest the viewer (the view ring at its right) and drags it along
// the ring by the given angle, through the same hit test and angle code as the mouse.
void Editor::script_rotate_drag(std::istringstream& in) {
  std::string name;
  double degrees = 0.0;
  in >> name >> degrees;
  const char* names[] = {"x", "y", "z", "view"};
  int h = -1;
  for (int k = 0; k < 4; ++k)
    if (name == names[k]) h = k;
  const RotateGizmoLayout g = rotate_gizmo();
  if (h < 0 || !g.visible) {
    log("error: script line " + std::to_string(script_pos_) + ": no rotation ring '" + name + "' (select one joint in joint mode)", true);
    return;
  }
  const RotateHandle handle = static_cast<RotateHandle>(h);
  const glm::dvec3 axis = rotate_handle_axis(camera_, g, handle);
  // the grab point: on the ring, nearest the viewer (view ring: any point)
  const glm::dvec3 to_eye = glm::normalize(camera_.eye() - g.world_centre);
  glm::dvec3 radial = to_eye - glm::dot(to_eye, axis) * axis;
  if (h == 3 || glm::length(radial) < 1e-6) radial = glm::dvec3(camera_.right());
  radial = glm::normalize(radial);
  const double r = h == 3 ? g.world_radius * kRotateViewRingShare : g.world_radius;
  auto pixel_at = [&](double a) {
    const glm::dvec3 p = g.world_centre + r * (std::cos(a) * radial + std::sin(a) * glm::cross(axis, radial));
    return camera_.project(p, view_w_, view_h_).pixel;
  };
  const glm::dvec2 grab = pixel_at(0.0);
  const RotateHandle hit = rotate_gizmo_hit(g, grab);
  if (hit != handle) {
    log("error: script line " + std::to_string(script_pos_) + ": the click meant for ring '" + name + "' hit another", true);
    return;
  }
  begin_rotate(hit, grab);
  for (int step = 1; step <= 4; ++step) {
    auto a = rotate_gizmo_angle(camera_, Viewport{view_w_, view_h_}, rot_layout_, hit, grab, pixel_at(glm::radians(degrees) * step / 4.0));
    if (a) apply_rotate(*a);
  }
  rot_handle_ = RotateHandle::kNone;
}

// export FORMAT MODE|- FPS all|CLIP[,CLIP...] PATH: File > Export's Export button with these
// settings (clips by name); the script waits until it is done.
void Editor::script_export(std::istringstream& in) {
  if (!export_panel_.visible()) {  // open the window first and press Export on the next frame, as a
    export_panel_.open(*scene_);   // person would (a window first shown under the error modal that
    --script_pos_;                 // a refused export opens trips an ImGui assertion)
    script_wait_ = 1;
    return;
  }
  std::string format, mode, clips, path;
  double fps = 0.0;
  in >> format >> mode >> fps >> clips;
  std::getline(in >> std::ws, path);
  ExportRequest request;
  request.out = path;
  request.options.fps = fps;
  const std::string where = "error: script line " + std::to_string(script_pos_) + ": export: ";
  if (!parse_export_format(format, request.format)) return log(where + "format '" + format + "' is not glb, obj or json", true);
  if (mode != "-" && !parse_export_mode(mode, request.options.mode)) return log(where + "unknown mode '" + mode + "'", true);
  const Character& ch = *scene_->doc().character;
  if (clips == "all")
    for (size_t c = 0; c < ch.clips.size(); ++c) request.options.clips.push_back(static_cast<int32_t>(c));
  for (size_t start = 0; clips != "all" && start < clips.size();) {
    const size_t comma = std::min(clips.find(',', start), clips.size());
    const std::string name = clips.substr(start, comma - start);
    const int32_t c = ch.find_clip(name);
    if (c < 0) return log(where + "no clip '" + name + "'", true);
    request.options.clips.push_back(c);
    start = comma + 1;
  }
  export_panel_.start(*scene_, request, hooks_);
}

// bind_param NAME VALUE: sets a field of the Binding panel as its slider would (Rebind applies it).
void Editor::script_bind_param(std::istringstream& in) {
  std::string name, value;
  in >> name >> value;
  const std::string where = "error: script line " + std::to_string(script_pos_) + ": bind_param " + name + ": ";
  BindParams p = scene_->params;
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (name == "variant") {
    if (!parse_variant(value, p.variant)) return log(where + "unknown variant '" + value + "'", true);
  } else if (value.empty() || *end != '\0' || !(v >= 0.0) || v > 1e9) {
    return log(where + "'" + value + "' is not a non-negative number", true);
  } else if (name == "local") p.local = v;
  else if (name == "epsilon") p.epsilon = v;
  else if (name == "max_elements") p.max_elements = static_cast<uint32_t>(v);
  else if (name == "scale") p.scale = v;
  else if (name == "max_distance") p.max_distance = v;
  else if (name == "separation_steps") p.separation_steps = static_cast<uint32_t>(v);
  else return log(where + "unknown parameter", true);
  if (auto st = validate(p); !st) return log(where + st.error().message, true);
  scene_->params = p;
}

// Resident memory of this process in KiB (/proc/self/statm's second field, in pages); 0 where it
// cannot be read.
long resident_kib() {
  std::ifstream in("/proc/self/statm");
  long size = 0, resident = 0;
  if (!(in >> size >> resident)) return 0;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

// memory PATH [LABEL]: appends "LABEL rss_kib=N history_bytes=N undo_steps=N redo_steps=N" to PATH
// (the soak test reads it: tests/editor_soak_gui_test.cpp).
void Editor::script_memory(std::istringstream& in) {
  std::string path, label;
  in >> path;
  std::getline(in >> std::ws, label);
  std::ofstream out(path, std::ios::app);
  const History* h = scene_ ? &scene_->history : nullptr;
  out << (label.empty() ? "-" : label) << " rss_kib=" << resident_kib() << " history_bytes=" << (h ? h->memory_bytes() : 0)
      << " undo_steps=" << (h ? h->undo_steps() : 0) << " redo_steps=" << (h ? h->redo_steps() : 0) << "\n";
  if (!out.flush()) log("error: " + path + ": cannot append the memory figures", true);
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
  draw_toolbar();
  if (scene_) fidelity_panel_.draw_warning(*scene_, view_x_ + 10, view_y_ + view_h_ - 10);
  if (scene_) cage_tools_.draw_windows(*scene_, hooks_);
  if (scene_) export_panel_.draw(*scene_, hooks_);
  if (scene_) rig_panel_.draw(*scene_, selection_, mirror_.enabled, rig_mirror_tolerance(), hooks_);
  if (scene_) sets_panel_.draw(*scene_, selection_, hooks_);
  if (scene_ && sim_panel_.visible()) sim_panel_.draw(*scene_, sim_paint_weights(), hooks_);
  if (scene_) patch_panel_.draw(*scene_, selection_, hooks_);
  draw_help();
  // last: a window appearing after a modal's first Begin in the same frame trips an assertion in
  // Dear ImGui 1.86 (FindBlockingModal), and at start-up every panel appears with the prompt
  act_on(dialogs_.draw());
}

bool Editor::save_screenshot(const std::string& path, bool view_only) {
  int w, h;
  framebuffer_size(w, h);
  std::vector<unsigned char> pixels(static_cast<size_t>(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  if (offscreen_) offscreen_->bind_for_reading();
  else glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  if (offscreen_) offscreen_->begin_frame();
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
  if (options_.offscreen && options_.screenshot.empty() && options_.script.empty()) {
    std::fprintf(stderr, "error: --offscreen has no window and no input: give --script or --screenshot\n");
    return 1;
  }
  if (!open_window()) return 1;
  log(skin_display_.init(options_.cpu_deform ? SkinDisplay::Path::kCpu
                         : options_.gpu_deform ? SkinDisplay::Path::kGpu
                                               : SkinDisplay::Path::kAutomatic,
                         options_.frame_stats));
  if (window_) {
    glfwSetWindowUserPointer(window_, this);
    glfwSetDropCallback(window_, [](GLFWwindow* w, int count, const char** paths) {
      auto* self = static_cast<Editor*>(glfwGetWindowUserPointer(w));
      if (count > 0) self->dropped_ = paths[0];
    });
  }
  if (!options_.script.empty()) {
    std::ifstream in(options_.script);
    if (!in) {
      std::fprintf(stderr, "error: %s: cannot open the script\n", options_.script.c_str());
      return 1;
    }
    for (std::string line; std::getline(in, line);) script_.push_back(line);
  }
  hooks_.log = [this](const std::string& text, bool error) { log(text, error); };
  hooks_.show_error = [this](const std::string& message) {
    error_modal_ = message;
    log("error: " + message, true);
  };
  {
    const double interval = options_.autosave_seconds >= 0 ? options_.autosave_seconds : files_.prefs().autosave_seconds;
    const std::string dir = recovery_directory(preferences_directory());
    auto scan = list_recovery_files(dir);  // before this editor writes its own
    autosave_ = std::make_unique<Autosave>(dir, interval);
    load_initial();
    for (const auto& note : scan.notes) log(note);
    if (!scan.offer.empty()) log(std::to_string(scan.offer.size()) + " recovery file(s) of unsaved work found in " + dir);
    dialogs_.offer_recovery(std::move(scan.offer));
  }
  int frame = 0;
  int exit_code = 0;
  auto last = std::chrono::steady_clock::now();
  const bool scripted = !options_.screenshot.empty() || !script_.empty();
  while (!close_ && !(window_ && glfwWindowShouldClose(window_))) {
    if (window_) glfwPollEvents();
    auto now = std::chrono::steady_clock::now();
    double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    fps_ = 0.9 * fps_ + 0.1 * (dt > 0 ? 1.0 / dt : 0.0);
    int w, h;
    framebuffer_size(w, h);
    view_x_ = kLeftWidth;
    view_y_ = kMenuHeight;
    view_w_ = std::max(1.0f, w - kLeftWidth - kRightWidth);
    view_h_ = std::max(1.0f, h - kMenuHeight - kBottomHeight);
    if (!dropped_.empty()) {  // a mesh file becomes the cage; a project or character is opened
      const std::string path = dropped_;
      dropped_.clear();
      const bool mesh = has_extension(path, ".obj") || has_extension(path, ".ply") || has_extension(path, ".off") || has_extension(path, ".stl");
      if (mesh && scene_) import_cage(path);
      else guard_unsaved([this, path] { open_path(path); });
    }
    ImGui_ImplOpenGL3_NewFrame();
    if (window_) {
      ImGui_ImplGlfw_NewFrame();
    } else {  // no platform backend: the frame's size and time, no input
      ImGui::GetIO().DisplaySize = ImVec2(static_cast<float>(w), static_cast<float>(h));
      ImGui::GetIO().DeltaTime = dt > 0 ? static_cast<float>(dt) : 1.0f / 60.0f;
    }
    ImGui::NewFrame();
    handle_input();
    // a scripted run waits for the first bind so that the steps act on the deformed skin
    const bool export_blocks = export_panel_.busy() && script_waits_for_export_;
    const bool fidelity_blocks = fidelity_panel_.busy() && script_waits_for_fidelity_;
    if (!script_.empty() && !(scene_ && (scene_->job || cage_tools_.busy() || patch_panel_.busy() || export_blocks ||
                                         fidelity_blocks)))
      run_script_step();

    const auto scene_start = std::chrono::steady_clock::now();
    if (scene_) {
      if (auto msg = scene_->poll_bind()) {
        log(*msg, msg->rfind("error", 0) == 0);
        if (scene_->binding && !scene_->binding->invalid_elements.empty())
          log("warning: " + std::to_string(scene_->binding->invalid_elements.size()) + " cage elements skipped (zero area, non-finite or duplicate)");
      }
      cage_tools_.poll(*scene_, hooks_);
      patch_panel_.poll(*scene_, hooks_);
      export_panel_.poll(hooks_);
      fidelity_panel_.poll(*scene_, hooks_);
      if (sets_panel_.take_select_limb_request()) {
        selection_.cage_faces = SetsPanel::limb_faces(*scene_, selection_.joints);
        log("selected " + std::to_string(selection_.cage_faces.size()) + " cage faces of the selected joints' limbs");
      }
      if (scene_->doc().cage != shown_cage_) {  // a new cage (edit, undo, import): new topology?
        const Cage* c = scene_->doc().cage.get();
        if (!c || !shown_cage_ || c->num_vertices() != shown_cage_->num_vertices() || c->polygons.face_vertices != shown_cage_->polygons.face_vertices) {
          selection_.cage_vertices.clear();
          selection_.cage_faces.clear();
          topology_dirty_ = true;
        }
        shown_cage_ = scene_->doc().cage;
        display_key_.clear();
      }
      // scripted runs advance a fixed 1/30 s per frame so they are reproducible
      scene_->player.advance(scripted ? 1.0 / 30.0 : dt);
      // the cage simulation fills a few milliseconds a frame; a script waits for all of it
      scene_->fill_simulation(scripted ? 0.0 : 6.0);
      skin_display_.before_pose(*scene_);
      patch_panel_.drive_skin(*scene_);  // a parametric driver's skin replaces the cage's
      scene_->update_pose();
      if (topology_dirty_) upload_topology();
      if (auto e = skin_display_.update(*scene_, *renderer_); !e.empty()) log(e);
      patch_panel_.update_display(*scene_, *renderer_);  // a parametric driver's control net
      update_selection_display();
      {
        fidelity_panel_.update(*scene_);
        const auto& set_colors = sets_panel_.colors(*scene_, selection_);
        // the sets panel's colours while it shows them, else the fidelity heat map when it is on
        const auto& colors = set_colors.empty() ? fidelity_panel_.colors() : set_colors;
        if (!colors.empty() || skin_colored_) renderer_->set_skin_colors(colors);
        skin_colored_ = !colors.empty();
        if (auto faces = sets_panel_.highlighted_faces(*scene_, selection_); !faces.empty()) {
          face_mask_.assign(scene_->doc().cage->polygons.num_faces(), 0);
          for (uint32_t f : faces) face_mask_[f] = 1;
          display_key_.clear();  // the selection's own mask comes back when the panel lets go
        }
      }
      if (scene_->doc().cage) renderer_->update_cage(scene_->cage_posed, cage_weights_, face_mask_, bone_colors_);
      // the skin's CPU copy only when points are shown on it (the GPU path makes it on demand)
      const bool skin_points = !selection_.skin_vertices.empty() || cage_tools_.show_failing();
      renderer_->update_skin_points(skin_points ? std::span<const glm::vec3>(scene_->skin_posed()) : std::span<const glm::vec3>(),
                                    selection_.skin_vertices.indices(),
                                    cage_tools_.show_failing() ? std::span<const uint32_t>(cage_tools_.failing_points()) : std::span<const uint32_t>());
      renderer_->update_skeleton(scene_->joint_heads, scene_->bones, joint_mask_);
      std::string title = "cagewrap - " + (scene_->doc().project_path.empty() ? std::string("untitled") : scene_->doc().project_path) +
                          (recovered_ ? " (recovered)" : "") + (scene_->history.dirty(scene_->doc()) ? " *" : "");
      if (auto m = autosave_->tick(scene_->doc(), scene_->history.dirty(scene_->doc()))) log(*m, m->rfind("error", 0) == 0);
      if (title != title_ && window_) glfwSetWindowTitle(window_, (title_ = title).c_str());
    }
    const auto ui_start = std::chrono::steady_clock::now();
    skin_display_.add_scene_ms(std::chrono::duration<double, std::milli>(ui_start - scene_start).count());
    draw_panels();
    ImGui::Render();
    skin_display_.add_cpu_ms(FramePart::kUiBuild, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - ui_start).count());

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
      skin_display_.begin(FramePart::kDraw);
      renderer_->draw(v, style_);
      skin_display_.end(FramePart::kDraw);
    }
    skin_display_.begin(FramePart::kUiDraw);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    skin_display_.end(FramePart::kUiDraw);
    skin_display_.end_frame(dt * 1e3);
    ++frame;
    if (!pending_screenshot_.empty() && pending_screenshot_frames_-- <= 0) {
      save_screenshot(pending_screenshot_, screenshot_view_only_);
      pending_screenshot_.clear();
      screenshot_view_only_ = false;
    }
    const bool script_done = script_pos_ >= script_.size() && script_wait_ == 0;
    if (!options_.screenshot.empty() && frame >= options_.frames && script_done &&
        !(scene_ && (scene_->job || cage_tools_.busy() || patch_panel_.busy() || export_panel_.busy() || fidelity_panel_.busy()))) {
      exit_code = save_screenshot(options_.screenshot) && export_panel_.failures() == 0 ? 0 : 1;
      break;
    }
    // a script ending in `export` waits for the export to finish; a failed one fails the run
    if (options_.screenshot.empty() && !script_.empty() && script_done && frame > 1 &&
        !(scene_ && (scene_->job || cage_tools_.busy() || patch_panel_.busy() || export_panel_.busy() || fidelity_panel_.busy()))) {
      if (export_panel_.failures() > 0) exit_code = 1;
      break;
    }
    if (offscreen_) offscreen_->end_frame();
    else glfwSwapBuffers(window_);
  }
  if (options_.frame_stats || options_.frame_time) std::printf("%s\n", skin_display_.summary().c_str());
  if (window_) {  // an offscreen run keeps the window size the artist left
    int window_w = 0, window_h = 0;
    glfwGetWindowSize(window_, &window_w, &window_h);
    files_.remember(style_, window_w, window_h);
  }
  autosave_->discard();  // a clean quit: the work was saved, or the artist chose to discard it
  if (auto e = files_.save(); !e.empty()) log("warning: " + e);
  ImGui_ImplOpenGL3_Shutdown();
  if (window_) ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  scene_.reset();
  renderer_.reset();  // GL objects go while the context is current
  skin_display_.release_gl();
  offscreen_.reset();
  if (window_) glfwDestroyWindow(window_);
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
