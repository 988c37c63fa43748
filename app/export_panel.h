// The editor's File > Export window: format (glb, obj, json), mode, the clips to bake, frames per
// second, the output path (typed, or chosen with the file browser), and Export, which starts the
// workspace's background export (app/workspace/workspace_export.cpp) and shows its progress bar and
// Cancel. The report (what was written, frames, morph targets, size, errors against the live rig)
// shows in the window and the log; a failure shows in the error modal, and the document is never
// changed. ImGui only; the work is core's.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/cage_tools.h"
#include "app/workspace/scene.h"
#include "app/workspace/workspace.h"
#include "app/file_browser.h"
#include "core/export/rig_exporter.h"

namespace cagewrap::app {

class ExportPanel {
 public:
  // Shows the window; the first time for a document, the output path is set beside its project
  // (or character) file.
  void open(const Scene& scene);
  bool visible() const { return visible_; }
  void draw(Workspace& ws);
  // Shows `request` in the window (format, mode, clips, fps, output), as a script's export line set it.
  void show(const Scene& scene, const ExportRequest& request);
  const ExportRequest& request() const { return request_; }
  // What the window's Export button starts: the settings shown, the clips checked.
  ExportRequest shown_request() const;
  // The window's Browse... button, for scripts.
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
};

}  // namespace cagewrap::app
