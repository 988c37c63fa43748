#include "app/workspace/actions.h"

namespace cagewrap::app {

void ActionTable::add(Action action) {
  std::string name = action.name;
  actions_[std::move(name)] = std::move(action);
}

const Action* ActionTable::find(std::string_view name) const {
  auto it = actions_.find(name);
  return it == actions_.end() ? nullptr : &it->second;
}

ActionTable::Result ActionTable::run(const std::string& line, bool have_document) const {
  Result r;
  std::istringstream in(line);
  in >> r.name;
  if (r.name.empty() || r.name[0] == '#') return r;
  r.action = find(r.name);
  if (!r.action) {
    r.outcome = Outcome::kUnknown;
    return r;
  }
  if (r.action->needs_document && !have_document) {
    r.outcome = Outcome::kNeedsDocument;
    return r;
  }
  r.action->run(in);
  r.outcome = Outcome::kRan;
  return r;
}

bool ActionTable::run(std::string_view name, const std::string& args) const {
  const Action* a = find(name);
  if (!a) return false;
  std::istringstream in(args);
  a->run(in);
  return true;
}

std::vector<const Action*> ActionTable::list() const {
  std::vector<const Action*> out;
  out.reserve(actions_.size());
  for (const auto& [name, a] : actions_) out.push_back(&a);
  return out;
}

std::string ActionTable::reference() const {
  std::string out = "| action | arguments | what it does |\n|---|---|---|\n";
  for (const auto& [name, a] : actions_) {
    std::string usage = a.usage;
    for (size_t p = 0; (p = usage.find('|', p)) != std::string::npos; p += 2) usage.replace(p, 1, "\\|");
    out += "| `" + name + "` | " + (usage.empty() ? "" : "`" + usage + "`") + " | " + a.help +
           (a.needs_document ? "" : " (works with no document open)") + " |\n";
  }
  return out;
}

}  // namespace cagewrap::app
