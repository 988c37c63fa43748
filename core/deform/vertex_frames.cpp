#include "core/deform/vertex_frames.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <glm/geometric.hpp>

namespace cagewrap {

void vertex_normals(std::span<const glm::dvec3> positions, std::span<const Tri> triangles,
                    std::span<glm::dvec3> out) {
  std::fill(out.begin(), out.end(), glm::dvec3(0.0));
  for (const Tri& t : triangles) {
    glm::dvec3 n = glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
    for (uint32_t v : t) out[v] += n;
  }
  for (auto& n : out) {
    double len = glm::length(n);
    n = len > 0 ? n / len : glm::dvec3(0.0);
  }
}

glm::dvec3 lean_normal(const glm::dvec3& n, double scale2, const glm::dvec3& toward) {
  const double len = glm::length(n), floor = kCollapseRatio * scale2;
  if (!std::isfinite(len) || !std::isfinite(floor)) return toward;
  if (len >= floor && len > 0) return n / len;
  // |n / floor| = s < 1 of the element's own direction, 1 - s of `toward`: continuous at s = 1 and at n = 0
  const glm::dvec3 m = n / floor + (1.0 - len / floor) * toward;
  const double ml = glm::length(m);
  return ml > 0 && std::isfinite(ml) ? m / ml : toward;
}

namespace {
// The one-ring is flat when its second moment's smallest eigenvalue is this small relative to the largest.
constexpr double kFlatRatio = 1e-6;
// A nearly flat ring (issue 18): the normal column of L = B A^-1 comes from the ring's small relief and
// amplifies any out-of-plane motion by about 1 / relief. Below kReliefFull (eigenvalue ratio) the fit is
// regularised toward mapping the rest normal to the posed one scaled like the ring, with a weight of
// kReliefWeight times the ring's second moment; the weight fades to 0 at kReliefNone, where the relief
// itself determines the normal column (affine maps stay exact there).
constexpr double kReliefFull = 0.005, kReliefNone = 0.05, kReliefWeight = 0.03;

double relief_weight(double ratio) {
  if (ratio <= kReliefFull) return kReliefWeight;
  if (ratio >= kReliefNone) return 0.0;
  const double t = (kReliefNone - ratio) / (kReliefNone - kReliefFull);
  return kReliefWeight * t * t * (3 - 2 * t);
}
}  // namespace

OneRingFit::OneRingFit(std::span<const glm::vec3> rest, std::span<const Tri> triangles)
    : triangles_(triangles.begin(), triangles.end()) {
  const size_t n = rest.size();
  rest_.resize(n);
  for (size_t i = 0; i < n; ++i) rest_[i] = glm::dvec3(rest[i]);
  std::vector<std::array<uint32_t, 2>> edges;
  for (const Tri& t : triangles)
    for (int i = 0; i < 3; ++i) {
      uint32_t a = t[static_cast<size_t>(i)], b = t[static_cast<size_t>((i + 1) % 3)];
      edges.push_back({a, b});
      edges.push_back({b, a});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  ring_start_.assign(n + 1, 0);
  for (auto [a, b] : edges) ring_start_[a + 1]++;
  for (size_t i = 0; i < n; ++i) ring_start_[i + 1] += ring_start_[i];
  ring_.resize(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) ring_[i] = edges[i][1];  // edges are sorted by source

  rest_normal_.resize(n);
  vertex_normals(rest_, triangles_, rest_normal_);
  ring_scale2_.assign(n, 0.0);
  flat_.assign(n, 0);
  relief_.assign(n, 0.0);
  for (size_t v = 0; v < n; ++v) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    double len = 0;
    for (uint32_t k = ring_start_[v]; k < ring_start_[v + 1]; ++k) {
      glm::dvec3 r = rest_[ring_[k]] - rest_[v];
      Eigen::Vector3d e(r.x, r.y, r.z);
      a += e * e.transpose();
      len += glm::length(r);
    }
    uint32_t deg = ring_start_[v + 1] - ring_start_[v];
    ring_scale2_[v] = deg ? (len / deg) * (len / deg) : 0.0;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(a, Eigen::EigenvaluesOnly);
    auto ev = eig.eigenvalues();
    flat_[v] = !(ev(0) > kFlatRatio * ev(2));
    relief_[v] = flat_[v] ? 0.0 : relief_weight(ev(0) / ev(2)) * a.trace();
    any_flat_ = any_flat_ || flat_[v] || relief_[v] > 0;
  }
  posed_.resize(n);
  posed_normal_.resize(n);
  posed_cross_.resize(n);
}

void OneRingFit::posed_normals() {
  const size_t n = rest_.size();
  std::fill(posed_cross_.begin(), posed_cross_.end(), glm::dvec3(0.0));
  for (const Tri& t : triangles_) {
    const glm::dvec3 c = glm::cross(posed_[t[1]] - posed_[t[0]], posed_[t[2]] - posed_[t[0]]);
    for (uint32_t v : t) posed_cross_[v] += c;
  }
  // a vertex whose triangles collapse leans toward the normal of its ring's vertices (their triangles)
  for (size_t v = 0; v < n; ++v) {
    double longest2 = 0.0;
    glm::dvec3 around = posed_cross_[v];
    for (uint32_t k = ring_start_[v]; k < ring_start_[v + 1]; ++k) {
      const glm::dvec3 e = posed_[ring_[k]] - posed_[v];
      longest2 = std::max(longest2, glm::dot(e, e));
      around += posed_cross_[ring_[k]];
    }
    const double al = glm::length(around);
    const glm::dvec3 toward = al > 0 && std::isfinite(al) ? around / al : rest_normal_[v];
    posed_normal_[v] = lean_normal(posed_cross_[v], longest2, toward);
  }
}

void OneRingFit::fit(std::span<const glm::vec3> posed, std::span<glm::dmat3> out) {
  const size_t n = rest_.size();
  auto& posed_d = posed_;
  auto& posed_normal = posed_normal_;
  for (size_t i = 0; i < n; ++i) posed_d[i] = glm::dvec3(posed[i]);
  if (any_flat_) posed_normals();
  for (size_t v = 0; v < n; ++v) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero(), b = Eigen::Matrix3d::Zero();
    for (uint32_t k = ring_start_[v]; k < ring_start_[v + 1]; ++k) {
      glm::dvec3 r = rest_[ring_[k]] - rest_[v], d = posed_d[ring_[k]] - posed_d[v];
      Eigen::Vector3d er(r.x, r.y, r.z), ed(d.x, d.y, d.z);
      a += er * er.transpose();
      b += ed * er.transpose();
    }
    if (flat_[v] || relief_[v] > 0) {
      double s2 = flat_[v] ? (ring_scale2_[v] > 0 ? ring_scale2_[v] : 1.0) : relief_[v];
      const glm::dvec3& nr = rest_normal_[v];
      const glm::dvec3& nd = posed_normal[v];
      Eigen::Vector3d er(nr.x, nr.y, nr.z), ed(nd.x, nd.y, nd.z);
      // the posed normal scaled like the one-ring's stretch keeps uniform scale exact
      double scale = 1.0;
      double rest_len = 0, posed_len = 0;
      for (uint32_t k = ring_start_[v]; k < ring_start_[v + 1]; ++k) {
        rest_len += glm::length(rest_[ring_[k]] - rest_[v]);
        posed_len += glm::length(posed_d[ring_[k]] - posed_d[v]);
      }
      if (rest_len > 0) scale = posed_len / rest_len;
      a += s2 * er * er.transpose();
      b += s2 * scale * ed * er.transpose();
      // still singular (a vertex on a lone edge, or no ring): keep the remaining directions unchanged
      // (a nearly flat ring spans 3-D already)
      if (flat_[v]) {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(a, Eigen::EigenvaluesOnly);
        if (!(eig.eigenvalues()(0) > kFlatRatio * std::max(eig.eigenvalues()(2), 1e-300))) {
          double lambda = 1e-6 * std::max(a.trace(), 1e-30);
          a += lambda * Eigen::Matrix3d::Identity();
          b += lambda * Eigen::Matrix3d::Identity();
        }
      }
    }
    Eigen::Matrix3d l = b * a.inverse();
    glm::dmat3 m;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) m[c][r] = l(r, c);
    out[v] = m;
  }
}

}  // namespace cagewrap
