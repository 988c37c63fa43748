#include "app/editor_window.h"

#include <malloc.h>

#if CAGEWRAP_GUI

namespace cagewrap::app {

// --script FILE: one action of the table per line (app/workspace/actions.h; `cagewrap actions`
// lists them all, docs/editor-actions.md). An action may make the script wait frames
// (Action::script_frames, `wait N`), and a background job it starts (an automatic cage, an export,
// a fidelity check, a bind) holds the script until it ends.
void Editor::run_script_step() {
  if (script_wait_ > 0) {
    --script_wait_;
    return;
  }
  while (script_pos_ < script_.size() && script_wait_ == 0) {
    const size_t line = script_pos_++;  // script_pos_: the next line's index, the running line's number (1-based)
    ws_.run(script_[line], "script line " + std::to_string(line + 1));
  }
}

// The window's own actions: what needs the window, its panels or its file browser. The workspace
// registered the rest (app/workspace/workspace_actions.cpp).
void Editor::add_window_actions() {
  ActionTable& t = ws_.actions;
  ws_.after_action = [this](const Action& a) { script_wait_ = std::max(script_wait_, a.script_frames); };
  // a file's name is the rest of the line (names may hold spaces)
  auto rest_of_line = [](std::istringstream& in) {
    std::string arg;
    std::getline(in >> std::ws, arg);
    arg.erase(arg.find_last_not_of(" \t\r") + 1);
    return arg;
  };
  auto add = [&t](std::string name, std::string usage, std::string help, std::function<void(std::istringstream&)> run,
                  bool needs_document = true, int frames = 0) {
    t.add({std::move(name), std::move(usage), std::move(help), needs_document, frames, std::move(run)});
  };
  auto fail = [this](const std::string& text) { log("error: script line " + std::to_string(script_pos_) + ": " + text, true); };

  // ---- the script itself
  add("wait", "N", "Waits N frames before the next line.", [this](std::istringstream& in) { in >> script_wait_; }, false);
  add("screenshot", "PATH", "Saves the window as a PNG once this frame is drawn.",
      [this](std::istringstream& in) { in >> pending_screenshot_; }, false, 1);
  add("memory", "PATH [LABEL]", "Appends resident memory and the undo history's size to PATH (the soak test).",
      [this](std::istringstream& in) { script_memory(in); }, false);

  // ---- files
  add("open", "PATH", "Opens a character or a project (no question about unsaved work).",
      [this, rest_of_line](std::istringstream& in) { open_path(rest_of_line(in)); }, false);
  add("keep_units", "on|off", "Ticks the file browser's \"Keep the file's units and up axis\" for the next character opened.",
      [this, fail](std::istringstream& in) {
        std::string v;
        in >> v;
        if (v != "on" && v != "off") return fail("keep_units takes on or off");
        files_.browser().set_keep_units(v == "on");
      }, false);
  add("open_asking", "PATH", "Opens as File > Open does: asks first when there are unsaved changes.",
      [this, rest_of_line](std::istringstream& in) {
        std::string p = rest_of_line(in);
        guard_unsaved([this, p] { open_path(p); });
      }, false, 1);
  add("save", "PATH", "Saves the project to PATH.", [this](std::istringstream& in) {
    std::string p;
    in >> p;
    save_project_to(p);
  });
  add("browse", "open|save|import_cage|add_deformer|add_driver|screenshot [DIR]", "Opens the file browser for that purpose.",
      [this, rest_of_line, fail](std::istringstream& in) {
        std::string arg = rest_of_line(in), dir;
        const size_t space = arg.find(' ');
        if (space != std::string::npos) dir = arg.substr(arg.find_first_not_of(' ', space));
        arg.resize(std::min(space, arg.size()));
        const std::pair<const char*, FilePurpose> purposes[] = {{"open", FilePurpose::kOpen}, {"save", FilePurpose::kSaveProject},
                                                                {"import_cage", FilePurpose::kImportCage}, {"add_deformer", FilePurpose::kAddDeformer}, {"add_driver", FilePurpose::kAddDriver}, {"screenshot", FilePurpose::kScreenshot}};
        auto it = std::find_if(std::begin(purposes), std::end(purposes), [&](const auto& p) { return arg == p.first; });
        if (it == std::end(purposes)) return fail("browse open|save|import_cage|add_deformer|add_driver|screenshot [DIR]");
        browse(it->second, dir);
      }, false);
  add("browser_select", "NAME", "Selects NAME in the file browser.", [this, rest_of_line](std::istringstream& in) {
    const std::string arg = rest_of_line(in);
    if (!files_.browser().select(arg)) log("error: script: no " + arg + " in " + files_.browser().directory(), true);
  }, false);
  add("browser_name", "NAME", "Types NAME into the file browser's name field.",
      [this, rest_of_line](std::istringstream& in) { files_.browser().set_file_name(rest_of_line(in)); }, false);
  add("browser_confirm", "", "Presses the file browser's Open / Save.", [this](std::istringstream&) { files_.browser().confirm(); }, false);
  add("browser_cancel", "", "Presses the file browser's Cancel.", [this](std::istringstream&) { files_.browser().cancel(); }, false);
  add("error_ok", "", "Presses OK on the open Error dialog (nothing when there is none).",
      [this](std::istringstream&) { script_error_ok_ = !error_modal_.empty(); }, false, 1);
  add("answer", "save|discard|cancel", "Presses that button of the open \"Save changes?\" dialog.",
      [this](std::istringstream& in) { in >> script_answer_; }, false, 1);
  add("answer_missing", "locate|cancel", "Answers the \"character not found\" prompt of a project.",
      [this](std::istringstream& in) { dialogs_.answer_missing(in); }, false, 1);
  add("answer_recovery", "recover|discard|later", "Answers the prompt for a recovery file of unsaved work.",
      [this](std::istringstream& in) { dialogs_.answer_recovery(in); }, false, 1);
  // the window's embed: `embed off` with no path asks where to write the character (as the File menu
  // does) when the file it came from no longer holds it
  add("embed", "on|off [PATH]", "Keeps the character file inside the project (on), or writes it out (off: to PATH, where it came from, or where the browser says).",
      [this, rest_of_line, fail](std::istringstream& in) {
        std::string on;
        in >> on;
        const std::string path = rest_of_line(in);
        if (on == "on") ws_.embed_character();
        else if (on != "off") fail("embed on|off [PATH]");
        else if (auto ask = ws_.where_to_unembed(); ask && path.empty()) files_.browser().open(FilePurpose::kSaveCharacter, ask->directory, ask->name);
        else ws_.unembed_character(path);
      }, true, 1);

  // ---- the view
  add("panels", "LEFT RIGHT BOTTOM", "Sets the panels' sizes in pixels, as dragging their edges does (remembered).",
      [this, fail](std::istringstream& in) {
        float l = 0, r = 0, b = 0;
        if (!(in >> l >> r >> b) || l <= 0 || r <= 0 || b <= 0) return fail("panels LEFT RIGHT BOTTOM (pixels)");
        layout_.left = l;
        layout_.right = r;
        layout_.bottom = b;
      }, false, 1);
  add("log_layout", "", "Logs the 3-D view's rectangle and every open floating window's (window pixels).", [this](std::istringstream&) {
    char buf[320];
    std::snprintf(buf, sizeof buf, "layout: view %.0f %.0f %.0f %.0f, display %.0f %.0f", view_x_, view_y_, view_w_, view_h_,
                  ImGui::GetIO().DisplaySize.x, ImGui::GetIO().DisplaySize.y);
    log(buf);
    for (const ImGuiWindow* w : ImGui::GetCurrentContext()->Windows)
      if ((w->Active || w->WasActive) && placed_.count(w->ID)) {
        std::snprintf(buf, sizeof buf, "layout: window '%s' %.0f %.0f %.0f %.0f", w->Name, w->Pos.x, w->Pos.y, w->Size.x, w->Size.y);
        log(buf);
      }
  }, false);
  add("toggle", "wireframe|xray|skin|cage|skeleton|grid|gpu_deform", "Turns a view option on or off.",
      [this, rest_of_line, fail](std::istringstream& in) {
        const std::string arg = rest_of_line(in);
        bool* flags[] = {&style_.wireframe, &style_.xray, &style_.show_skin, &style_.show_cage, &style_.show_skeleton,
                         &style_.show_grid, &skin_display_.use_gpu()};
        const char* names[] = {"wireframe", "xray", "skin", "cage", "skeleton", "grid", "gpu_deform"};
        auto it = std::find(std::begin(names), std::end(names), arg);
        if (it == std::end(names)) return fail("unknown view option '" + arg + "'");
        bool* f = flags[it - std::begin(names)];
        *f = !*f;
      }, false);
  // ---- clicks and drags where a person would make them (they exercise picking and the gizmos)
  auto click_at = [this](const glm::dvec3& p) {
    glm::dvec2 px = ws_.view.camera.project(p, view_w_, view_h_).pixel;
    click_select(ImVec2(view_x_ + static_cast<float>(px.x), view_y_ + static_cast<float>(px.y)), false, false);
  };
  add("click_cage_vertex", "I", "Clicks at cage vertex I's projection.", [this, click_at](std::istringstream& in) {
    uint32_t i = 0;
    in >> i;
    if (i < ws_.scene()->cage_posed.size()) click_at(glm::dvec3(ws_.scene()->cage_posed[i]));
  });
  add("click_skin_vertex", "I", "Clicks at skin vertex I's projection (in skin-vertex mode).", [this, click_at](std::istringstream& in) {
    uint32_t i = 0;
    in >> i;
    ws_.view.mode = SelectMode::kSkinVertices;
    if (i < ws_.scene()->skin_posed().size()) click_at(glm::dvec3(ws_.scene()->skin_posed()[i]));
  });
  add("click_patch_point", "I", "Clicks at the parametric driver's control point I (`move` then moves it).",
      [this, click_at](std::istringstream& in) {
        uint32_t i = 0;
        in >> i;
        const auto& driver = ws_.scene()->doc().patch_driver;
        if (driver && i < driver->posed.num_control_points()) click_at(driver->posed.control_points()[i]);
      });
  add("click_patch_sample", "I [add]", "With the driver window's sample tool on, clicks at the driver's sample I (shift-clicks with `add`).",
      [this](std::istringstream& in) {
        uint32_t i = 0;
        std::string mode;
        in >> i >> mode;
        const std::vector<glm::vec3>& samples = ws_.driver_sample_points();
        if (i >= samples.size()) return;
        const glm::dvec2 px = ws_.view.camera.project(glm::dvec3(samples[i]), view_w_, view_h_).pixel;
        click_select(ImVec2(view_x_ + static_cast<float>(px.x), view_y_ + static_cast<float>(px.y)), mode == "add", false);
      });
  // the workspace's `move` moves the cage selection; with a control point picked it moves that
  add("move", "DX DY DZ", "Moves the selection (cage vertices, faces' corners, or the picked control point) by a world displacement: one undo step.",
      [this, fail](std::istringstream& in) {
        glm::dvec3 d(0.0);
        if (!(in >> d.x >> d.y >> d.z)) return fail("move DX DY DZ");
        if (begin_move(GizmoHandle::kScreen, glm::dvec2(0.0))) {
          apply_move(d);
          end_move();
        }
      });
  add("gizmo_drag", "x|y|z|yz|xz|xy|screen DX DY", "Drags a handle of the move gizmo by DX DY pixels.",
      [this](std::istringstream& in) { script_gizmo_drag(in); });
  add("rotate_drag", "x|y|z|view DEGREES", "Drags a ring of the rotate gizmo of the selected joint.",
      [this](std::istringstream& in) { script_rotate_drag(in); });

  // ---- cage tools
  // the window's auto_cage opens the dialog with those faces and holds the script until the build ends
  add("auto_cage", "[FACES]", "Builds an automatic cage in the background; the script waits for it.", [this](std::istringstream& in) {
    uint32_t faces;
    if (in >> faces) cage_tools_.auto_params().target_faces = faces;
    cage_tools_.open_auto_cage_dialog();
    ws_.start_auto_cage(cage_tools_.auto_params());
  }, true, 1);

  // ---- export and fidelity
  add("export_window", "", "Opens the Export window.", [this](std::istringstream&) { export_panel_.open(*ws_.scene()); });
  // the window's export lines replace the workspace's: they open the Export window first, show what
  // they export there, and (not _nowait) hold the script until it ends
  add("export", "FORMAT MODE|- FPS all|CLIP[,CLIP] PATH", "Exports the rig (glb, obj or json); the script waits for it.",
      [this](std::istringstream& in) {
        script_waits_for_export_ = true;
        script_export(in);
      });
  add("export_nowait", "FORMAT MODE|- FPS all|CLIP[,CLIP] PATH", "Exports the rig; the script goes on meanwhile.",
      [this](std::istringstream& in) {
        script_waits_for_export_ = false;
        script_export(in);
      });
  add("export_browse", "", "The Export window's Browse.", [this](std::istringstream&) { export_panel_.press_browse(); });
  add("export_press", "", "The Export window's Export; the script waits for it.", [this](std::istringstream&) {
    script_waits_for_export_ = true;
    ws_.start_export(export_panel_.shown_request());
  });
  // (fidelity_check, fidelity_cancel, fidelity_frame, heatmap: the workspace's, app/workspace/workspace_actions.cpp)

  // ---- rig: attachment and keyposes
  add("rig_panel", "", "Opens the Rig window.", [this](std::istringstream&) { rig_panel_.visible() = true; });
  // (attach, keyset, key, remove_key, mirror_keyset: the workspace's, app/workspace/workspace_actions.cpp)

  // ---- simulation
  add("sim_panel", "", "Opens the Simulation window.", [this](std::istringstream&) { sim_panel_.visible() = true; });

  // ---- contributing sets
  add("sets_panel", "[none|influence|size|flags|separated]", "Opens the Sets window with that map.", [this](std::istringstream& in) {
    std::string m;
    in >> m;
    sets_panel_.visible() = true;
    const char* maps[] = {"none", "influence", "size", "flags", "separated"};
    for (int k = 0; k < 5; ++k)
      if (m == maps[k]) sets_panel_.map() = static_cast<SetMap>(k);
  });
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
    auto total = gizmo_drag(ws_.view.camera, Viewport{view_w_, view_h_}, hit, drag_centre_, grab, grab + d * (step / 4.0));
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
  const glm::dvec3 axis = rotate_handle_axis(ws_.view.camera, g, handle);
  // the grab point: on the ring, nearest the viewer (view ring: any point)
  const glm::dvec3 to_eye = glm::normalize(ws_.view.camera.eye() - g.world_centre);
  glm::dvec3 radial = to_eye - glm::dot(to_eye, axis) * axis;
  if (h == 3 || glm::length(radial) < 1e-6) radial = glm::dvec3(ws_.view.camera.right());
  radial = glm::normalize(radial);
  const double r = h == 3 ? g.world_radius * kRotateViewRingShare : g.world_radius;
  auto pixel_at = [&](double a) {
    const glm::dvec3 p = g.world_centre + r * (std::cos(a) * radial + std::sin(a) * glm::cross(axis, radial));
    return ws_.view.camera.project(p, view_w_, view_h_).pixel;
  };
  const glm::dvec2 grab = pixel_at(0.0);
  const RotateHandle hit = rotate_gizmo_hit(g, grab);
  if (hit != handle) {
    log("error: script line " + std::to_string(script_pos_) + ": the click meant for ring '" + name + "' hit another", true);
    return;
  }
  begin_rotate(hit, grab);
  for (int step = 1; step <= 4; ++step) {
    auto a = rotate_gizmo_angle(ws_.view.camera, Viewport{view_w_, view_h_}, rot_layout_, hit, grab, pixel_at(glm::radians(degrees) * step / 4.0));
    if (a) apply_rotate(*a);
  }
  rot_handle_ = RotateHandle::kNone;
}

// export FORMAT MODE|- FPS all|CLIP[,CLIP...] PATH: File > Export's Export button with these
// settings (clips by name); the script waits until it is done.
void Editor::script_export(std::istringstream& in) {
  if (!export_panel_.visible()) {  // open the window first and press Export on the next frame, as a
    export_panel_.open(*ws_.scene());   // person would (a window first shown under the error modal that
    --script_pos_;                 // a refused export opens trips an ImGui assertion)
    script_wait_ = 1;
    return;
  }
  auto request = ws_.parse_export(in);
  if (!request) return ws_.refuse_export("script line " + std::to_string(script_pos_) + ": " + request.error().message);
  export_panel_.show(*ws_.scene(), *request);
  ws_.start_export(*request);
}

// Resident memory of this process in KiB (/proc/self/statm's second field, in pages); 0 where it
// cannot be read. glibc's malloc first gives back the free memory it keeps for reuse (freed bindings
// and skins, several MiB each, in every thread's arena), so that the figure is what is in use and a
// leak stands out from the allocator's caching.
long resident_kib() {
#if defined(__GLIBC__) && !defined(CAGEWRAP_ASAN)
  malloc_trim(0);
#endif
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
  const History* h = ws_.scene() ? &ws_.scene()->history() : nullptr;
  out << (label.empty() ? "-" : label) << " rss_kib=" << resident_kib() << " history_bytes=" << (h ? h->memory_bytes() : 0)
      << " undo_steps=" << (h ? h->undo_steps() : 0) << " redo_steps=" << (h ? h->redo_steps() : 0) << "\n";
  if (!out.flush()) log("error: " + path + ": cannot append the memory figures", true);
}

}  // namespace cagewrap::app

#endif
