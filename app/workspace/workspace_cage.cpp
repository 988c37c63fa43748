// The workspace's cage changes (app/workspace/workspace.h "the cage"): a new cage (imported, or built
// by the automatic cage in the background) and the Cage menu's topology edits. The Cage menu and the
// actions auto_cage, cage_op and import_cage run these; each change is one undo step.
#include <cstdio>
#include <filesystem>

#include "app/workspace/workspace.h"
#include "core/rig/auto_cage.h"
#include "core/document/cage_edit.h"
#include "core/io/cage_import.h"
#include "core/document/cage_subdivide.h"
#include "core/document/topology_change.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap::app {

void Workspace::replace_cage(std::shared_ptr<const Cage> cage, const std::string& label) {
  if (!scene_) return;
  const Document& before = scene_->doc();
  Document d = with_cage(before, std::move(cage));
  // a different cage: sculpted offsets and set edits named the old one's vertices and elements
  if (!d.cage_offsets.empty()) d = with_cage_offsets(d, {});
  if (!d.set_edits.empty()) d = with_set_edits(d, {});
  if (!d.attachment.overrides.empty()) {
    AttachmentSettings a = d.attachment;
    a.overrides.clear();
    d = with_attachment(d, a);
  }
  std::vector<KeyposeSet> sets = d.keyposes;  // drivers and key values stay, their vertices go
  clear_vertex_data(sets);
  if (sets != d.keyposes) d = with_keyposes(d, std::move(sets));
  scene_->apply(label, std::move(d));
  // the selection named the old cage's vertices and faces
  view.selection.cage_vertices = {};
  view.selection.cage_faces = {};
}

void Workspace::clip_cage_selection() {
  const Cage* cage = scene_ ? scene_->doc().cage.get() : nullptr;
  auto clip = [](IndexSet& set, size_t n) {
    std::vector<uint32_t> kept;
    for (uint32_t i : set)
      if (i < n) kept.push_back(i);
    if (kept.size() != set.size()) set = IndexSet(std::move(kept));
  };
  clip(view.selection.cage_vertices, cage ? cage->num_vertices() : 0);
  clip(view.selection.cage_faces, cage ? cage->polygons.num_faces() : 0);
}

std::optional<Cage> Workspace::read_cage(const std::string& path) {
  auto mesh = load_cage_mesh(path);
  if (!mesh) {
    report_error(mesh.error().message);
    return std::nullopt;
  }
  if (auto st = validate_mesh(*mesh, path); !st.ok()) {
    report_error(st.error().message);
    return std::nullopt;
  }
  auto cage = make_cage(std::move(mesh).value(), path);
  if (!cage) {
    report_error(cage.error().message);
    return std::nullopt;
  }
  return std::move(cage).value();
}

bool Workspace::import_cage(const std::string& path) {
  if (!scene_) return false;
  auto cage = read_cage(path);
  if (!cage) return false;
  const CageProblems problems = find_cage_problems(*cage);
  log("imported cage " + path + ": " + std::to_string(cage->num_vertices()) + " vertices, " + std::to_string(cage->polygons.num_faces()) +
      " faces" +
      (problems.total() ? ", " + std::to_string(problems.total()) + " problems (listed below; the bind skips bad elements)" : ", no problems"));
  for (const auto& l : problems.lines) log("warning: " + path + ": " + l);
  if (problems.lines.size() < problems.total()) log("warning: " + path + ": ... and " + std::to_string(problems.total() - problems.lines.size()) + " more");
  replace_cage(std::make_shared<const Cage>(std::move(cage).value()), "Import cage " + std::filesystem::path(path).filename().string());
  return true;
}

bool Workspace::start_auto_cage(AutoCageParams params) {
  if (!scene_) return false;
  if (auto_cage_.job) {
    log("error: an automatic cage is being built already: wait for it or cancel it", true);
    return false;
  }
  params.bind = scene_->params;
  if (auto v = validate(params); !v) {
    report_error("automatic cage: " + v.error().message);
    return false;
  }
  auto character = scene_->doc().character;
  auto_cage_.job = std::make_unique<BackgroundTask<AutoCageReport>>(
      "automatic cage", [character, params](const BackgroundTask<AutoCageReport>::Progress& progress, const std::atomic<bool>& cancel) {
        AutoCageProgress p;
        p.on_progress = [&progress](const char* stage, double share) { progress(stage, share); };
        p.cancel = &cancel;
        return build_auto_cage(*character, params, p);
      });
  return true;
}

void Workspace::cancel_auto_cage() {
  if (auto_cage_.job) auto_cage_.job->cancel();
}

