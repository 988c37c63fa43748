#include "core/deform/set_editing.h"

#include <algorithm>
#include <iterator>
#include <map>

namespace cagewrap {

const char* set_edit_mode_name(SetEditMode mode) {
  switch (mode) {
    case SetEditMode::kRemove:
      return "remove";
    case SetEditMode::kAdd:
      return "add";
    case SetEditMode::kOnly:
      return "only";
    case SetEditMode::kReset:
      return "reset";
  }
  return "?";
}

bool parse_set_edit_mode(const std::string& name, SetEditMode& out) {
  for (SetEditMode m : {SetEditMode::kRemove, SetEditMode::kAdd, SetEditMode::kOnly, SetEditMode::kReset})
    if (name == set_edit_mode_name(m)) {
      out = m;
      return true;
    }
  return false;
}

namespace {

void sort_unique(std::vector<uint32_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// a - b, both sorted
std::vector<uint32_t> minus(const std::vector<uint32_t>& a, std::span<const uint32_t> b) {
  std::vector<uint32_t> out;
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

std::vector<uint32_t> plus(const std::vector<uint32_t>& a, std::span<const uint32_t> b) {
  std::vector<uint32_t> out;
  std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

// In place; false when no rule is left.
bool make_canonical(SetEdit& e) {
  sort_unique(e.include);
  if (e.only) {
    e.exclude.clear();
    return true;
  }
  sort_unique(e.exclude);
  e.exclude = minus(e.exclude, e.include);
  return !e.exclude.empty() || !e.include.empty();
}

bool same_rules(const SetEdit& a, const SetEdit& b) {
  return a.only == b.only && a.exclude == b.exclude && a.include == b.include;
}

}  // namespace

std::vector<SetEdit> canonical_set_edits(std::span<const SetEdit> edits) {
  std::vector<const SetEdit*> last;  // the last edit of each point, by point
  last.reserve(edits.size());
  for (const SetEdit& e : edits) last.push_back(&e);
  std::stable_sort(last.begin(), last.end(),
                   [](const SetEdit* a, const SetEdit* b) { return a->point < b->point; });
  std::vector<SetEdit> out;
  out.reserve(last.size());
  for (size_t i = 0; i < last.size(); ++i) {
    if (i + 1 < last.size() && last[i + 1]->point == last[i]->point) continue;  // a later one wins
    SetEdit e = *last[i];
    if (make_canonical(e)) out.push_back(std::move(e));
  }
  return out;
}

std::vector<uint32_t> face_elements(const Cage& cage, const IndexSet& faces) {
  std::vector<uint32_t> out;
  for (uint32_t e = 0; e < cage.element_face.size(); ++e)
    if (faces.contains(cage.element_face[e])) out.push_back(e);
  return out;
}

std::vector<glm::vec3> face_centroids(const PolyMesh& mesh) {
  std::vector<glm::vec3> out(mesh.num_faces());
  for (size_t f = 0; f < mesh.num_faces(); ++f) {
    glm::dvec3 c(0.0);
    auto corners = mesh.face(f);
    for (uint32_t v : corners) c += glm::dvec3(mesh.positions[v]);
    out[f] = glm::vec3(corners.empty() ? c : c / double(corners.size()));
  }
  return out;
}

// Applies `mode` to each target point with its elements (ascending by point), into result.edits and
// result.changed_points.
static void apply_to_targets(std::span<const SetEdit> edits, SetEditMode mode, const std::map<uint32_t, std::vector<uint32_t>>& targets,
                             SetEditResult& result) {
  std::vector<SetEdit> current = canonical_set_edits(edits);
  auto it = current.begin();
  std::vector<SetEdit> out;
  out.reserve(current.size() + targets.size());
  for (const auto& [p, elements] : targets) {
    for (; it != current.end() && it->point < p; ++it) out.push_back(std::move(*it));
    const bool had = it != current.end() && it->point == p;
    SetEdit before = had ? std::move(*it++) : SetEdit{p, {}, {}};
    SetEdit after = before;
    switch (mode) {
      case SetEditMode::kRemove:
        after.include = minus(after.include, elements);
        if (!after.only) after.exclude = plus(after.exclude, elements);
        break;
      case SetEditMode::kAdd:
        after.include = plus(after.include, elements);
        after.exclude = minus(after.exclude, elements);
        break;
      case SetEditMode::kOnly:
        after = SetEdit{p, {}, elements, true};
        break;
      case SetEditMode::kReset:
        after = SetEdit{p, {}, {}};
        break;
    }
    const bool keep = make_canonical(after);
    if (keep != had || (keep && !same_rules(before, after))) result.changed_points.push_back(p);
    if (keep) out.push_back(std::move(after));
  }
  for (; it != current.end(); ++it) out.push_back(std::move(*it));
  result.edits = std::move(out);
}

Result<SetEditResult> apply_set_edit(std::span<const SetEdit> edits, SetEditMode mode, const IndexSet& points,
                                     const IndexSet& faces, const Cage& cage, size_t num_points,
                                     const SetEditMirror& mirror) {
  const size_t num_faces = cage.polygons.num_faces();
  if (!points.empty() && points.indices().back() >= num_points)
    return make_error(ErrorCode::kIndexOutOfRange, "skin point " + std::to_string(points.indices().back()) +
                                                       " is out of range: the skin has " +
                                                       std::to_string(num_points) + " points");
  if (!faces.empty() && faces.indices().back() >= num_faces)
    return make_error(ErrorCode::kIndexOutOfRange, "face " + std::to_string(faces.indices().back()) +
                                                       " is out of range: the cage has " +
                                                       std::to_string(num_faces) + " faces");
  if (mode != SetEditMode::kReset && faces.empty() && !points.empty())
    return make_error(ErrorCode::kInvalidArgument, std::string("no cage faces given to ") +
                                                       set_edit_mode_name(mode) + " for the selected points");
  SetEditResult result;
  // the elements each affected point takes: the faces', and the mirrored faces' for mirrored points
  std::map<uint32_t, std::vector<uint32_t>> targets;
  const std::vector<uint32_t> direct = face_elements(cage, faces);
  for (uint32_t p : points) targets[p] = direct;
  if (mirror.enabled()) {
    MirrorResult mp = mirror.points->mirror(points);
    MirrorResult mf = mirror.faces->mirror(faces);
    result.unmatched_points = std::move(mp.unmatched);
    result.unmatched_faces = std::move(mf.unmatched);
    const std::vector<uint32_t> mirrored = face_elements(cage, mf.mirrored);
    for (uint32_t p : mp.mirrored) {
      if (p >= num_points) continue;
      auto [it, fresh] = targets.try_emplace(p, mirrored);
      if (!fresh) it->second = plus(it->second, mirrored);
    }
  }

  apply_to_targets(edits, mode, targets, result);
  return result;
}

Result<SetEditResult> apply_element_set_edit(std::span<const SetEdit> edits, SetEditMode mode, const IndexSet& points,
                                             std::span<const uint32_t> elements, size_t num_points, size_t num_elements) {
  if (!points.empty() && points.indices().back() >= num_points)
    return make_error(ErrorCode::kIndexOutOfRange, "skin point " + std::to_string(points.indices().back()) +
                                                       " is out of range: the skin has " + std::to_string(num_points) + " points");
  std::vector<uint32_t> sorted(elements.begin(), elements.end());
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  if (!sorted.empty() && sorted.back() >= num_elements)
    return make_error(ErrorCode::kIndexOutOfRange, "element " + std::to_string(sorted.back()) + " is out of range: there are " +
                                                       std::to_string(num_elements));
  if (mode != SetEditMode::kReset && sorted.empty() && !points.empty())
    return make_error(ErrorCode::kInvalidArgument, std::string("no elements given to ") + set_edit_mode_name(mode) +
                                                       " for the selected points");
  SetEditResult result;
  std::map<uint32_t, std::vector<uint32_t>> targets;
  for (uint32_t p : points) targets[p] = sorted;
  apply_to_targets(edits, mode, targets, result);
  return result;
}

}  // namespace cagewrap
