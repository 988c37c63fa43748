#include "app/editor_window.h"

#if defined(CAGEWRAP_ASAN)
#include <sanitizer/lsan_interface.h>
#endif

#if CAGEWRAP_GUI

namespace cagewrap::app {

bool Editor::open_window() {
  if (options_.offscreen) {
    auto surface = OffscreenSurface::create(options_.width, options_.height, options_.msaa);
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
  GLint samples = 0;  // of the window, or of the offscreen framebuffer (bound)
  glGetIntegerv(GL_SAMPLES, &samples);
  if (samples > 1)
    log("view: antialiasing " + std::to_string(samples) + "x");
  else
    log(std::string("view: antialiasing off") +
        (options_.msaa < 0 ? " (software OpenGL, where it would cost more than half of each frame; --msaa 4 turns it on)" : ""));
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
  // antialiasing (--msaa, else render::editor_samples): the window's samples are fixed when it is made, so
  // a hidden 1 x 1 window first tells whether this OpenGL is software
  bool software = false;
  if (options_.msaa < 0) {
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    if (GLFWwindow* probe = glfwCreateWindow(1, 1, "cagewrap", nullptr, nullptr)) {
      glfwMakeContextCurrent(probe);
      software = render::current_context_is_software();
      glfwMakeContextCurrent(nullptr);
      glfwDestroyWindow(probe);
    }
    glfwWindowHint(GLFW_VISIBLE, GLFW_TRUE);
  }
  glfwWindowHint(GLFW_SAMPLES, render::editor_samples(options_.msaa, software));
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

void Editor::frame_all() {
  if (!ws_.scene()) return;
  Aabb box = bounding_box(ws_.scene()->skin_posed().empty() ? ws_.scene()->skin_rest : ws_.scene()->skin_posed());
  ws_.view.camera.frame(box, view_w_ / std::max(1.0f, view_h_));
}

void Editor::upload_topology() {
  renderer_->set_skin_topology(ws_.scene()->skin_rest.size(), ws_.scene()->skin_triangles());
  if (const Cage* cage = ws_.scene()->doc().cage.get()) {
    renderer_->set_cage_topology(cage->polygons, cage->elements, cage->element_face);
    cage_picker_ = PolygonPicker(cage->polygons);
  }
  skin_bvh_built_ = false;
  display_key_.reset();
  topology_dirty_ = false;
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
    if (ImGui::MenuItem("Save", "Ctrl+S", false, ws_.scene() != nullptr)) request_save();
    if (ImGui::MenuItem("Save as...", nullptr, false, ws_.scene() != nullptr)) open_save_popup_ = true;
    if (ws_.scene()) act_on(dialogs_.menu_items(ws_));
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
    if (ImGui::MenuItem("Import cage...", nullptr, false, ws_.scene() != nullptr)) browse(FilePurpose::kImportCage);
    if (ImGui::MenuItem("Add cage as a deformer layer...", nullptr, false, ws_.scene() != nullptr)) browse(FilePurpose::kAddDeformer);
    if (ImGui::MenuItem("Add a parametric driver...", nullptr, false, ws_.scene() != nullptr)) browse(FilePurpose::kAddDriver);
    if (ImGui::MenuItem("Export...", nullptr, false, ws_.scene() != nullptr)) export_panel_.open(*ws_.scene());
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
    const bool u = ws_.scene() && ws_.scene()->history().can_undo(), r = ws_.scene() && ws_.scene()->history().can_redo();
    if (ImGui::MenuItem(u ? ws_.scene()->history().undo_label().c_str() : "Undo", "Ctrl+Z", false, u)) ws_.run("undo");
    if (ImGui::MenuItem(r ? ws_.scene()->history().redo_label().c_str() : "Redo", "Ctrl+Shift+Z", false, r)) ws_.run("redo");
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Select")) {
    const char* keys[] = {"F5", "F6", "F7", "F8"};
    for (int k = 0; k < 4; ++k)
      if (ImGui::MenuItem(select_mode_name(static_cast<SelectMode>(k)), keys[k], ws_.view.mode == static_cast<SelectMode>(k)))
        ws_.view.mode = static_cast<SelectMode>(k);
    ImGui::Separator();
    const bool any = ws_.active_count() > 0;
    const bool meshy = ws_.view.mode != SelectMode::kJoints;
    if (ImGui::MenuItem("All", "Ctrl+A", false, any)) ws_.run(std::string("select ") + select_op_name(SelectOp::kAll));
    if (ImGui::MenuItem("None", "Esc", false, any)) ws_.run(std::string("select ") + select_op_name(SelectOp::kNone));
    if (ImGui::MenuItem("Invert", "Ctrl+I", false, any)) ws_.run(std::string("select ") + select_op_name(SelectOp::kInvert));
    if (ImGui::MenuItem("Grow", "Num+ or .", false, any && meshy)) ws_.run(std::string("select ") + select_op_name(SelectOp::kGrow));
    if (ImGui::MenuItem("Shrink", "Num- or ,", false, any && meshy)) ws_.run(std::string("select ") + select_op_name(SelectOp::kShrink));
    if (ImGui::MenuItem("Add mirror (X)", "Ctrl+M", false, any)) ws_.run(std::string("select ") + select_op_name(SelectOp::kMirror));
    ImGui::Separator();
    ImGui::MenuItem("Soft selection", "B", &ws_.view.soft.enabled);
    ImGui::MenuItem("X-mirror editing", "Shift+X", &ws_.view.mirror.enabled);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Cage", ws_.scene() != nullptr)) {
    cage_tools_.menu_items(ws_);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Rig", ws_.scene() != nullptr)) {
    ImGui::MenuItem("Attachment and keyposes...", "K", &rig_panel_.visible());
    ImGui::MenuItem("Contributing sets...", "J", &sets_panel_.visible());
    ImGui::MenuItem("Simulation...", nullptr, &sim_panel_.visible());
    ImGui::MenuItem("Parametric driver...", nullptr, &ws_.view.patch.editing);
    if (ImGui::MenuItem("Reset pose")) ws_.run("reset_pose");
    ImGui::MenuItem("Show the file's own skinning", "L", &ws_.view.playback.show_file_skinning);
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

// Floating windows (reports, Export, Rig, Sets, ...) open inside the 3-D view, at its right edge
// where they cover the least of the character, and never reach beyond the window: too wide or too
// tall for the view, they are made to fit (their contents scroll or wrap).
void Editor::keep_windows_in_view() {
  static const char* const kDocked[] = {"Outliner", "Properties", "Timeline", "Log", "toolbar", "stats", "view cues", "fidelity warning",
                                        "Debug##Default"};
  ImGuiContext& g = *ImGui::GetCurrentContext();
  const ImVec2 lo(view_x_, view_y_), hi(view_x_ + view_w_, view_y_ + view_h_);
  auto floating = [&](const ImGuiWindow* w) {
    // docked panels and the main menu bar do not move
    return w->Active && !(w->Flags & (ImGuiWindowFlags_ChildWindow | ImGuiWindowFlags_Popup | ImGuiWindowFlags_Tooltip |
                                      ImGuiWindowFlags_Modal | ImGuiWindowFlags_ChildMenu | ImGuiWindowFlags_NoMove)) &&
           std::none_of(std::begin(kDocked), std::end(kDocked), [&](const char* n) { return std::strcmp(w->Name, n) == 0; });
  };
  // A new window goes at the view's right edge, or left of the windows already there (side by
  // side while they fit, then cascaded), so that a second window does not hide the first.
  auto free_spot = [&](const ImGuiWindow* self, ImVec2 size) {
    float right = hi.x - 10.0f;
    for (int tries = 0; tries < 8; ++tries) {
      const ImVec2 p(right - size.x, lo.y + 40.0f);
      bool clear = p.x >= lo.x;
      float next_right = right;
      for (const ImGuiWindow* o : g.Windows)
        if (o != self && floating(o) && p.x < o->Pos.x + o->Size.x && o->Pos.x < p.x + size.x && p.y < o->Pos.y + o->Size.y &&
            o->Pos.y < p.y + size.y) {
          clear = false;
          next_right = std::min(next_right, o->Pos.x - 10.0f);
        }
      if (clear) return p;
      if (next_right >= right || next_right - size.x < lo.x) break;
      right = next_right;
    }
    int others = 0;
    for (const ImGuiWindow* o : g.Windows) others += o != self && floating(o);
    return ImVec2(hi.x - size.x - 10.0f - 24.0f * others, lo.y + 40.0f + 24.0f * others);  // cascaded
  };
  for (ImGuiWindow* w : g.Windows) {
    if (!floating(w)) continue;
    ImVec2 size = w->Size;
    const ImVec2 most(std::max(160.0f, view_w_ - 20.0f), std::max(120.0f, view_h_ - 20.0f));
    if (size.x > most.x || size.y > most.y) {
      size = ImVec2(std::min(size.x, most.x), std::min(size.y, most.y));
      ImGui::SetWindowSize(w, size, ImGuiCond_Always);
    }
    ImVec2 pos = w->Pos;
    const bool first = placed_.insert(w->ID).second;
    if (w->Appearing || first) pos = free_spot(w, size);
    // inside the view where it fits (an auto-sized window may not: then on the screen)
    const ImVec2 min = size.x <= view_w_ ? lo : ImVec2(0, PanelLayout::kMenuHeight);
    const ImVec2 max = size.x <= view_w_ ? hi : ImGui::GetIO().DisplaySize;
    pos.x = std::clamp(pos.x, min.x, std::max(min.x, max.x - size.x));
    pos.y = std::clamp(pos.y, min.y, std::max(min.y, max.y - size.y));
    if (pos.x != w->Pos.x || pos.y != w->Pos.y) ImGui::SetWindowPos(w, pos, ImGuiCond_Always);
  }
}

std::vector<const char*> Editor::hidden_view_parts() const {
  std::vector<const char*> out;
  for (auto [on, name] : {std::pair{style_.show_skin, "skin"}, std::pair{style_.show_cage, "cage"}, std::pair{style_.show_skeleton, "skeleton"}})
    if (!on) out.push_back(name);
  return out;
}

// What the View menu hides, said in the view (the toggles are remembered between runs).
void Editor::draw_view_cues() {
  std::string hidden;
  for (const char* name : hidden_view_parts()) hidden += std::string(hidden.empty() ? "" : ", ") + name;
  if (hidden.empty() || !ws_.scene()) return;
  const std::string text = "hidden: " + hidden + " (View menu)";
  ImGui::SetNextWindowPos(ImVec2(view_x_ + view_w_ - 10, view_y_ + view_h_ - 10), ImGuiCond_Always, ImVec2(1, 1));
  ImGui::SetNextWindowBgAlpha(0.6f);
  ImGui::Begin("view cues", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
  ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.2f, 1), "%s", text.c_str());
  ImGui::End();
}

void Editor::draw_panels() {
  draw_menu();
  draw_file_popups();
  draw_gizmo();
  draw_outliner();
  draw_properties();
  draw_timeline();
  draw_log();
  draw_toolbar();
  draw_stats();
  if (ws_.scene()) fidelity_panel_.draw_warning(ws_, view_x_ + 10, view_y_ + view_h_ - 10);
  if (ws_.scene()) cage_tools_.draw_windows(ws_);
  export_panel_.draw(ws_);
  rig_panel_.draw(ws_);
  sets_panel_.draw(ws_);
  sim_panel_.draw(ws_);
  if (ws_.scene()) patch_panel_.draw(ws_);
  draw_help();
  draw_view_cues();
  keep_windows_in_view();
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
  layout_.left = files_.prefs().panel_left;
  layout_.right = files_.prefs().panel_right;
  layout_.bottom = files_.prefs().panel_bottom;
  for (const char* name : hidden_view_parts())
    log(std::string("view: the ") + name + " is hidden (View > " + name + ", remembered from the last run)");
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
  ws_.show_error = hooks_.show_error;
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
  // a scripted run (a script or --screenshot) before its first binding: its frames count from there
  auto first_bind_wait = [&] { return scripted && ws_.scene() && ws_.scene()->job && !ws_.scene()->binding; };
  while (!close_ && !(window_ && glfwWindowShouldClose(window_))) {
    if (window_) glfwPollEvents();
    auto now = std::chrono::steady_clock::now();
    double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    fps_ = 0.9 * fps_ + 0.1 * (dt > 0 ? 1.0 / dt : 0.0);
    int w, h;
    framebuffer_size(w, h);
    layout_ = layout_.fitted(static_cast<float>(w), static_cast<float>(h));
    const ViewRect view = layout_.view(static_cast<float>(w), static_cast<float>(h));
    view_x_ = view.x;
    view_y_ = view.y;
    view_w_ = view.w;
    view_h_ = view.h;
    if (!dropped_.empty()) {  // a mesh file becomes the cage; a project or character is opened
      const std::string path = dropped_;
      dropped_.clear();
      const bool mesh = has_extension(path, ".obj") || has_extension(path, ".ply") || has_extension(path, ".off") || has_extension(path, ".stl");
      if (mesh && ws_.scene()) ws_.run("import_cage " + path);
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
    const bool export_blocks = ws_.exporting() && script_waits_for_export_;
    const bool fidelity_blocks = ws_.checking_fidelity() && !ws_.fidelity().nowait;
    if (!script_.empty() && !(ws_.scene() && (ws_.binding_any() || ws_.building_cage() || (ws_.binding_patch_driver() && !ws_.patch_state().nowait) || export_blocks ||
                                         fidelity_blocks)))
      run_script_step();

    const auto scene_start = std::chrono::steady_clock::now();
    if (ws_.scene()) {
      if (auto msg = ws_.scene()->poll_bind()) {
        log(*msg, msg->rfind("error", 0) == 0);
        if (ws_.scene()->binding && !ws_.scene()->binding->invalid_elements.empty())
          log("warning: " + std::to_string(ws_.scene()->binding->invalid_elements.size()) + " cage elements skipped (zero area, non-finite or duplicate)");
      }
      ws_.poll_jobs();
      if (sets_panel_.take_select_limb_request()) {
        ws_.run("select_limb_faces");
        log("selected " + std::to_string(ws_.view.selection.cage_faces.size()) + " cage faces of the selected joints' limbs");
      }
      if (ws_.scene()->doc().cage != shown_cage_) {  // a new cage (edit, undo, import): new topology?
        const Cage* c = ws_.scene()->doc().cage.get();
        if (!c || !shown_cage_ || c->num_vertices() != shown_cage_->num_vertices() || c->polygons.face_vertices != shown_cage_->polygons.face_vertices) {
          ws_.view.selection.cage_vertices.clear();
          ws_.view.selection.cage_faces.clear();
          topology_dirty_ = true;
        }
        shown_cage_ = ws_.scene()->doc().cage;
        display_key_.reset();
      }
      // scripted runs advance a fixed 1/30 s per frame so they are reproducible; while they wait for
      // the first bind neither the clip's time nor the frame count moves (however long it takes)
      if (!first_bind_wait()) ws_.view.playback.player.advance(scripted ? 1.0 / 30.0 : dt);
      // the cage simulation fills a few milliseconds a frame; a script waits for all of it
      ws_.scene()->fill_simulation(ws_.view.playback.clip, scripted ? 0.0 : 6.0);
      skin_display_.before_pose(*ws_.scene());
      ws_.update_pose();
      if (topology_dirty_) upload_topology();
      if (auto e = skin_display_.update(*ws_.scene(), *renderer_); !e.empty()) log(e);
      patch_panel_.update_display(ws_, *renderer_);  // a parametric driver's control net
      update_selection_display();
      {
        ws_.measure_fidelity();
        const auto& set_colors = sets_panel_.colors(*ws_.scene(), ws_.view.selection);
        // the sets panel's colours while it shows them, else the mask brush's weights while it paints, else the
        // fidelity heat map when it is on
        const auto& mask_colors = ws_.mask_colors();
        const auto& colors = !set_colors.empty() ? set_colors : !mask_colors.empty() ? mask_colors : ws_.fidelity().colors;
        if (!colors.empty() || skin_colored_) renderer_->set_skin_colors(colors);
        skin_colored_ = !colors.empty();
        if (auto faces = sets_panel_.highlighted_faces(*ws_.scene(), ws_.view.selection); !faces.empty()) {
          face_mask_.assign(ws_.scene()->doc().cage->polygons.num_faces(), 0);
          for (uint32_t f : faces) face_mask_[f] = 1;
          display_key_.reset();  // the selection's own mask comes back when the panel lets go
        }
      }
      if (ws_.scene()->doc().cage) renderer_->update_cage(ws_.scene()->cage_posed, cage_weights_, face_mask_, bone_colors_);
      update_other_cages();
      // the skin's CPU copy only when points are shown on it (the GPU path makes it on demand)
      const std::span<const uint32_t> failing = cage_tools_.failing_points(ws_);
      const bool skin_points = !ws_.view.selection.skin_vertices.empty() || !failing.empty();
      renderer_->update_skin_points(skin_points ? std::span<const glm::vec3>(ws_.scene()->skin_posed()) : std::span<const glm::vec3>(),
                                    ws_.view.selection.skin_vertices.indices(),
                                    failing);
      renderer_->update_skeleton(ws_.scene()->joint_heads, ws_.scene()->bones, joint_mask_);
      std::string title = "cagewrap - " + (ws_.scene()->doc().project_path.empty() ? std::string("untitled") : ws_.scene()->doc().project_path) +
                          (recovered_ ? " (recovered)" : "") + (ws_.scene()->dirty() ? " *" : "");
      if (auto m = autosave_->tick(ws_.scene()->work(), ws_.scene()->dirty())) log(*m, m->rfind("error", 0) == 0);
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
    if (ws_.scene()) {
      render::ViewParams v;
      v.x = static_cast<int>(view_x_);
      v.y = static_cast<int>(h - view_y_ - view_h_);  // GL's origin is the bottom-left corner
      v.width = static_cast<int>(view_w_);
      v.height = static_cast<int>(view_h_);
      v.view = glm::mat4(ws_.view.camera.view());
      v.projection = glm::mat4(ws_.view.camera.projection(double(v.width) / double(v.height)));
      v.grid_spacing = static_cast<float>(ws_.grid_spacing());
      skin_display_.begin(FramePart::kDraw);
      render::ViewportStyle style = style_;
      if (deformer_hidden(ws_.scene()->work(), ws_.scene()->active_deformer())) style.show_cage = false;  // hidden in the outliner
      style.show_other_cages = style_.show_cage;
      renderer_->draw(v, style);
      skin_display_.end(FramePart::kDraw);
    }
    skin_display_.begin(FramePart::kUiDraw);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    skin_display_.end(FramePart::kUiDraw);
    skin_display_.end_frame(dt * 1e3);
    if (!first_bind_wait()) ++frame;
    if (!pending_screenshot_.empty() && pending_screenshot_frames_-- <= 0) {
      save_screenshot(pending_screenshot_, screenshot_view_only_);
      pending_screenshot_.clear();
      screenshot_view_only_ = false;
    }
    const bool script_done = script_pos_ >= script_.size() && script_wait_ == 0;
    if (!options_.screenshot.empty() && frame >= options_.frames && script_done &&
        !background_busy()) {
      exit_code = save_screenshot(options_.screenshot) && ws_.export_state().failures == 0 ? 0 : 1;
      break;
    }
    // a script ending in `export` waits for the export to finish; a failed one fails the run
    if (options_.screenshot.empty() && !script_.empty() && script_done && frame > 1 &&
        !background_busy()) {
      if (ws_.export_state().failures > 0) exit_code = 1;
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
    files_.remember_panels(layout_.left, layout_.right, layout_.bottom);
  }
  autosave_->discard();  // a clean quit: the work was saved, or the artist chose to discard it
  if (auto e = files_.save(); !e.empty()) log("warning: " + e);
  ImGui_ImplOpenGL3_Shutdown();
  if (window_) ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  ws_.set_scene(nullptr);
  renderer_.reset();  // GL objects go while the context is current
  skin_display_.release_gl();
  offscreen_.reset();
  if (window_) glfwDestroyWindow(window_);
  // No glfwTerminate(): with Mesa's software rasterizer it unloads swrast_dri.so, whose LLVM static
  // destructors crash in __cxa_finalize. The process is about to exit; the OS reclaims the display.
  return exit_code;
}

int run_editor(const EditorOptions& options) {
  const int exit_code = Editor(options).run();
  // Under AddressSanitizer (make test-sanitize): the leak check now, with the editor gone and every thread
  // idle, instead of at exit, where LeakSanitizer's thread-stopping tracer crashed (signal 11) in about one
  // run in forty while the process wound down among Mesa's and TBB's threads. It is the same check (it
  // honours detect_leaks, reports and fails the same way) and the one at exit then does not run.
#if defined(CAGEWRAP_ASAN)
  __lsan_do_leak_check();
#endif
  return exit_code;
}

bool Editor::background_busy() const {
  return ws_.scene() && (ws_.binding_any() || ws_.building_cage() || ws_.binding_patch_driver() || ws_.exporting() || ws_.checking_fidelity());
}

std::string Editor::action_reference() const { return ws_.actions.reference(); }
std::string editor_action_reference() { return Editor(EditorOptions{}).action_reference(); }

}  // namespace cagewrap::app

#else  // built without the GUI

#include <cstdio>

#include "app/workspace/workspace.h"

namespace cagewrap::app {
int run_editor(const EditorOptions&) {
  std::fprintf(stderr, "error: this cagewrap was built without the editor (CAGEWRAP_GUI=OFF)\n");
  return 1;
}
std::string editor_action_reference() { return Workspace().actions.reference(); }
}  // namespace cagewrap::app

#endif
