// The workspace's export (app/workspace/workspace.h "export"): the document written as a rig in the
// background (a bind of its own, then core/export/rig_exporter.h's run_export), with progress and
// Cancel; the report goes to the log, a failure to the error modal, and the document is never changed.
// The Export window and the actions export, export_nowait and export_cancel run these.
#include <chrono>
#include <cstdio>

#include "app/workspace/workspace.h"
#include "core/rig/rig.h"

namespace cagewrap::app {

namespace {

double now_seconds() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace

Result<ExportRequest> Workspace::parse_export(std::istringstream& in) const {
  auto bad = [](const std::string& m) -> Result<ExportRequest> { return make_error(ErrorCode::kInvalidArgument, "export: " + m); };
  if (!scene_) return bad("no document is open");
  std::string format, mode, clips, path;
  double fps = 0.0;
  if (!(in >> format >> mode >> fps >> clips)) return bad("export FORMAT MODE|- FPS all|CLIP[,CLIP] PATH");
  std::getline(in >> std::ws, path);
  path.erase(path.find_last_not_of(" \t\r") + 1);
  ExportRequest request;
  request.out = path;
  request.options.fps = fps;
  request.options.max_targets = export_correctives.max_targets;
  request.options.max_error = export_correctives.max_error;
  request.options.max_influences = export_correctives.max_influences;
  request.options.optimize = export_correctives.optimize;
  request.options.quantize = export_correctives.quantize;
  if (export_correctives.pose_driven) request.options.correctives = ExportOptions::Correctives::kPoseDriven;
  if (!parse_export_format(format, request.format)) return bad("format '" + format + "' is not glb, obj or json");
  if (mode != "-" && !parse_export_mode(mode, request.options.mode)) return bad("unknown mode '" + mode + "'");
  const Character& ch = *scene_->doc().character;
  if (clips == "all")
    for (size_t c = 0; c < ch.clips.size(); ++c) request.options.clips.push_back(static_cast<int32_t>(c));
  for (size_t start = 0; clips != "all" && start < clips.size();) {
    const size_t comma = std::min(clips.find(',', start), clips.size());
    const std::string name = clips.substr(start, comma - start);
    const int32_t c = ch.find_clip(name);
    if (c < 0) return bad("no clip '" + name + "'");
    request.options.clips.push_back(c);
    start = comma + 1;
  }
  if (!export_correctives.hold_out.empty()) {
    request.options.hold_out = ch.find_clip(export_correctives.hold_out);
    if (request.options.hold_out < 0) return bad("export_pose_driven holds out '" + export_correctives.hold_out + "', which is no clip");
  }
  return request;
}

void Workspace::refuse_export(const std::string& message) {
  export_.outcome = message;
  ++export_.failures;
  log("error: " + message, true);
}

bool Workspace::start_export(const ExportRequest& request) {
  if (!scene_) return false;
  ExportState& e = export_;
  auto refuse = [&](const std::string& message) {
    e.outcome = message;
    ++e.failures;
    report_error("export: " + message);
    return false;
  };
  if (e.job) return refuse("an export is running already: wait for it or cancel it");
  e.request = request;
  e.report.reset();
  e.outcome.clear();
  const Document& doc = scene_->work();  // every deformer
  if (!doc.cage) return refuse("the document has no cage yet: build or import one first (Cage menu)");
  if (request.format != ExportFormat::kJson && doc.character->clips.empty()) return refuse("the character has no animation clip to bake");
  if (request.format != ExportFormat::kJson && request.options.clips.empty()) return refuse("choose at least one clip to bake");
  if (auto bad = check_export_path(request); !bad.empty()) return refuse(bad);
  e.started = now_seconds();
  const bool needs_rig = request.format != ExportFormat::kJson || doc.attachment.mode == AttachmentMode::kFitted;
  std::shared_ptr<const Binding> bound = needs_rig ? scene_->binding_for_jobs() : nullptr;
  log("exporting " + export_kind_name(request) + " to " + request.out + (bound ? " (with the current binding)" : "") + " ...");
  e.job = std::make_unique<BackgroundTask<ExportReport>>(
      "export", [doc, request, needs_rig, bound](const BackgroundTask<ExportReport>::Progress& progress,
                                                 const std::atomic<bool>& cancel) -> Result<ExportReport> {
        // A rig of its own: the export must not share the editor's deformer across threads. From the
        // scene's binding when it is the document's; else bound here (about a quarter of the time).
        const double bind_share = needs_rig && !bound ? 0.25 : 0.0;
        std::optional<Rig> rig;
        if (needs_rig) {
          BindProgress bp;
          bp.cancel = &cancel;
          bp.on_progress = [&progress, bind_share](double s) { progress("binding", bind_share * s); };
          auto made = bound ? Rig::create(doc, Binding(*bound)) : Rig::create(doc, bp);
          if (!made) return made.error();
          rig.emplace(std::move(made).value());
        }
        ExportProgress ep;
        ep.cancel = &cancel;
        ep.on_progress = [&progress, bind_share](const char* stage, size_t done, size_t total, double share) {
          char text[64];
          std::snprintf(text, sizeof text, "%s %zu/%zu", stage, done, total);
          progress(text, bind_share + (1.0 - bind_share) * share);
        };
        return run_export(doc, rig ? &*rig : nullptr, request, ep);
      });
  return true;
}

void Workspace::cancel_export() {
  if (export_.job) export_.job->cancel();
}

void Workspace::poll_export() {
  ExportState& e = export_;
  if (!e.job || !e.job->done()) return;
  auto& r = e.job->result();
  e.seconds = now_seconds() - e.started;
  if (!r.ok()) {
    if (r.error().code == ErrorCode::kCancelled) {
      e.outcome = "cancelled; nothing was written";
      log("export cancelled; nothing was written");
    } else {
      e.outcome = r.error().message;
      ++e.failures;
      report_error("export: " + r.error().message);
    }
    e.job.reset();
    return;
  }
  e.report = std::move(r).value();
  e.job.reset();
  char secs[32];
  std::snprintf(secs, sizeof secs, " in %.1f s", e.seconds);
  log("exported " + e.report->what + ": " + e.report->summary + secs);
  for (const std::string& line : e.report->error_lines) log("  " + line);
  for (const std::string& w : e.report->warnings) log("warning: export: " + w);
}

}  // namespace cagewrap::app
