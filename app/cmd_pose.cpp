// cagewrap pose --project P [--clip NAME|INDEX|rest] [--time t] [--loop] [--pose node=rx,ry,rz]...
//               --out skin.obj|.bin [--cage-out cage.obj]
// Writes the skin of a saved project deformed through its cage at a pose: the clip at a time, with
// per-joint rotations on top; the cage follows the skeleton by the project's attachment settings and
// keyposes (core/rig/rig.h, the same path the editor takes).
#include <cmath>
#include <cstdio>
#include <sstream>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/geometry/mesh_io.h"
#include "core/document/project_io.h"
#include "core/rig/rig.h"
#include "core/character/skinning.h"

namespace cagewrap::app {

namespace {
// "forearm.L=0,0,90" -> node, rotation; the node name may itself contain '='.
bool parse_pose_override(const std::string& text, const Skeleton& skeleton, uint32_t& node, glm::quat& q,
                         std::string& error) {
  size_t eq = text.rfind('=');
  if (eq == std::string::npos || eq == 0) {
    error = "--pose '" + text + "' should be NODE=rx,ry,rz (degrees)";
    return false;
  }
  std::string name = text.substr(0, eq);
  int32_t n = skeleton.find(name);
  if (n < 0) {
    error = "--pose '" + text + "': the character has no node named '" + name + "'";
    return false;
  }
  double a[3];
  std::istringstream in(text.substr(eq + 1));
  for (int i = 0; i < 3; ++i) {
    std::string part;
    if (!std::getline(in, part, i < 2 ? ',' : '\n')) {
      error = "--pose '" + text + "' should give three angles rx,ry,rz in degrees";
      return false;
    }
    char* end = nullptr;
    a[i] = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(a[i])) {
      error = "--pose '" + text + "': '" + part + "' is not a finite number of degrees";
      return false;
    }
  }
  node = static_cast<uint32_t>(n);
  q = rotation_xyz_degrees(a[0], a[1], a[2]);
  return true;
}
}  // namespace

void add_pose_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string project, clip, out, cage_out;
    std::vector<std::string> pose;
    double time = 0.0;
    bool loop = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("pose", "write a project's skin deformed through its cage at a clip time and pose");
  cmd->add_option("--project", args->project, "project file (.cagewrap)")->required();
  cmd->add_option("--clip", args->clip, "clip name or index; 'rest' or omitted: the rest pose");
  cmd->add_option("--time", args->time, "seconds into the clip (clamped to the clip)")->capture_default_str();
  cmd->add_flag("--loop", args->loop, "wrap the time into the clip instead of clamping");
  cmd->add_option("--pose", args->pose,
                  "NODE=rx,ry,rz: rotate a joint by these degrees about its local X, Y, Z on top of the clip "
                  "(repeatable)");
  cmd->add_option("--out", args->out, "deformed skin: .obj (with triangles), or .bin (raw float32 N x 3)")
      ->required();
  cmd->add_option("--cage-out", args->cage_out,
                  "also write the posed driver cage (.obj with its polygons, or .bin)");
  cmd->callback([args, &exit_code] {
    exit_code = 1;
    const std::string& P = args->project;
    if (!positions_output_or_report(args->out)) return;
    if (!std::isfinite(args->time)) {
      std::fprintf(stderr, "error: --time must be a finite number of seconds\n");
      return;
    }
    auto loaded = load_project_or_report(P);
    if (!loaded) return;
    const Document& doc = loaded->document;
    const Character& ch = *doc.character;
    int32_t clip = -1;
    if (!args->clip.empty() && args->clip != "rest") {
      clip = ch.find_clip(args->clip);
      if (clip < 0) {
        std::string names;
        for (size_t i = 0; i < ch.clips.size(); ++i) names += (i ? ", " : "") + ch.clips[i].name;
        std::fprintf(
            stderr,
            "error: %s: its character %s has no clip named or numbered '%s' (it has %zu: %s; or 'rest')\n",
            P.c_str(), doc.character_path.c_str(), args->clip.c_str(), ch.clips.size(),
            names.empty() ? "none" : names.c_str());
        return;
      }
    }
    std::vector<glm::quat> overrides(ch.skeleton.size(), glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
    for (const std::string& text : args->pose) {
      uint32_t node;
      glm::quat q;
      std::string error;
      if (!parse_pose_override(text, ch.skeleton, node, q, error)) {
        std::fprintf(stderr, "error: %s: %s\n", P.c_str(), error.c_str());
        return;
      }
      overrides[node] = glm::normalize(overrides[node] * q);
    }
    auto rig = rig_of_project(doc, P);
    if (!rig) return;
    PosedCage posed;
    std::vector<glm::vec3> skin(rig->num_skin_points());
    // a clip plays: through pose_clip, which applies the cage's simulation when the project has one
    auto s = clip < 0 ? rig->pose(doc, compose_pose(ch, clip, args->time, args->loop, overrides), posed, skin)
                      : rig->pose_clip(doc, clip, clip_time(args->time, ch.clips[clip].duration, args->loop),
                                       overrides, posed, skin);
    if (!s) {
      report_error(
          {s.error().code, P + (clip >= 0 ? " (clip '" + ch.clips[clip].name + "')" : std::string()) + ": " +
                               s.error().message});
      return;
    }
    if (auto s = save_positions(args->out, skin, combined_topology(ch)); !s) {
      report_error(s.error());
      return;
    }
    if (!args->cage_out.empty()) {
      if (auto s = save_positions(args->cage_out, posed.positions, doc.cage->polygons); !s) {
        report_error(s.error());
        return;
      }
    }
    size_t active = 0;
    for (size_t i = 0; i < doc.keyposes.size(); ++i) active += keypose_set_active(doc.keyposes, i);
    std::string when = "the rest pose";
    if (clip >= 0) {
      char t[32];
      std::snprintf(t, sizeof t, "%g", clip_time(args->time, ch.clips[clip].duration, args->loop));
      when = "clip '" + ch.clips[clip].name + "' t=" + t + " s";
    }
    std::printf(
        "posed %zu skin vertices of %s at %s%s (%s attachment, %zu of %zu keypose sets active%s), wrote %s\n",
        skin.size(), P.c_str(), when.c_str(), args->pose.empty() ? "" : " with --pose overrides",
        attachment_mode_name(doc.attachment.mode), active, doc.keyposes.size(),
        doc.sim.enabled && clip >= 0 ? ", cage simulated" : "", args->out.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
