// What the editor shows and animates: the character, its cage, the binding, and the pose of the
// current frame. No GL or ImGui here: the viewport draws from it, panels edit it.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/animation.h"
#include "core/cage.h"
#include "core/cage_attachment.h"
#include "core/character.h"
#include "core/deformer.h"
#include "core/document.h"
#include "core/history.h"
#include "core/registration.h"

namespace cagewrap::app {

// A bind running on a worker thread, with progress and cancel; the UI polls it every frame.
class BindJob {
 public:
  BindJob(std::vector<glm::vec3> skin, Cage cage, BindParams params);
  ~BindJob();
  double progress() const { return progress_.load(); }
  bool done() const { return done_.load(); }
  void cancel() { cancel_ = true; }
  // Valid once done(): the binding, or the error (kCancelled when cancelled).
  Result<Binding>& result() { return *result_; }

 private:
  std::vector<glm::vec3> skin_;
  Cage cage_;
  BindParams params_;
  std::atomic<double> progress_{0.0};
  std::atomic<bool> cancel_{false}, done_{false};
  std::optional<Result<Binding>> result_;
  std::thread thread_;
};

struct Scene {
  explicit Scene(Document doc) : history(std::move(doc)) {}
  History history;  // the document and its undo steps
  std::optional<Document> live;  // during a drag: the document being edited (history holds its start)
  const Document& doc() const { return live ? *live : history.current(); }

  std::vector<glm::vec3> skin_rest;  // #V bind pose, every primitive in file order
  PolyMesh skin_topology;            // combined triangles
  std::optional<CageAttachment> attachment;
  BindParams params;                 // as edited in the panel (committed to the document on release)
  std::unique_ptr<Binding> binding;  // the registration in use
  std::shared_ptr<const Cage> bound_cage;  // the rest cage it was made from
  std::optional<Deformer> deformer;
  std::unique_ptr<BindJob> job;

  // animation (view state: never undone)
  int32_t clip = -1;
  ClipPlayer player;

  // the current frame
  std::vector<glm::vec3> cage_posed, skin_posed, joint_heads;
  std::vector<glm::dmat3> cage_linear;
  std::vector<glm::mat4> cage_skinning;  // skinning matrix of each cage vertex's joint
  std::vector<std::array<uint32_t, 2>> bones;
  double deform_ms = 0.0;
  bool skin_from_cage = false;  // false: the file's own linear blend skinning is shown

  bool needs_rebind() const;
  // Call after the document changed (undo, redo, load): re-attaches and rebinds what it must.
  void document_changed();
  // Poses skeleton and cage at the player's time and deforms the skin.
  void update_pose();
  void start_bind();
  // Polls the running job; returns a message when it finished (bound, failed or cancelled).
  std::optional<std::string> poll_bind();
  // Replaces the cage with one read from a mesh file (.obj .ply .off .stl), as one undo step: it
  // follows the skeleton and is bound like one opened with --cage; offsets and set edits made for
  // the old cage go with it. Returns the message to log; errors name the file.
  Result<std::string> import_cage(const std::string& path);
  // Moves cage vertices of the driver by a world-space displacement at the current pose (stored as
  // offsets in each vertex's joint bind space) and returns the new document (not yet in history).
  Document moved(const Document& from, std::span<const uint32_t> vertices, const glm::dvec3& world_delta) const;

 private:
  std::shared_ptr<const Cage> pending_cage_;   // the cage the running job binds
  std::shared_ptr<const Cage> attached_cage_;  // the cage `attachment` was made for
};

// Loads a character file (glTF) and optionally a cage; errors name the file.
Result<std::unique_ptr<Scene>> load_scene(const std::string& character_path, const std::string& cage_path);
// Opens a saved project (.cagewrap); warnings are appended.
Result<std::unique_ptr<Scene>> load_project_scene(const std::string& project_path, std::vector<std::string>& warnings);
// The demo character shipped in assets/ (found beside the executable or the source tree), or
// generated in-process when the file cannot be found.
std::string demo_character_path();
// The cage made for it by `cagewrap cage` (assets/demo_cage.obj beside the character), or "".
std::string demo_cage_path(const std::string& character_path);

}  // namespace cagewrap::app
