// cagewrap: no arguments opens the editor; subcommands work headless for pipelines and tests.
#include <cstdio>

#include "app/commands.h"
#include "app/editor.h"

int main(int argc, char** argv) {
  CLI::App app{"cagewrap: skin characters with surface-oriented free-form deformation cages"};
  app.set_version_flag("--version", std::string("cagewrap ") + CAGEWRAP_VERSION);
  int exit_code = 0;
  cagewrap::app::EditorOptions editor;
  app.add_option("file", editor.file, "character (.glb .gltf .fbx .dae .x .b3d .ms3d .smd .md5mesh) or project (.cagewrap) to open; default: the demo character");
  app.add_flag("--keep-units", editor.keep_units,
               "FBX, Collada, ...: read the character in the file's own units and up axis (default: metres, Y up)");
  app.add_option("--cage", editor.cage, "cage to open with the character (.obj .ply .off .stl)");
  app.add_option("--screenshot", editor.screenshot, "render the editor, save this PNG and exit (for tests)");
  app.add_option("--script", editor.script, "replay editor actions from this file (tests)");
  app.add_option("--frames", editor.frames, "frames to run before the screenshot")->capture_default_str();
  app.add_option("--width", editor.width, "window width (default: as it was left, else 1600)");
  app.add_option("--height", editor.height, "window height (default: as it was left, else 900)");
  app.add_flag("--play", editor.play, "start playing the first clip");
  app.add_option("--autosave-seconds", editor.autosave_seconds,
                 "write a recovery file of unsaved work this often (default: the preferences' autosave, 180 s; 0 = off)");
  app.add_flag("--cpu-deform", editor.cpu_deform,
               "deform the skin on the CPU (default: on the GPU with OpenGL 4.3, unless the OpenGL is software)");
  app.add_flag("--gpu-deform", editor.gpu_deform,
               "deform the skin with OpenGL compute shaders even on a software OpenGL (Mesa's llvmpipe), where the CPU is faster");
  app.add_flag("--frame-stats", editor.frame_stats,
               "print where the frame time goes (deform, normals, scene, draw, UI; medians) at exit, finishing the GL's "
               "work after each part so that CPU times include it");
  app.add_flag("--frame-time", editor.frame_time,
               "print the same medians at exit without finishing GL work between parts: the frame rate as the artist "
               "sees it (GPU times still from timer queries)");
  app.add_option("--msaa", editor.msaa,
                 "antialiasing samples of the 3-D view (0 = none; default: 4 on a GPU, none on a software OpenGL such as "
                 "Mesa's llvmpipe, where they cost more than half of each frame)")
      ->check(CLI::Range(0, 16));
  app.add_flag("--offscreen", editor.offscreen,
               "run the editor with no window or display, drawing into an offscreen framebuffer through a headless "
               "OpenGL 4.3 context (EGL; a GPU server or CI runner); needs --script or --screenshot");
  app.positionals_at_end(false);
  cagewrap::app::add_bind_command(app, exit_code);
  cagewrap::app::add_deform_command(app, exit_code);
  cagewrap::app::add_bench_command(app, exit_code);
  cagewrap::app::add_info_command(app, exit_code);
  cagewrap::app::add_skin_command(app, exit_code);
  cagewrap::app::add_make_demo_command(app, exit_code);
  cagewrap::app::add_new_command(app, exit_code);
  cagewrap::app::add_cage_command(app, exit_code);
  cagewrap::app::add_cage_edit_command(app, exit_code);
  cagewrap::app::add_pose_command(app, exit_code);
  cagewrap::app::add_export_command(app, exit_code);
  cagewrap::app::add_project_command(app, exit_code);
  cagewrap::app::add_simulate_command(app, exit_code);
  cagewrap::app::add_demo_sim_command(app, exit_code);
  cagewrap::app::add_patch_command(app, exit_code);
  cagewrap::app::add_deformer_command(app, exit_code);
  cagewrap::app::add_check_command(app, exit_code);
  cagewrap::app::add_probe_command(app, exit_code);
  cagewrap::app::add_actions_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (app.get_subcommands().empty()) return cagewrap::app::run_editor(editor);
  return exit_code;
}
