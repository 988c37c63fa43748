#include "core/deform/attachment_fit.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <glm/geometric.hpp>

#include "core/deform/stencil_smooth.h"

namespace cagewrap {

Status fit_attachment(const Character& character, const Binding& binding, const AttachmentSettings& settings,
                      CageAttachment& att, const FitOptions& options) {
  const size_t nv = att.joint.size();
  const size_t np = binding.num_points;
  if (binding.num_cage_vertices != nv || att.influence_start.size() != nv + 1)
    return make_error(ErrorCode::kTopologyMismatch, "the attachment has " + std::to_string(nv) +
                                                        " cage vertices, the binding " +
                                                        std::to_string(binding.num_cage_vertices));
  if (np != character.num_vertices() || binding.offsets.size() != np + 1)
    return make_error(ErrorCode::kTopologyMismatch, "the binding has " + std::to_string(np) + " points, the character " +
                                                        std::to_string(character.num_vertices()));
  if (att.skin >= character.skins.size()) return make_error(ErrorCode::kInvalidArgument, "the attachment names no skin");
  const size_t nj = character.skins[att.skin].joints.size();
  if (nv == 0 || nj == 0) return Ok{};
  const bool extended = binding.params.variant == Variant::kExtended;

  // W (#P x #Vc) and T (#P x #J) over the points of the attachment's skin
  std::vector<Eigen::Triplet<double>> w_entries;
  w_entries.reserve(binding.ids.size() * (extended ? 1 : 3));
  std::vector<Eigen::Triplet<double>> t_entries;
  std::vector<uint8_t> rigid(np, 0);
  for (uint32_t p : binding.rigid_points)
    if (p < np) rigid[p] = 1;
  // the points that can be fitted (of the attachment's skin, with a set of their own)
  std::vector<uint8_t> valid(np, 0);
  {
    size_t base = 0;
    for (const Primitive& prim : character.primitives) {
      const bool ours = prim.skin == static_cast<int32_t>(att.skin) && prim.influence_start.size() == prim.num_vertices() + 1;
      for (size_t v = 0; v < prim.num_vertices(); ++v) {
        const size_t p = base + v;
        valid[p] = ours && !rigid[p] && binding.offsets[p] != binding.offsets[p + 1];
      }
      base += prim.num_vertices();
    }
  }
  // A large skin is sampled: every stride-th point and its edges (the unknowns are the cage's, a
  // few thousand; 200,000 points decide them as well as a million, in a fraction of the time and
  // memory: 1M demo vertices, fit 4.0 s and 650 MB without sampling)
  const size_t stride = std::max<size_t>(1, np / kFitMaxPoints);
  std::vector<uint8_t> use(np, 0);
  for (size_t p = 0; p < np; p += stride) use[p] = valid[p];
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  if (options.gradient > 0) {
    // the sampled points' edges, straight from the triangles (an edge inside the surface comes once
    // from each side, so each weighs half)
    uint32_t offset = 0;
    for (const Primitive& prim : character.primitives) {
      for (const Tri& t : prim.triangles)
        for (int k = 0; k < 3; ++k) {
          uint32_t a = t[k] + offset, b = t[(k + 1) % 3] + offset;
          if (a > b) std::swap(a, b);
          if (a == b || a >= np || b >= np || a % stride != 0 || !valid[a] || !valid[b]) continue;
          edges.emplace_back(a, b);
          use[b] = 1;
        }
      offset += static_cast<uint32_t>(prim.num_vertices());
    }
  }
  size_t row = 0;
  std::vector<uint32_t> point_row(np, UINT32_MAX);
  size_t base = 0;
  for (const Primitive& prim : character.primitives) {
    for (size_t v = 0; v < prim.num_vertices(); ++v) {
      const size_t p = base + v;
      if (!use[p]) continue;
      point_row[p] = static_cast<uint32_t>(row);
      for (uint32_t k = prim.influence_start[v]; k < prim.influence_start[v + 1]; ++k)
        if (prim.influence_joint[k] < nj) t_entries.emplace_back(row, prim.influence_joint[k], prim.influence_weight[k]);
      for (uint32_t e = binding.offsets[p]; e < binding.offsets[p + 1]; ++e) {
        const double u = binding.weights[e];
        const uint32_t id = binding.ids[e];
        if (extended) {
          if (id < nv) w_entries.emplace_back(row, id, u);
        } else if (id < binding.elements.size()) {
          for (uint32_t c : binding.elements[id])
            if (c < nv) w_entries.emplace_back(row, c, u / 3.0);
        }
      }
      ++row;
    }
    base += prim.num_vertices();
  }
  if (row == 0) return Ok{};
  Eigen::SparseMatrix<double> W(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(nv));
  W.setFromTriplets(w_entries.begin(), w_entries.end());
  Eigen::SparseMatrix<double> T(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(nj));
  T.setFromTriplets(t_entries.begin(), t_entries.end());
  Eigen::SparseMatrix<double> A = W.transpose() * W;
  double mean_diag = 0.0;
  for (Eigen::Index i = 0; i < A.rows(); ++i) mean_diag += A.coeff(i, i);
  mean_diag /= double(A.rows());
  const double lambda = options.regularization * (mean_diag > 0 ? mean_diag : 1.0);
  Eigen::MatrixXd w0 = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(nv), static_cast<Eigen::Index>(nj));
  for (size_t v = 0; v < nv; ++v)
    for (uint32_t i = att.influence_start[v]; i < att.influence_start[v + 1]; ++i)
      w0(static_cast<Eigen::Index>(v), att.influence_joint[i]) = att.influence_weight[i];
  Eigen::SparseMatrix<double> I(A.rows(), A.cols());
  I.setIdentity();
  A += lambda * I;
  // the weights' differences along the skin's edges too (a Sobolev fit): W w should change across
  // an edge as the file's weights do, or the rig stretches the edge where W changes faster than T
  // (a concave armpit, where neighbouring points project far apart on the cage)
  Eigen::SparseMatrix<double> L(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(row));
  const double gamma = options.gradient;
  if (gamma > 0) {
    std::vector<glm::vec3> rest;
    for (const Primitive& prim : character.primitives) rest.insert(rest.end(), prim.positions.begin(), prim.positions.end());
    double mean_len = 0.0;
    size_t n = 0;
    for (const auto& [a, b] : edges)
      if (point_row[a] != UINT32_MAX && point_row[b] != UINT32_MAX) mean_len += glm::length(rest[a] - rest[b]), ++n;
    mean_len = n ? mean_len / double(n) : 0.0;
    std::vector<Eigen::Triplet<double>> l_entries;
    for (const auto& [a, b] : edges) {
      const uint32_t ra = point_row[a], rb = point_row[b];
      if (ra == UINT32_MAX || rb == UINT32_MAX) continue;
      const double len = glm::length(rest[a] - rest[b]);
      if (!(len > 1e-3 * mean_len)) continue;
      const double k = 0.5 * (mean_len / len) * (mean_len / len);  // each interior edge comes twice
      l_entries.emplace_back(ra, ra, k);
      l_entries.emplace_back(rb, rb, k);
      l_entries.emplace_back(ra, rb, -k);
      l_entries.emplace_back(rb, ra, -k);
    }
    L.setFromTriplets(l_entries.begin(), l_entries.end());
    A += gamma * Eigen::SparseMatrix<double>(W.transpose() * L * W);
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success)
    return make_error(ErrorCode::kInvalidArgument, "the attachment fit's system could not be factorized");
  Eigen::MatrixXd rhs = Eigen::MatrixXd(W.transpose() * T) + lambda * w0;
  if (gamma > 0) rhs += gamma * Eigen::MatrixXd(W.transpose() * (L * T));
  const Eigen::MatrixXd w = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !w.allFinite())
    return make_error(ErrorCode::kInvalidArgument, "the attachment fit's system could not be solved");

  // keep each vertex's heaviest positive weights; overrides stay pinned to their joint
  CageAttachment out = att;
  out.influence_start.assign(1, 0);
  out.influence_joint.clear();
  out.influence_weight.clear();
  // a vertex follows only joints of one chain (its heaviest joint's ancestors and descendants): a
  // thigh's vertex never takes the other leg, whatever the least squares would trade for it
  const Skeleton& sk = character.skeleton;
  const Skin& skin = character.skins[att.skin];
  auto above = [&](uint32_t a, uint32_t b) {  // a is b or an ancestor of b
    for (int32_t x = static_cast<int32_t>(b); x >= 0 && size_t(x) < sk.size(); x = sk.node(size_t(x)).parent)
      if (static_cast<uint32_t>(x) == a) return true;
    return false;
  };
  auto same_chain = [&](uint32_t a, uint32_t b) {  // skin joints
    const uint32_t x = skin.joints[a], y = skin.joints[b];
    return above(x, y) || above(y, x);
  };
  std::vector<std::pair<double, uint32_t>> raw;
  for (size_t v = 0; v < nv; ++v) {
    raw.clear();
    if (!assigned_node(settings, static_cast<uint32_t>(v))) {
      for (size_t j = 0; j < nj; ++j) {
        const double x = w(static_cast<Eigen::Index>(v), static_cast<Eigen::Index>(j));
        if (x > 1e-4) raw.emplace_back(x, static_cast<uint32_t>(j));
      }
      std::stable_sort(raw.begin(), raw.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
      if (!raw.empty()) {
        const uint32_t heaviest = raw[0].second;
        std::erase_if(raw, [&](const auto& x) { return !same_chain(heaviest, x.second); });
      }
      if (raw.size() > kMaxAttachmentInfluences) raw.resize(kMaxAttachmentInfluences);
    }
    if (raw.empty())  // an override, or nothing positive: the transferred weights
      for (uint32_t i = att.influence_start[v]; i < att.influence_start[v + 1]; ++i)
        raw.emplace_back(att.influence_weight[i], att.influence_joint[i]);
    append_influences(out, v, raw);
  }
  att = std::move(out);
  return Ok{};
}

