// The editor: a GLFW window with Dear ImGui panels around a 3-D viewport. Opened by `cagewrap` with
// no subcommand.
#pragma once

#include <string>

namespace cagewrap::app {

struct EditorOptions {
  std::string file;        // a character (.glb/.gltf) to open; empty = the demo character
  std::string cage;        // a cage to use with it (.obj/.ply/.off/.stl); empty = automatic
  std::string script;      // editor actions to replay (see Editor::run_script_step)
  std::string screenshot;  // render, save this PNG after `frames` frames, and exit
  int frames = 3;
  int width = 0, height = 0;  // 0 = the size the window was left at (preferences), else 1600 x 900
  bool play = false;       // start playing the first clip
  bool keep_units = false;  // an FBX, Collada, ... `file` read in its own units and up axis (not metres, Y up)
  double autosave_seconds = -1;  // recovery file interval (app/workspace/autosave.h); < 0 = the preferences'; 0 = off
  bool cpu_deform = false;   // deform the skin on the CPU even where OpenGL 4.3 could (app/skin_display.h)
  bool gpu_deform = false;   // deform it on the GPU even on a software OpenGL (Mesa's llvmpipe)
  bool frame_stats = false;  // print the frame-time split (medians) at exit; finishes GL work per part
  bool frame_time = false;   // print the same at exit without finishing GL work between parts
  int msaa = -1;             // antialiasing samples; -1: 4 on a GPU, none on a software OpenGL (render/headless_gl.h)
  bool offscreen = false;    // no window: a headless EGL context and a framebuffer (app/offscreen_surface.h)
};

// Returns the process exit code.
int run_editor(const EditorOptions& options);
// The editor's action table (menus, shortcuts, panels and --script run it) as a Markdown table:
// the workspace's actions and the window's. Opens no window.
std::string editor_action_reference();

}  // namespace cagewrap::app
