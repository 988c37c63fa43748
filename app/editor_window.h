// The editor's window: the Editor class, whose methods are spread over app/editor*.cpp by concern:
//   editor.cpp            the window, the frame loop, the layout, the menus
//   editor_panels.cpp     the side panels (outliner, properties, tools, timeline, log)
//   editor_view.cpp       the 3-D view: input, picking, the selection's display, the gizmos
//   editor_documents.cpp  opening, saving, the file browser and the "save changes?" flow
//   editor_script.cpp     --script: the window's own actions in the action table, and the runner
// What the editor does to the document and the selection lives in the workspace
// (app/workspace/workspace.h), which has no window; this class draws it and routes input to it.
#pragma once

#include "app/editor.h"

#if CAGEWRAP_GUI
#include <epoxy/gl.h>
// epoxy first, then GLFW without its own GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui/backends/imgui_impl_glfw.h>
#include <imgui/backends/imgui_impl_opengl3.h>
#include <imgui/imgui.h>
#include <imgui/imgui_internal.h>
#include <stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <array>
#include <functional>
#include <unordered_set>
#include <cstring>
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
#include "app/workspace/scene.h"
#include "app/project_dialogs.h"
#include "app/workspace/autosave.h"
#include "core/document/binding_cache.h"
#include "app/workspace/camera.h"
#include "core/geometry/mesh_io.h"
#include "app/workspace/move_gizmo.h"
#include "app/workspace/rotate_gizmo.h"
#include "app/workspace/soft_selection.h"
#include "core/geometry/triangle_bvh.h"
#include "app/workspace/picking.h"
#include "core/document/project_io.h"
#include "core/geometry/selection.h"
#include "core/character/demo_character.h"
#include "core/io/gltf_writer.h"
#include "render/headless_gl.h"
#include "render/viewport_renderer.h"

#include "app/workspace/joint_tree.h"
#include "app/workspace/panel_layout.h"
#include "app/workspace/workspace.h"

namespace cagewrap::app {


class Editor {
 public:
  explicit Editor(const EditorOptions& o) : options_(o) { add_window_actions(); }
  int run();
  std::string action_reference() const;  // the action table as Markdown (`cagewrap actions`)

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
  // The selected cage vertices with their soft-selection shares, for the Simulation window.
  std::optional<glm::dvec3> selection_centre() const;
  GizmoLayout gizmo() const;
  void apply_move(const glm::dvec3& total);
  bool begin_move(GizmoHandle handle, glm::dvec2 from);
  void end_move();
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
  void update_selection_display();
  void update_other_cages();  // the other deformers' posed cages, for the view
  void draw_deformers();      // the outliner's Deformers (issue 21)
  void draw_driver_row(size_t i);  // parametric driver i among them
  void draw_mask_brush();          // the mask brush's settings while it paints
  void mask_dab(const ImVec2& mouse);
  char mask_field_[256] = "";  // the Deformers list's mask popup
  void draw_gizmo();
  void request_save();
  bool save_project_to(const std::string& path);
  // A project, or a character (read with the file browser's "keep units" choice).
  bool open_path(const std::string& path);
  bool open_project(const std::string& path, const std::string& character_override = {});
  void act_on(const ProjectDialogs::Request& request);
  void guard_unsaved(std::function<void()> action);
  // A bind, automatic cage, driver bind, export or fidelity check is under way.
  bool background_busy() const;
  void browse(FilePurpose purpose, const std::string& dir = {});
  void act_on(const EditorFiles::Choice& choice);
  void add_window_actions();  // editor_script.cpp
  void run_script_step();
  void script_gizmo_drag(std::istringstream& in);
  void script_rotate_drag(std::istringstream& in);
  void script_export(std::istringstream& in);
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
  void log(std::string text, bool error = false) { ws_.log(std::move(text), error); }
  bool save_screenshot(const std::string& path, bool view_only = false);

  PanelLayout layout_;  // panel sizes (splitters), from the preferences
  // Begins a docked panel at `pos` of `size` that the artist resizes by the edges in `resizable`
  // (ImGui borders): returns its size after this frame's resize.
  ImVec2 begin_panel(const char* name, ImVec2 pos, ImVec2 size, ImVec2 min, ImVec2 max);
  void draw_view_cues();  // says in the view what the View toggles hide
  std::vector<const char*> hidden_view_parts() const;  // "skin", "cage", "skeleton" hidden by the View menu
  void keep_windows_in_view();
  ImVec4 toolbar_rect_{0, 0, 0, 0};  // x, y, width, height of the view's toolbar last frame
  float stats_width_ = 0;            // of the stats overlay last frame
  std::unordered_set<unsigned> placed_;  // floating windows already placed in the view once
  JointTree outliner_tree_;
  const Character* outliner_for_ = nullptr;  // the character outliner_tree_ was made for
  const JointTree& outliner_tree(const Character& ch);
  void draw_joint_tree(const Character& ch, const JointTree& tree, uint32_t node);
  Workspace ws_;  // the document, view state, log and action table (app/workspace/workspace.h)
  EditorOptions options_;
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<OffscreenSurface> offscreen_;  // --offscreen: no window, an EGL context and a framebuffer
  bool close_ = false;                          // quit chosen (offscreen runs end with their script)
  std::unique_ptr<render::ViewportRenderer> renderer_ = std::make_unique<render::ViewportRenderer>();
  render::ViewportStyle style_;
  // the 3-D view rectangle in window pixels (top-left origin), updated every frame
  float view_x_ = 0, view_y_ = 0, view_w_ = 1, view_h_ = 1;
  // Moves edit the reference (rest) cage instead of adding pose offsets: the skin stays and only the
  // skin points near the moved vertices are registered again (Scene::moved_rest).
  // gizmo drag
  GizmoHandle drag_handle_ = GizmoHandle::kNone;
  glm::dvec2 drag_from_{0.0};    // view pixels where it began
  glm::dvec3 drag_centre_{0.0};  // gizmo centre when it began
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
  std::vector<glm::vec3> other_cage_segments_;
  std::vector<glm::vec4> bone_colors_;  // per cage vertex, when colouring the cage by bone
  bool color_by_bone_ = false;
  // What the selection's display was built from: rebuilt when any of it changes.
  struct SelectionDisplayKey {
    std::shared_ptr<const Cage> cage;
    SelectMode mode;
    bool soft;
    double radius;
    Falloff falloff;
    FalloffDistance distance;
    bool mirror;
    double mirror_tolerance;
    IndexSet vertices, faces, joints;
    uint64_t sim_revision;  // the document's, while the Simulation window (which paints weights) is open
    bool bones;
    uint64_t attachment_revision;
    bool operator==(const SelectionDisplayKey&) const = default;
  };
  std::optional<SelectionDisplayKey> display_key_;
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
  CageTools cage_tools_;
  ExportPanel export_panel_;
  FidelityPanel fidelity_panel_;
  bool script_waits_for_export_ = true;    // false after `export_nowait`: the script goes on meanwhile
  SkinDisplay skin_display_;  // the skin on the GPU or the CPU, and the frame-time split
  RigPanel rig_panel_;
  SetsPanel sets_panel_;
  SimPanel sim_panel_;
  PatchPanel patch_panel_;
  bool skin_colored_ = false;
  EditorHooks hooks_;
  std::string error_modal_;
  bool show_help_ = false;
  bool topology_dirty_ = true;
  double fps_ = 0.0;
};

// Resident memory of this process in KiB; 0 where it cannot be read.
long resident_kib();

}  // namespace cagewrap::app

#endif