void Workspace::poll_auto_cage() {
  if (!auto_cage_.job || !auto_cage_.job->done()) return;
  auto& r = auto_cage_.job->result();
  if (!r.ok()) {
    if (r.error().code == ErrorCode::kCancelled) log("automatic cage cancelled");
    else report_error(r.error().message);
    auto_cage_.job.reset();
    return;
  }
  AutoCageReport report = std::move(r).value();
  auto_cage_.job.reset();
  auto cage = make_cage(report.cage, "automatic cage");
  if (!cage) {
    report_error(cage.error().message);
    return;
  }
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "automatic cage: %u faces, %u vertices in %.2f s; largest skin-to-cage distance %.4g, %u skin points outside; "
                "cage quality %.1f%%",
                report.faces, report.vertices, report.seconds, report.max_distance, report.outside_points, 100.0 * report.quality);
  log(buf);
  for (const auto& w : report.warnings) log("warning: " + w);
  report.cage = PolyMesh{};  // the document holds it
  auto_cage_.report = std::move(report);
  auto_cage_.cage = std::make_shared<const Cage>(std::move(cage).value());
  ++auto_cage_.builds;
  replace_cage(auto_cage_.cage, "Automatic cage");
}

namespace {

// The operations by name: what each needs from the selection and its undo step's label.
struct CageOperation {
  const char* name;
  const char* label;
};
constexpr CageOperation kCageOperations[] = {
    {"merge", "Merge vertices"},         {"weld", "Weld vertices"},       {"flip", "Flip faces"},
    {"flip_all", "Flip all faces"},      {"linear", "Subdivide (linear)"}, {"loop", "Subdivide (Loop)"},
    {"refine", "Refine faces"},          {"triangulate", "Triangulate"}};

}  // namespace

bool Workspace::cage_operation(const std::string& op, double arg) {
  if (!scene_) return false;
  if (!scene_->doc().cage) {
    report_error("there is no cage to edit: build or import one first (Cage menu)");
    return false;
  }
  const Cage& cage = *scene_->doc().cage;
  const Selection& sel = view.selection;
  const auto levels = static_cast<uint32_t>(arg >= 1 ? arg : 1);
  const CageOperation* what = nullptr;
  for (const auto& o : kCageOperations)
    if (op == o.name) what = &o;
  if (!what) {
    std::string names;
    for (const auto& o : kCageOperations) names += std::string(names.empty() ? "" : ", ") + o.name;
    report_error("unknown cage operation '" + op + "' (" + names + ")");
    return false;
  }
  Result<CageEdit> edit = op == "merge"      ? merge_vertices(cage, sel.cage_vertices.indices())
                          : op == "weld"     ? weld_cage_vertices(cage, arg)
                          : op == "flip"     ? flip_faces(cage, sel.cage_faces.indices())
                          : op == "flip_all" ? flip_all_faces(cage)
                          : op == "linear"   ? subdivide_linear(cage, levels)
                          : op == "loop"     ? subdivide_loop(cage, levels)
                          : op == "refine"   ? refine_faces(cage, sel.cage_faces.indices())
                                             : triangulate_cage(cage);
  if (!edit) {
    report_error(std::string(what->label) + ": " + edit.error().message);
    return false;
  }
  auto doc = apply_topology_change(scene_->doc(), *edit);
  if (!doc) {
    report_error(std::string(what->label) + ": " + doc.error().message);
    return false;
  }
  for (const auto& w : edit->warnings) log(std::string("warning: ") + what->label + ": " + w);
  const size_t faces_before = cage.polygons.num_faces();
  // a local edit keeps the distance scale h the skin is bound with (a scale of 0 would follow the mean
  // edge length, which the edit changes, and every weight with it): the points out of reach of the
  // changed faces keep their rows (core/deform/rest_edit.h rebind_new_topology); a subdivision of the
  // whole cage lets h follow
  const double scale_before = doc->params.scale;
  if (op != "linear" && op != "loop") doc = scene_->keep_bound_scale(std::move(doc).value());
  if (doc->params.scale != scale_before) {
    char note[160];
    std::snprintf(note, sizeof note, "%s: scale h fixed to the bound %.5g so that the edit stays local", what->label,
                  doc->params.scale);
    log(note);
  }
  scene_->apply(what->label, std::move(doc).value());
  clip_cage_selection();  // ids past the new counts named the old topology
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s: %zu -> %zu faces, %zu vertices", what->label, faces_before, scene_->doc().cage->polygons.num_faces(),
                scene_->doc().cage->num_vertices());
  log(buf);
  return true;
}

}  // namespace cagewrap::app