Result<std::optional<Binding>> fit_rig(const Character& character, const Binding& registration,
                                       const AttachmentSettings& settings, CageAttachment& att) {
  if (auto f = fit_attachment(character, registration, settings, att); !f) return f.error();
  if (registration.params.variant != Variant::kExtended || registration.num_points != character.num_vertices())
    return std::optional<Binding>();
  std::optional<Binding> rig = registration;
  if (registration.num_points <= kSmoothMaxPoints) {
    const SkinGraph graph = character_skin_graph(character);
    const std::vector<float> excess = rig_weight_excess(registration, graph, character, att);
    const StencilSmoothing options;
    if (std::any_of(excess.begin(), excess.end(), [&](float x) { return x > options.jump_low; }))
      smooth_stencil(*rig, graph, options, excess, related_to_file_weights(graph, character, att));
  }
  reweight_rows(*rig, character, att);
  // then the cage weights are fitted to the re-weighted rows and the rows re-weighted again: each
  // round brings W w closer to T (docs/algorithm-notes.md, "Re-weighting each row")
  for (int round = 0; round < kRigFitRounds; ++round) {
    if (auto f = fit_attachment(character, *rig, settings, att); !f) return f.error();
    reweight_rows(*rig, character, att);
  }
  return rig;
}

}  // namespace cagewrap
