#include "app/workspace/history.h"

namespace cagewrap {

History::History(Document initial, size_t memory_cap_bytes) : saved_revision_(initial.revision), cap_(memory_cap_bytes) {
  entries_.push_back({"", std::move(initial), 0});
  entries_.back().own_bytes = estimated_own_bytes(entries_.back().doc);
  account(entries_.back(), true);
}

void History::share(const void* key, size_t bytes, bool add) {
  if (!key) return;
  Shared& s = shared_[key];
  if (add) {
    if (s.refs++ == 0) {
      s.bytes = bytes;
      bytes_ += bytes;
    }
  } else if (--s.refs == 0) {
    bytes_ -= s.bytes;
    shared_.erase(key);
  }
}

void History::account(const Entry& e, bool add) {
  if (add) bytes_ += e.own_bytes;
  else bytes_ -= e.own_bytes;
  const Character* character = e.doc.character.get();
  const Cage* cage = e.doc.cage.get();
  // the estimate is only computed the first time an address is seen
  share(character, add && character && !shared_.contains(character) ? estimated_bytes(*character) : 0, add);
  share(cage, add && cage && !shared_.contains(cage) ? estimated_bytes(*cage) : 0, add);
  const std::string* embedded = e.doc.embedded_character.get();
  share(embedded, add && embedded && !shared_.contains(embedded) ? embedded->size() : 0, add);
}

bool History::push(std::string label, Document doc) {
  drag_start_.reset();
  if (doc.revision == current().revision) return false;
  while (can_redo()) {
    account(entries_.back(), false);
    entries_.pop_back();
  }
  entries_.push_back({std::move(label), std::move(doc), 0});
  entries_.back().own_bytes = estimated_own_bytes(entries_.back().doc);
  account(entries_.back(), true);
  cursor_ = entries_.size() - 1;
  enforce_cap();
  return true;
}

void History::enforce_cap() {
  while (bytes_ > cap_ && cursor_ > 0) {
    account(entries_.front(), false);
    entries_.pop_front();
    --cursor_;
  }
}

void History::set_memory_cap(size_t bytes) {
  cap_ = bytes;
  enforce_cap();
}

const Document& History::undo() {
  drag_start_.reset();
  if (can_undo()) --cursor_;
  return current();
}

const Document& History::redo() {
  drag_start_.reset();
  if (can_redo()) ++cursor_;
  return current();
}

std::string History::undo_label() const { return can_undo() ? "Undo " + entries_[cursor_].label : "Undo"; }
std::string History::redo_label() const { return can_redo() ? "Redo " + entries_[cursor_ + 1].label : "Redo"; }

void History::begin(const Document& doc) { drag_start_ = doc; }

bool History::commit(std::string label, const Document& doc) {
  if (!drag_start_) return false;
  bool changed = doc.revision != drag_start_->revision;
  drag_start_.reset();
  return changed && push(std::move(label), doc);
}

Document History::cancel() {
  Document start = drag_start_ ? std::move(*drag_start_) : current();
  drag_start_.reset();
  return start;
}

void History::mark_saved(const std::string& project_path) {
  saved_revision_ = current().revision;
  for (Entry& e : entries_) {
    bytes_ -= e.own_bytes;
    e.doc.project_path = project_path;
    e.own_bytes = estimated_own_bytes(e.doc);
    bytes_ += e.own_bytes;
  }
  if (drag_start_) drag_start_->project_path = project_path;
}

void History::mark_unsaved() { saved_revision_ = 0; }

}  // namespace cagewrap
