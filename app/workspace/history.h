// Undo and redo of Document snapshots. Snapshots share the big immutable data (character, cage),
// so a step costs what it changed; a memory cap drops the oldest steps (Blender's undo_memory_limit).
//
// Use from the editor (the editor owns the live Document `doc`):
//   doc = with_params(doc, p); history.push("Change epsilon", doc);       // one-shot edit
//   if (ImGui::IsItemActivated()) history.begin(doc);                      // a drag starts
//   doc = with_cage_positions(doc, moved);                                 // every frame of it
//   if (ImGui::IsItemDeactivatedAfterEdit()) history.commit("Move vertices", doc);  // one step
//   if (escape pressed while dragging) doc = history.cancel();
//   if (history.can_undo()) doc = history.undo();   // menu item: history.undo_label()
//   save_project(path, doc) ok -> history.mark_saved(path); doc = history.current();
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>

#include "core/document/document.h"

namespace cagewrap {

inline constexpr size_t kDefaultHistoryBytes = size_t{512} << 20;

class History {
 public:
  // `initial` is the first state and the save point (not dirty).
  explicit History(Document initial, size_t memory_cap_bytes = kDefaultHistoryBytes);

  const Document& current() const { return entries_[cursor_].doc; }

  // Records `doc` as the new current state reached by the step `label` ("Move vertices"); drops
  // the redo steps and any open drag. Returns false (and records nothing) when doc.revision is the
  // current one (nothing changed).
  bool push(std::string label, Document doc);

  bool can_undo() const { return cursor_ > 0; }
  bool can_redo() const { return cursor_ + 1 < entries_.size(); }
  // Step back/forward and return the new current state; no-ops at either end. Cancel an open drag.
  const Document& undo();
  const Document& redo();
  // Menu text: "Undo Move vertices" / "Redo Change epsilon"; "Undo" / "Redo" when there is none.
  std::string undo_label() const;
  std::string redo_label() const;
  size_t undo_steps() const { return cursor_; }
  size_t redo_steps() const { return entries_.size() - 1 - cursor_; }

  // One drag = one step. begin() at activation remembers the state before the drag; commit() at
  // deactivation pushes the final state (returns false when the drag changed nothing or none was
  // open); cancel() closes the drag and returns the state to restore.
  void begin(const Document& doc);
  bool commit(std::string label, const Document& doc);
  Document cancel();
  bool dragging() const { return drag_start_.has_value(); }
  // The state the open drag started from (the one copy of it), or null when no drag is open.
  const Document* drag_start() const { return drag_start_ ? &*drag_start_ : nullptr; }

  // The current state was written to `project_path`: it becomes the save point, and every snapshot
  // learns the path (where the work lives is not an undoable edit). Revisions are unchanged.
  void mark_saved(const std::string& project_path);
  // No state is saved (a document recovered from an autosave): dirty until the next save.
  void mark_unsaved();
  // Whether the current state (or the live document, during a drag) differs from the save point.
  // Undoing back to the saved state is clean again; a save point dropped by the cap or by a new
  // branch can never come back, so it stays dirty until the next save.
  bool dirty() const { return current().revision != saved_revision_; }
  bool dirty(const Document& live) const { return live.revision != saved_revision_; }

  // Estimated bytes held by all snapshots, each shared character and cage counted once.
  size_t memory_bytes() const { return bytes_; }
  size_t memory_cap() const { return cap_; }
  // Drops the oldest undo steps until the estimate fits (the current state always stays).
  void set_memory_cap(size_t bytes);

 private:
  struct Entry {
    std::string label;  // the step that led to this state
    Document doc;
    size_t own_bytes = 0;
  };
  struct Shared {
    size_t bytes = 0;
    size_t refs = 0;
  };
  void account(const Entry& e, bool add);
  void share(const void* key, size_t bytes, bool add);
  void enforce_cap();

  std::deque<Entry> entries_;
  size_t cursor_ = 0;
  std::optional<Document> drag_start_;
  uint64_t saved_revision_ = 0;
  size_t cap_;
  size_t bytes_ = 0;
  std::unordered_map<const void*, Shared> shared_;  // by address of the shared character / cage
};

}  // namespace cagewrap
