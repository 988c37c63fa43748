#include "core/document/topology_change.h"

#include "core/cage/cage_attachment.h"
#include "core/cage/keyposes.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <memory>
#include <optional>

#include "core/base/check.h"

namespace cagewrap {

namespace {

using P2 = std::array<double, 2>;

double cross2(const P2& o, const P2& a, const P2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

double polygon_area(const std::vector<P2>& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const P2& u = p[i];
    const P2& v = p[(i + 1) % p.size()];
    a += u[0] * v[1] - v[0] * u[1];
  }
  return 0.5 * a;
}

// Area of the intersection of two triangles (either orientation): Sutherland-Hodgman.
double overlap_area(std::array<P2, 3> subject, std::array<P2, 3> clip) {
  if (cross2(clip[0], clip[1], clip[2]) < 0) std::swap(clip[1], clip[2]);
  std::vector<P2> poly(subject.begin(), subject.end()), next;
  for (int i = 0; i < 3 && !poly.empty(); ++i) {
    const P2& a = clip[i];
    const P2& b = clip[(i + 1) % 3];
    next.clear();
    for (size_t j = 0; j < poly.size(); ++j) {
      const P2& p = poly[j];
      const P2& q = poly[(j + 1) % poly.size()];
      const double sp = cross2(a, b, p), sq = cross2(a, b, q);
      if (sp >= 0) next.push_back(p);
      if ((sp >= 0) != (sq >= 0)) {
        const double t = sp / (sp - sq);
        next.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
      }
    }
    poly.swap(next);
  }
  return poly.size() < 3 ? 0.0 : std::abs(polygon_area(poly));
}

// Squared distance from p to triangle t in the plane.
double distance2_to_triangle(const P2& p, std::array<P2, 3> t) {
  if (cross2(t[0], t[1], t[2]) < 0) std::swap(t[1], t[2]);
  if (cross2(t[0], t[1], p) >= 0 && cross2(t[1], t[2], p) >= 0 && cross2(t[2], t[0], p) >= 0) return 0.0;
  double best = 1e300;
  for (int i = 0; i < 3; ++i) {
    const P2& a = t[i];
    const P2& b = t[(i + 1) % 3];
    const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
    double s = len2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2 : 0.0;
    s = std::clamp(s, 0.0, 1.0);
    const double ex = a[0] + s * dx - p[0], ey = a[1] + s * dy - p[1];
    best = std::min(best, ex * ex + ey * ey);
  }
  return best;
}

// Projection onto an old polygon's best-fit plane.
struct PlaneBasis {
  glm::dvec3 u{1, 0, 0}, v{0, 1, 0};
  P2 operator()(const glm::dvec3& p) const { return {glm::dot(p, u), glm::dot(p, v)}; }
};

PlaneBasis basis_of(const PolyMesh& mesh, size_t face) {
  glm::dvec3 n = newell_normal(mesh.positions, mesh.face(face));
  PlaneBasis b;
  if (!(glm::length(n) > 0) || !std::isfinite(glm::length(n))) return b;
  n = glm::normalize(n);
  b.u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  b.v = glm::cross(n, b.u);
  return b;
}

// Sparse row accumulator: (id, weight) pairs merged by id.
void add_entry(std::vector<std::pair<uint32_t, double>>& row, uint32_t id, double w) {
  for (auto& e : row)
    if (e.first == id) {
      e.second += w;
      return;
    }
  row.emplace_back(id, w);
}

}  // namespace

CageTopologyChange identity_change(const Cage& cage) {
  CageTopologyChange c;
  c.old_vertices = static_cast<uint32_t>(cage.num_vertices());
  c.old_faces = static_cast<uint32_t>(cage.polygons.num_faces());
  c.old_elements = static_cast<uint32_t>(cage.num_elements());
  for (uint32_t v = 0; v < c.old_vertices; ++v) {
    c.vertex_parents.push_back(v);
    c.vertex_weights.push_back(1.0);
    c.vertex_offsets.push_back(v + 1);
  }
  for (uint32_t f = 0; f < c.old_faces; ++f) c.face_parent.push_back(f);
  for (uint32_t e = 0; e < c.old_elements; ++e) {
    c.element_parents.push_back(e);
    c.element_offsets.push_back(e + 1);
  }
  return c;
}

CageTopologyChange compose(const CageTopologyChange& first, const CageTopologyChange& second) {
  CAGEWRAP_CHECK(second.old_vertices == first.num_vertices() && second.old_faces == first.num_faces() &&
                     second.old_elements == first.num_elements(),
                 "compose: the second change must start where the first ends");
  CageTopologyChange out;
  out.old_vertices = first.old_vertices;
  out.old_faces = first.old_faces;
  out.old_elements = first.old_elements;
  std::vector<std::pair<uint32_t, double>> row;
  for (size_t v = 0; v < second.num_vertices(); ++v) {
    row.clear();
    auto mids = second.parents_of_vertex(v);
    auto mid_w = second.weights_of_vertex(v);
    for (size_t i = 0; i < mids.size(); ++i) {
      auto olds = first.parents_of_vertex(mids[i]);
      auto old_w = first.weights_of_vertex(mids[i]);
      for (size_t j = 0; j < olds.size(); ++j) add_entry(row, olds[j], mid_w[i] * old_w[j]);
    }
    std::sort(row.begin(), row.end());
    for (auto [id, w] : row) {
      if (w == 0.0) continue;
      out.vertex_parents.push_back(id);
      out.vertex_weights.push_back(w);
    }
    out.vertex_offsets.push_back(static_cast<uint32_t>(out.vertex_parents.size()));
  }
  out.face_parent.reserve(second.face_parent.size());
  for (uint32_t f : second.face_parent) out.face_parent.push_back(first.face_parent[f]);
  std::vector<uint32_t> ids;
  for (size_t e = 0; e < second.num_elements(); ++e) {
    ids.clear();
    for (uint32_t mid : second.parents_of_element(e)) {
      auto olds = first.parents_of_element(mid);
      ids.insert(ids.end(), olds.begin(), olds.end());
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    out.element_parents.insert(out.element_parents.end(), ids.begin(), ids.end());
    out.element_offsets.push_back(static_cast<uint32_t>(out.element_parents.size()));
  }
  set_dropped_faces(out);
  return out;
}

Status check_change(const CageTopologyChange& change, const Cage& before, const Cage& after) {
  auto mismatch = [](const char* what, size_t expected, size_t got) {
    return make_error(ErrorCode::kTopologyMismatch, std::string("the topology change ") + what + " " +
                                                        std::to_string(got) + " but the cage has " +
                                                        std::to_string(expected));
  };
  if (change.old_vertices != before.num_vertices())
    return mismatch("starts from a cage of vertex count", before.num_vertices(), change.old_vertices);
  if (change.old_faces != before.polygons.num_faces())
    return mismatch("starts from a cage of face count", before.polygons.num_faces(), change.old_faces);
  if (change.old_elements != before.num_elements())
    return mismatch("starts from a cage of element count", before.num_elements(), change.old_elements);
  if (change.num_vertices() != after.num_vertices())
    return mismatch("ends at a cage of vertex count", after.num_vertices(), change.num_vertices());
  if (change.num_faces() != after.polygons.num_faces())
    return mismatch("ends at a cage of face count", after.polygons.num_faces(), change.num_faces());
  if (change.num_elements() != after.num_elements())
    return mismatch("ends at a cage of element count", after.num_elements(), change.num_elements());
  for (size_t v = 0; v < change.num_vertices(); ++v) {
    double sum = 0.0;
    auto parents = change.parents_of_vertex(v);
    auto weights = change.weights_of_vertex(v);
    for (size_t i = 0; i < parents.size(); ++i) {
      if (parents[i] >= change.old_vertices)
        return make_error(ErrorCode::kIndexOutOfRange, "new vertex " + std::to_string(v) +
                                                           " names old vertex " + std::to_string(parents[i]) +
                                                           " out of range");
      sum += weights[i];
    }
    if (parents.empty() || std::abs(sum - 1.0) > 1e-6)
      return make_error(ErrorCode::kInvalidArgument,
                        "the weights of new vertex " + std::to_string(v) + " sum to " + std::to_string(sum));
  }
  for (size_t f = 0; f < change.num_faces(); ++f)
    if (change.face_parent[f] >= change.old_faces)
      return make_error(ErrorCode::kIndexOutOfRange, "new face " + std::to_string(f) + " names old face " +
                                                         std::to_string(change.face_parent[f]) +
                                                         " out of range");
  for (size_t e = 0; e < change.num_elements(); ++e) {
    auto parents = change.parents_of_element(e);
    if (parents.empty())
      return make_error(ErrorCode::kInvalidArgument, "new element " + std::to_string(e) + " has no parent");
    for (uint32_t k : parents)
      if (k >= change.old_elements)
        return make_error(
            ErrorCode::kIndexOutOfRange,
            "new element " + std::to_string(e) + " names old element " + std::to_string(k) + " out of range");
  }
  return Ok{};
}

uint32_t dominant_parent(const CageTopologyChange& change, size_t v) {
  auto parents = change.parents_of_vertex(v);
  auto weights = change.weights_of_vertex(v);
  CAGEWRAP_CHECK(!parents.empty(), "every new vertex has a parent");
  size_t best = 0;
  for (size_t i = 1; i < parents.size(); ++i)
    if (weights[i] > weights[best] || (weights[i] == weights[best] && parents[i] < parents[best])) best = i;
  return parents[best];
}

ElementChildren element_children(const CageTopologyChange& change) {
  ElementChildren c;
  c.offsets.assign(change.old_elements + 1, 0);
  for (uint32_t k : change.element_parents) ++c.offsets[k + 1];
  for (size_t k = 0; k < change.old_elements; ++k) c.offsets[k + 1] += c.offsets[k];
  c.ids.resize(change.element_parents.size());
  std::vector<uint32_t> fill(c.offsets.begin(), c.offsets.end() - 1);
  for (size_t e = 0; e < change.num_elements(); ++e)  // ascending e: each list comes out sorted
    for (uint32_t k : change.parents_of_element(e)) c.ids[fill[k]++] = static_cast<uint32_t>(e);
  return c;
}

std::vector<glm::vec3> interpolate_vertex_attribute(const CageTopologyChange& change,
                                                    std::span<const glm::vec3> old_values) {
  CAGEWRAP_CHECK(old_values.size() == change.old_vertices, "one value per old vertex");
  std::vector<glm::vec3> out(change.num_vertices());
  for (size_t v = 0; v < out.size(); ++v) {
    glm::dvec3 sum(0.0);
    auto parents = change.parents_of_vertex(v);
    auto weights = change.weights_of_vertex(v);
    for (size_t i = 0; i < parents.size(); ++i) sum += weights[i] * glm::dvec3(old_values[parents[i]]);
    out[v] = glm::vec3(sum);
  }
  return out;
}

std::vector<double> interpolate_vertex_attribute(const CageTopologyChange& change,
                                                 std::span<const double> old_values) {
  CAGEWRAP_CHECK(old_values.size() == change.old_vertices, "one value per old vertex");
  std::vector<double> out(change.num_vertices(), 0.0);
  for (size_t v = 0; v < out.size(); ++v) {
    auto parents = change.parents_of_vertex(v);
    auto weights = change.weights_of_vertex(v);
    for (size_t i = 0; i < parents.size(); ++i) out[v] += weights[i] * old_values[parents[i]];
  }
  return out;
}

std::vector<uint32_t> carry_vertex_labels(const CageTopologyChange& change,
                                          std::span<const uint32_t> old_labels) {
  CAGEWRAP_CHECK(old_labels.size() == change.old_vertices, "one label per old vertex");
  std::vector<uint32_t> out(change.num_vertices());
  for (size_t v = 0; v < out.size(); ++v) out[v] = old_labels[dominant_parent(change, v)];
  return out;
}

Result<std::vector<SetEdit>> carry_set_edits(const CageTopologyChange& change,
                                             std::span<const SetEdit> edits) {
  for (const SetEdit& e : edits)
    for (const auto* list : {&e.exclude, &e.include})
      for (uint32_t k : *list)
        if (k >= change.old_elements)
          return make_error(ErrorCode::kIndexOutOfRange,
                            "set edit of point " + std::to_string(e.point) + " names element " +
                                std::to_string(k) + " but the cage had " +
                                std::to_string(change.old_elements) + " elements");
  const ElementChildren children = element_children(change);
  auto carry = [&](const std::vector<uint32_t>& old_ids) {
    std::vector<uint32_t> ids;
    for (uint32_t k : old_ids) {
      auto c = children.of(k);
      ids.insert(ids.end(), c.begin(), c.end());
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
  };
  std::vector<SetEdit> out;
  out.reserve(edits.size());
  for (const SetEdit& e : edits) {
    SetEdit n{e.point, carry(e.exclude), carry(e.include), e.only};
    if (n.only || !n.exclude.empty() || !n.include.empty()) out.push_back(std::move(n));
  }
  return out;
}

namespace {
constexpr uint32_t kAutomaticLabel = 0xFFFFFFFFu;  // an automatic (not overridden) attachment
}  // namespace

Result<Document> apply_topology_change(const Document& doc, const CageEdit& edit) {
  if (!doc.has_cage()) return make_error(ErrorCode::kInvalidArgument, "the document has no cage to change");
  if (auto s = check_change(edit.change, *doc.cage, edit.cage); !s) return s.error();
  auto edits = carry_set_edits(edit.change, doc.set_edits);
  if (!edits) return edits.error();
  Document out = doc;
  out.cage = std::make_shared<const Cage>(edit.cage);
  out.cage_offsets.clear();
  if (doc.cage_offsets.size() == doc.cage->num_vertices())
    out.cage_offsets = interpolate_vertex_attribute(edit.change, doc.cage_offsets);
  out.set_edits = std::move(edits).value();
  // skeleton attachments: a new vertex follows the bone its dominant parent was assigned to
  if (!doc.attachment.overrides.empty()) {
    const std::vector<int32_t> old = overrides_per_vertex(doc.attachment, doc.cage->num_vertices());
    std::vector<uint32_t> labels(old.size());
    for (size_t v = 0; v < old.size(); ++v) labels[v] = old[v] < 0 ? kAutomaticLabel : static_cast<uint32_t>(old[v]);
    const std::vector<uint32_t> carried = carry_vertex_labels(edit.change, labels);
    std::vector<int32_t> per_vertex(carried.size());
    for (size_t v = 0; v < carried.size(); ++v) per_vertex[v] = carried[v] == kAutomaticLabel ? -1 : static_cast<int32_t>(carried[v]);
    out.attachment = with_overrides_per_vertex(doc.attachment, per_vertex);
  }
  // simulation weights: mass and stiffness interpolated from the parents, the pin from the dominant one
  out.sim.vertices.clear();
  if (doc.sim.vertices.size() == doc.cage->num_vertices()) {
    std::vector<double> mass, stiffness;
    std::vector<uint32_t> pinned;
    for (const SimVertex& w : doc.sim.vertices) {
      mass.push_back(w.mass);
      stiffness.push_back(w.stiffness);
      pinned.push_back(w.pinned ? 1u : 0u);
    }
    const auto m = interpolate_vertex_attribute(edit.change, std::span<const double>(mass));
    const auto k = interpolate_vertex_attribute(edit.change, std::span<const double>(stiffness));
    const auto p = carry_vertex_labels(edit.change, pinned);
    for (size_t v = 0; v < m.size(); ++v)
      out.sim.vertices.push_back({p[v] != 0, static_cast<float>(m[v]), static_cast<float>(k[v])});
  }
  // keypose offsets: interpolated from the parents like the driver offsets
  for (KeyposeSet& set : out.keyposes)
    for (KeyposeKey& key : set.keys) {
      const std::vector<glm::vec3> dense = dense_offsets(key, doc.cage->num_vertices());
      key = make_key(key.values, interpolate_vertex_attribute(edit.change, dense));
    }
  out.revision = next_revision();
  return out;
}

void set_element_parents(const Cage& before, const Cage& after, std::span<const glm::dvec3> corner_domain,
                         CageTopologyChange& change) {
  CAGEWRAP_CHECK(corner_domain.size() == after.polygons.face_vertices.size(),
                 "one domain point per new corner");
  CAGEWRAP_CHECK(change.face_parent.size() == after.polygons.num_faces(), "face parents come first");
  // old polygon -> its elements
  const size_t old_faces = before.polygons.num_faces();
  std::vector<uint32_t> start(old_faces + 1, 0), elems(before.num_elements());
  for (uint32_t f : before.element_face) ++start[f + 1];
  for (size_t f = 0; f < old_faces; ++f) start[f + 1] += start[f];
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t e = 0; e < before.num_elements(); ++e)
      elems[fill[before.element_face[e]]++] = static_cast<uint32_t>(e);
  }
  const auto& old_pos = before.polygons.positions;
  std::vector<std::optional<PlaneBasis>> bases(old_faces);  // built on first use

  change.element_offsets.assign(1, 0);
  change.element_parents.clear();
  for (size_t e = 0; e < after.num_elements(); ++e) {
    const uint32_t nf = after.element_face[e];
    const uint32_t of = change.face_parent[nf];
    const std::span<const uint32_t> candidates(elems.data() + start[of], start[of + 1] - start[of]);
    if (candidates.size() <= 1) {
      change.element_parents.insert(change.element_parents.end(), candidates.begin(), candidates.end());
    } else {
      if (!bases[of]) bases[of] = basis_of(before.polygons, of);
      const PlaneBasis& basis = *bases[of];
      auto corners = after.polygons.face(nf);
      std::array<P2, 3> domain;
      for (int i = 0; i < 3; ++i) {
        const uint32_t v = after.elements[e][static_cast<size_t>(i)];
        const size_t at = static_cast<size_t>(std::find(corners.begin(), corners.end(), v) - corners.begin());
        CAGEWRAP_CHECK(at < corners.size(), "an element's corners belong to its polygon");
        domain[static_cast<size_t>(i)] = basis(corner_domain[after.polygons.face_start[nf] + at]);
      }
      const double area = std::abs(0.5 * cross2(domain[0], domain[1], domain[2]));
      const size_t first = change.element_parents.size();
      if (area > 0 && std::isfinite(area)) {
        for (uint32_t k : candidates) {
          const Tri& t = before.elements[k];
          std::array<P2, 3> old_tri = {basis(glm::dvec3(old_pos[t[0]])), basis(glm::dvec3(old_pos[t[1]])),
                                       basis(glm::dvec3(old_pos[t[2]]))};
          if (overlap_area(domain, old_tri) > 1e-6 * area) change.element_parents.push_back(k);
        }
      }
      if (change.element_parents.size() == first) {  // degenerate, or outside the old polygon
        const P2 c = {(domain[0][0] + domain[1][0] + domain[2][0]) / 3,
                      (domain[0][1] + domain[1][1] + domain[2][1]) / 3};
        uint32_t best = candidates[0];
        double best_d = 1e300;
        for (uint32_t k : candidates) {
          const Tri& t = before.elements[k];
          const double d =
              distance2_to_triangle(c, {basis(glm::dvec3(old_pos[t[0]])), basis(glm::dvec3(old_pos[t[1]])),
                                        basis(glm::dvec3(old_pos[t[2]]))});
          if (d < best_d) {
            best_d = d;
            best = k;
          }
        }
        change.element_parents.push_back(best);
      }
    }
    change.element_offsets.push_back(static_cast<uint32_t>(change.element_parents.size()));
  }
}

Result<CageEdit> make_cage_edit(const Cage& before, PolyMesh polygons, CageTopologyChange change,
                                std::span<const glm::dvec3> corner_domain,
                                std::vector<std::string> warnings) {
  auto cage = make_cage(std::move(polygons), "edited cage");
  if (!cage) return cage.error();
  CageEdit edit{std::move(cage).value(), std::move(change), std::move(warnings)};
  set_element_parents(before, edit.cage, corner_domain, edit.change);
  set_dropped_faces(edit.change);
  return edit;
}

void set_dropped_faces(CageTopologyChange& change) {
  std::vector<uint8_t> has_child(change.old_faces, 0);
  for (uint32_t f : change.face_parent) has_child[f] = 1;
  change.dropped_faces.clear();
  for (uint32_t f = 0; f < change.old_faces; ++f)
    if (!has_child[f]) change.dropped_faces.push_back(f);
}

Result<std::vector<uint8_t>> selection_mask(std::span<const uint32_t> ids, size_t count, const char* what,
                                            const char* verb) {
  const std::string plural = std::string(what) == "vertex" ? "vertices" : std::string(what) + "s";
  if (ids.empty()) return make_error(ErrorCode::kInvalidArgument, "no " + plural + " given to " + verb);
  std::vector<uint8_t> mask(count, 0);
  for (uint32_t i : ids) {
    if (i >= count)
      return make_error(ErrorCode::kIndexOutOfRange, std::string(what) + " " + std::to_string(i) +
                                                         " out of range: the cage has " +
                                                         std::to_string(count) + " " + plural);
    mask[i] = 1;
  }
  return mask;
}

}  // namespace cagewrap
