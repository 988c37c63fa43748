// The editor's File > Export window: format (glb, obj, json), mode, the clips to bake, frames per
// second, the output path (typed, or chosen with the file browser), and Export, which runs in the
// background (bind, then core/export/rig_exporter.h's run_export) with a progress bar and Cancel. The
// report (what was written, frames, morph targets, size, errors against the live rig) shows in the
// window and the log; a failure shows in the error modal, and the document is never changed.
// ImGui only; the work is core's.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/workspace/background_task.h"
#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "app/file_browser.h"
#include "core/export/rig_exporter.h"

namespace cagewrap::app {

class ExportPanel {
 public:
  // Shows the window; the first time for a document, the output path is set beside its project
  // (or character) file.
  void open(const Scene& scene);
  bool visible() const { return visible_; }
  void draw(Scene& scene, const EditorHooks& hooks);
  // Finishes a background export: the report into the window and the log, or the error.
  void poll(const EditorHooks& hooks);
  bool busy() const { return job_ != nullptr; }
  // Exports refused or failed (not cancelled) since the editor started: a scripted run exits non-zero.
  int failures() const { return failures_; }
  void cancel() {
    if (job_) job_->cancel();
  }

  // Starts exporting the scene's document as `request` asks (scripts use it; the window's Export
  // button too). False (shown as an error) when it cannot start: a bad path, no cage, no clip.
  bool start(const Scene& scene, const ExportRequest& request, const EditorHooks& hooks);
  const ExportRequest& request() const { return request_; }
  // What the window's Export button starts: the settings shown, the clips checked.
  ExportRequest shown_request() const;
  // The window's buttons, for scripts: Export (false when it cannot start), Browse...
  bool press_export(const Scene& scene, const EditorHooks& hooks) {
    return start(scene, shown_request(), hooks);
  }
  void press_browse() { browse_requested_ = true; }

  // The Browse button asked for a file: the purpose for the current format, the folder and name to
  // start with. The editor opens its file browser and hands the choice to set_output.
  struct BrowseRequest {
    FilePurpose purpose;
    std::string near_path, file_name;
  };
  std::optional<BrowseRequest> take_browse_request();
  void set_output(const std::string& path);

 private:
  void default_output(const Scene& scene);
  void set_format(ExportFormat format);

  bool visible_ = false;
  ExportRequest request_;
  const void* defaults_for_ = nullptr;  // the character the output path was last defaulted for
  std::vector<char> clip_on_;           // per clip of the character: bake it
  char out_field_[4096] = {};
  bool browse_requested_ = false;
  std::unique_ptr<BackgroundTask<ExportReport>> job_;
  std::optional<ExportReport> report_;  // the last export's
  int failures_ = 0;
  std::string last_outcome_;            // "cancelled", or the last error, shown in the window
  double started_ = 0.0, seconds_ = 0.0;
};

}  // namespace cagewrap::app
