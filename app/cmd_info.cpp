// cagewrap info FILE: what a character or mesh file holds.
#include <cstdio>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/io/assimp_loader.h"
#include "core/io/gltf_loader.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap::app {

namespace {

void print_character(const std::string& path, const Character& c) {
  std::printf("file        %s\n", path.c_str());
  size_t meshes = 0;
  for (size_t i = 0; i < c.primitives.size(); ++i)
    if (i == 0 || c.primitives[i].mesh != c.primitives[i - 1].mesh || c.primitives[i].node != c.primitives[i - 1].node)
      ++meshes;
  std::printf("meshes      %zu (%zu primitives)\n", meshes, c.primitives.size());
  for (const Primitive& p : c.primitives) {
    std::printf("  %s: %zu vertices, %zu triangles", p.label().c_str(), p.num_vertices(), p.triangles.size());
    if (p.skin >= 0) std::printf(", skin %d", p.skin);
    if (!p.morph_targets.empty()) std::printf(", %zu morph targets", p.morph_targets.size());
    std::printf("\n");
  }
  std::printf("vertices    %zu\n", c.num_vertices());
  std::printf("triangles   %zu\n", c.num_triangles());
  std::printf("joints      %zu", c.num_joints());
  for (size_t s = 0; s < c.skins.size(); ++s) {
    std::printf("%s", s == 0 ? ":" : " |");
    for (uint32_t j : c.skins[s].joints) {
      const std::string& name = c.skeleton.node(j).name;
      std::printf(" %s", name.empty() ? ("node_" + std::to_string(j)).c_str() : name.c_str());
    }
  }
  std::printf("\n");
  std::printf("nodes       %zu\n", c.skeleton.size());
  std::printf("clips       %zu\n", c.clips.size());
  for (size_t i = 0; i < c.clips.size(); ++i) {
    const Clip& clip = c.clips[i];
    std::printf("  %zu %-24s %8.3f s  %zu channels\n", i, clip.name.c_str(), clip.duration, clip.channels.size());
  }
  std::printf("warnings    %zu\n", c.warnings.size());
  for (const std::string& w : c.warnings) std::printf("  %s\n", w.c_str());
}

}  // namespace

void add_info_command(CLI::App& app, int& exit_code) {
  auto file = std::make_shared<std::string>();
  auto keep_units = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("info", "print what a file holds: meshes, vertex and triangle counts, joints, clips, warnings");
  cmd->add_option("file", *file,
                  "a character (.glb, .gltf; through assimp .fbx, .dae, .x, .b3d, .ms3d, .smd, .md5mesh) or a mesh (.obj, "
                  ".ply, .off, .stl)")
      ->required();
  add_keep_units_flag(*cmd, *keep_units);
  cmd->callback([file, keep_units, &exit_code] {
    exit_code = 1;
    if (is_assimp_character(*file)) {
      CharacterLoadOptions options;
      options.keep_units = *keep_units;
      AssimpUnits units;
      auto c = load_character_assimp(*file, options, &units);
      if (!c) {
        report_error(c.error());
        return;
      }
      print_character(*file, *c);
      std::printf("units       the file: %g m a unit, %s up; %s\n", units.metres_per_unit, units.up_axis.c_str(),
                  *keep_units ? "kept (--keep-units)" : units.converted ? "brought to metres, Y up" : "already metres, Y up");
    } else if (has_extension(*file, ".glb") || has_extension(*file, ".gltf")) {
      auto c = load_character(*file);
      if (!c) {
        report_error(c.error());
        return;
      }
      print_character(*file, *c);
    } else {
      auto m = load_mesh_or_report(*file);
      if (!m) return;
      std::printf("file        %s\n", file->c_str());
      std::printf("meshes      1 (static mesh, no skeleton)\n");
      std::printf("vertices    %zu\n", m->num_vertices());
      std::printf("faces       %zu (%zu triangles after triangulation)\n", m->num_faces(), triangulate(*m).triangles.size());
      std::printf("joints      0\nclips       0\nwarnings    0\n");
    }
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
