// cagewrap cage-edit --in cage.obj --out new.obj OPERATION
//   --subdivide linear|loop [--levels n]  uniform subdivision
//   --refine-faces 1,2,5                   local red-green refinement of those faces
//   --flip | --flip-faces 1,2              reverse the winding of every face / of those faces
//   --weld-distance d                      merge vertices closer than d
//   --merge-vertices 3,4,9                 merge those vertices into one at their centroid
// Exactly one operation per call. Prints what changed; writes nothing on error.
#include <cstdio>

#include "app/cli_common.h"
#include "app/commands.h"
#include "core/document/cage_edit.h"
#include "core/document/cage_subdivide.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap::app {

namespace {

std::string join_ids(std::span<const uint32_t> ids, size_t most) {
  std::string s;
  for (size_t i = 0; i < ids.size() && i < most; ++i) s += (i ? " " : "") + std::to_string(ids[i]);
  if (ids.size() > most) s += " ... (" + std::to_string(ids.size() - most) + " more)";
  return s;
}

void print_counts(const char* label, const Cage& c) {
  std::printf("%-17s %zu vertices, %zu faces, %zu elements\n", label, c.num_vertices(),
              c.polygons.num_faces(), c.num_elements());
}

}  // namespace

void add_cage_edit_command(CLI::App& app, int& exit_code) {
  struct Args {
    std::string in, out, subdivide;
    uint32_t levels = 1;
    std::vector<uint32_t> refine_faces, flip_faces, merge_vertices;
    bool flip = false;
    double weld_distance = 0.0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("cage-edit", "change the cage's topology: subdivide, refine, flip, weld, merge");
  cmd->add_option("--in", args->in, "cage to edit (.obj .ply .off .stl)")->required();
  cmd->add_option("--out", args->out, "edited cage to write (.obj)")->required();
  auto* subdivide = cmd->add_option("--subdivide", args->subdivide, "uniform subdivision: linear or loop")
                        ->check(CLI::IsMember({"linear", "loop"}));
  auto* levels = cmd->add_option("--levels", args->levels, "subdivision levels (with --subdivide)")
                     ->capture_default_str();
  auto* refine = cmd->add_option("--refine-faces", args->refine_faces,
                                 "faces to refine 1-to-4, neighbours split to conform (red-green)")
                     ->delimiter(',');
  auto* flip = cmd->add_flag("--flip", args->flip, "reverse the winding of every face");
  auto* flip_faces_opt =
      cmd->add_option("--flip-faces", args->flip_faces, "faces whose winding to reverse")->delimiter(',');
  auto* weld = cmd->add_option("--weld-distance", args->weld_distance, "merge vertices closer than this");
  auto* merge = cmd->add_option("--merge-vertices", args->merge_vertices,
                                "vertices to merge into one at their centroid")
                    ->delimiter(',');
  cmd->callback([=, &exit_code] {
    exit_code = 1;
    const int given = int(subdivide->count() > 0) + int(refine->count() > 0) + int(flip->count() > 0) +
                      int(flip_faces_opt->count() > 0) + int(weld->count() > 0) + int(merge->count() > 0);
    if (given != 1) {
      std::fprintf(stderr,
                   "error: give exactly one operation (--subdivide, --refine-faces, --flip, --flip-faces, "
                   "--weld-distance, --merge-vertices); %d given\n",
                   given);
      return;
    }
    if (levels->count() > 0 && subdivide->count() == 0) {
      std::fprintf(stderr, "error: --levels goes with --subdivide\n");
      return;
    }
    if (!has_extension(args->out, ".obj")) {
      std::fprintf(stderr, "error: %s: the cage is written as .obj\n", args->out.c_str());
      return;
    }
    auto cage = load_cage_or_report(args->in);
    if (!cage) return;
    Result<CageEdit> r = make_error(ErrorCode::kInvalidArgument, "no operation");
    std::string what;
    if (subdivide->count()) {
      what = "subdivide " + args->subdivide + ", " + std::to_string(args->levels) + " level(s)";
      r = args->subdivide == "loop" ? subdivide_loop(*cage, args->levels)
                                    : subdivide_linear(*cage, args->levels);
    } else if (refine->count()) {
      what = "refine faces " + join_ids(args->refine_faces, 20);
      r = refine_faces(*cage, args->refine_faces);
    } else if (flip->count()) {
      what = "flip every face";
      r = flip_all_faces(*cage);
    } else if (flip_faces_opt->count()) {
      what = "flip faces " + join_ids(args->flip_faces, 20);
      r = flip_faces(*cage, args->flip_faces);
    } else if (weld->count()) {
      what = "weld vertices closer than " + std::to_string(args->weld_distance);
      r = weld_cage_vertices(*cage, args->weld_distance);
    } else {
      what = "merge vertices " + join_ids(args->merge_vertices, 20);
      r = merge_vertices(*cage, args->merge_vertices);
    }
    if (!r) {
      report_error({r.error().code, args->in + ": " + r.error().message});
      return;
    }
    if (auto s = save_obj(args->out, r->cage.polygons.positions, r->cage.polygons); !s) {
      report_error(s.error());
      return;
    }
    std::printf("operation         %s\n", what.c_str());
    print_counts("in", *cage);
    print_counts("out", r->cage);
    std::printf("dropped faces     %zu%s%s\n", r->change.dropped_faces.size(),
                r->change.dropped_faces.empty() ? "" : ": ", join_ids(r->change.dropped_faces, 20).c_str());
    std::printf("warnings          %zu\n", r->warnings.size());
    for (size_t i = 0; i < r->warnings.size() && i < 20; ++i) std::printf("  %s\n", r->warnings[i].c_str());
    if (r->warnings.size() > 20) std::printf("  and %zu similar warnings\n", r->warnings.size() - 20);
    std::printf("wrote             %s\n", args->out.c_str());
    exit_code = 0;
  });
}

}  // namespace cagewrap::app
