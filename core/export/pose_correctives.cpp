#include "core/export/pose_correctives.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <atomic>
#include <mutex>
#include <numeric>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

namespace cagewrap {
namespace {

std::string axis_name(const glm::vec3& a) {
  const glm::vec3 u = glm::normalize(a);
  if (u == glm::vec3(1, 0, 0)) return "x";
  if (u == glm::vec3(0, 1, 0)) return "y";
  if (u == glm::vec3(0, 0, 1)) return "z";
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%.3g %.3g %.3g)", u.x, u.y, u.z);
  return buf;
}

bool same_driver(const JointDriver& a, const JointDriver& b) {
  return a.node == b.node && a.kind == b.kind && glm::length(glm::normalize(a.axis) - glm::normalize(b.axis)) < 1e-6f;
}

// Ridge solve of one point: features `c` (indices into the sample matrix), returns #c x 3.
Eigen::MatrixXd solve_point(const Eigen::MatrixXd& gram, const Eigen::MatrixXd& features, const std::vector<size_t>& fitted,
                            const std::vector<std::vector<glm::vec3>>& residuals, size_t point, const std::vector<uint32_t>& c) {
  const Eigen::Index n = Eigen::Index(c.size());
  Eigen::MatrixXd g(n, n);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, 3);
  double trace = 0.0;
  for (Eigen::Index a = 0; a < n; ++a) {
    for (Eigen::Index b = 0; b < n; ++b) g(a, b) = gram(c[a], c[b]);
    trace += g(a, a);
  }
  for (size_t s : fitted) {
    const glm::vec3& r = residuals[s][point];
    for (Eigen::Index a = 0; a < n; ++a) {
      const double f = features(Eigen::Index(s), c[a]);
      if (f == 0.0) continue;
      h(a, 0) += f * r.x;
      h(a, 1) += f * r.y;
      h(a, 2) += f * r.z;
    }
  }
  const double lambda = kPoseRidge * trace / double(std::max<Eigen::Index>(1, n)) + 1e-12;
  g.diagonal().array() += lambda;
  return g.ldlt().solve(h);
}

}  // namespace

double pose_feature_value(const PoseFeature& f, const Skeleton& skeleton, const Pose& pose) {
  const double a = driver_value(f.driver, skeleton, pose);
  return std::clamp(double(f.side) * a / f.scale, 0.0, 1.0);
}

std::vector<JointDriver> pose_corrective_drivers(std::span<const KeyposeSet> sets, std::span<const uint32_t> joint_nodes) {
  std::vector<JointDriver> out;
  auto add = [&](const JointDriver& d) {
    if (glm::length(d.axis) <= 0.0f) return;
    for (const JointDriver& e : out)
      if (same_driver(d, e)) return;
    out.push_back(d);
  };
  for (const KeyposeSet& set : sets)
    for (const JointDriver& d : set.drivers) add(d);
  for (uint32_t node : joint_nodes)
    for (int k = 0; k < 3; ++k) {
      JointDriver d;
      d.node = node;
      d.kind = DriverKind::kRotation;
      d.axis = glm::vec3(0.0f);
      d.axis[k] = 1.0f;
      add(d);
    }
  return out;
}

bool fit_pose_correctives(const Skeleton& skeleton, std::span<const JointDriver> drivers, std::span<const Pose> poses,
                          const std::vector<std::vector<glm::vec3>>& residuals, const std::vector<bool>& fit,
                          const std::vector<std::vector<uint32_t>>& point_nodes, size_t max_targets,
                          const std::function<bool(size_t, size_t)>& step, PoseCorrectiveFit& out) {
  out = {};
  const size_t ns = poses.size(), np = residuals.empty() ? 0 : residuals[0].size();
  std::vector<size_t> fitted;
  for (size_t s = 0; s < ns; ++s)
    if (s < fit.size() && fit[s]) fitted.push_back(s);
  // the features: both sides of each driver, scaled to the largest reading over the fitted poses
  std::vector<PoseFeature> features;
  std::vector<size_t> driver_of;  // each feature's driver
  std::vector<std::vector<double>> readings(drivers.size(), std::vector<double>(ns));
  for (size_t d = 0; d < drivers.size(); ++d) {
    for (size_t s = 0; s < ns; ++s) readings[d][s] = driver_value(drivers[d], skeleton, poses[s]);
    for (int side : {1, -1}) {
      double scale = 0.0;
      for (size_t s : fitted) scale = std::max(scale, side * readings[d][s]);
      if (scale < kMinFeatureDegrees) continue;
      PoseFeature f;
      f.driver = drivers[d];
      f.side = side;
      f.scale = scale;
      const uint32_t node = drivers[d].node;
      f.name = (node < skeleton.size() && !skeleton.node(node).name.empty() ? skeleton.node(node).name
                                                                            : "node " + std::to_string(node)) +
               " " + driver_kind_name(drivers[d].kind) + " " + axis_name(drivers[d].axis) + (side > 0 ? "+" : "-");
      features.push_back(f);
      driver_of.push_back(d);
    }
  }
  const Eigen::Index nf = Eigen::Index(features.size());
  Eigen::MatrixXd values(Eigen::Index(ns), nf);
  for (Eigen::Index k = 0; k < nf; ++k)
    for (size_t s = 0; s < ns; ++s)
      values(Eigen::Index(s), k) =
          std::clamp(double(features[k].side) * readings[driver_of[k]][s] / features[k].scale, 0.0, 1.0);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(nf, nf);
  for (size_t s : fitted) gram.noalias() += values.row(Eigen::Index(s)).transpose() * values.row(Eigen::Index(s));
  // each point's candidates: the features on its nodes
  std::vector<std::vector<uint32_t>> by_node(skeleton.size());
  for (Eigen::Index k = 0; k < nf; ++k)
    if (features[k].driver.node < skeleton.size()) by_node[features[k].driver.node].push_back(uint32_t(k));
  auto candidates = [&](size_t i) {
    std::vector<uint32_t> c;
    for (uint32_t node : point_nodes[i])
      if (node < by_node.size())
        for (uint32_t k : by_node[node]) c.push_back(k);
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    return c;
  };
  if (nf == 0 || np == 0 || fitted.empty()) return step(1, 1);
  // each point's prediction of every sample's residual from its candidate features
  const Eigen::Index nfit = Eigen::Index(fitted.size());
  std::vector<std::vector<glm::vec3>> predicted(ns, std::vector<glm::vec3>(np, glm::vec3(0.0f)));
  constexpr size_t kChunk = 512;
  const size_t chunks = (np + kChunk - 1) / kChunk;
  std::atomic<size_t> done{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks, 1), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t chunk = range.begin(); chunk != range.end(); ++chunk) {
      for (size_t i = chunk * kChunk; i < std::min(np, (chunk + 1) * kChunk); ++i) {
        const std::vector<uint32_t> c = candidates(i);
        if (c.empty()) continue;
        const Eigen::MatrixXd t = solve_point(gram, values, fitted, residuals, i, c);
        for (size_t s = 0; s < ns; ++s) {
          glm::dvec3 x(0.0);
          for (size_t a = 0; a < c.size(); ++a) {
            const double f = values(Eigen::Index(s), c[a]);
            if (f != 0.0) x += f * glm::dvec3(t(Eigen::Index(a), 0), t(Eigen::Index(a), 1), t(Eigen::Index(a), 2));
          }
          predicted[s][i] = glm::vec3(x);
        }
      }
      ++done;
    }
  });
  if (!step(done.load(), chunks + 2)) return false;
  // the fitted predictions' principal components (Gram matrix over the fitted samples)
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(nfit, nfit);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nfit, 1), [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index a = range.begin(); a != range.end(); ++a)
      for (Eigen::Index b = 0; b <= a; ++b) {
        double d = 0.0;
        const auto& pa = predicted[fitted[a]];
        const auto& pb = predicted[fitted[b]];
        for (size_t i = 0; i < np; ++i) d += double(pa[i].x) * pb[i].x + double(pa[i].y) * pb[i].y + double(pa[i].z) * pb[i].z;
        g(a, b) = g(b, a) = d;
      }
  });
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(g);
  const Eigen::VectorXd lambda = eig.eigenvalues();  // ascending
  const double top = lambda.size() ? std::max(0.0, lambda(lambda.size() - 1)) : 0.0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) out.rank += lambda(k) > 1e-12 * top && lambda(k) > 0.0 ? 1 : 0;
  const size_t kept = std::min(max_targets, out.rank);
  Eigen::MatrixXd w(nfit, Eigen::Index(kept));  // fitted samples' weights
  for (size_t k = 0; k < kept; ++k) {
    const Eigen::Index col = lambda.size() - 1 - Eigen::Index(k);
    const double sigma = std::sqrt(lambda(col));
    const Eigen::VectorXd u = eig.eigenvectors().col(col);
    std::vector<glm::vec3> basis(np, glm::vec3(0.0f));
    tbb::parallel_for(tbb::blocked_range<size_t>(0, np, 4096), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        glm::dvec3 x(0.0);
        for (Eigen::Index a = 0; a < nfit; ++a) x += u(a) * glm::dvec3(predicted[fitted[a]][i]);
        basis[i] = glm::vec3(x / sigma);
      }
    });
    out.targets.push_back(std::move(basis));
    w.col(Eigen::Index(k)) = sigma * u;
  }
  if (!step(chunks + 1, chunks + 2)) return false;
  // the weights as linear functions of the features, fitted on the fitted samples
  Eigen::MatrixXd ff(nfit, nf);
  for (Eigen::Index a = 0; a < nfit; ++a) ff.row(a) = values.row(Eigen::Index(fitted[a]));
  Eigen::MatrixXd normal = ff.transpose() * ff;
  normal.diagonal().array() += 1e-9 * std::max(1e-300, normal.trace() / double(nf));
  const Eigen::MatrixXd wf = normal.ldlt().solve(ff.transpose() * w);  // #F x #K
  out.features = std::move(features);
  out.feature_weights.assign(kept, std::vector<double>(size_t(nf)));
  for (size_t k = 0; k < kept; ++k)
    for (Eigen::Index f = 0; f < nf; ++f) out.feature_weights[k][size_t(f)] = wf(f, Eigen::Index(k));
  const Eigen::MatrixXd all = values * wf;  // #S x #K
  out.weights.assign(ns, std::vector<float>(kept));
  for (size_t s = 0; s < ns; ++s)
    for (size_t k = 0; k < kept; ++k) out.weights[s][k] = float(all(Eigen::Index(s), Eigen::Index(k)));
  return step(chunks + 2, chunks + 2);
}

std::string pose_correctives_extras(const Skeleton& skeleton, const PoseCorrectiveFit& fit) {
  nlohmann::json names = nlohmann::json::array(), features = nlohmann::json::array();
  const size_t targets = fit.feature_weights.size();
  for (size_t k = 0; k < targets; ++k) names.push_back("pose corrective " + std::to_string(k));
  for (const PoseFeature& f : fit.features) {
    const uint32_t n = f.driver.node;
    const glm::vec3 axis = glm::normalize(f.driver.axis);
    const glm::quat rest = n < skeleton.size() ? skeleton.node(n).rest.rotation : glm::quat(1, 0, 0, 0);
    features.push_back({{"name", f.name},
                        {"node", n},
                        {"node_name", n < skeleton.size() ? skeleton.node(n).name : std::string()},
                        {"kind", driver_kind_name(f.driver.kind)},
                        {"axis", {axis.x, axis.y, axis.z}},
                        {"rest_rotation", {rest.x, rest.y, rest.z, rest.w}},
                        {"side", f.side},
                        {"scale", f.scale}});
  }
  nlohmann::json weights = nlohmann::json::array();
  for (const std::vector<double>& row : fit.feature_weights) {
    nlohmann::json r = nlohmann::json::array();
    for (double x : row) r.push_back(float(x));
    weights.push_back(r);
  }
  nlohmann::json extras = {{"targetNames", names},
                           {"cagewrap_pose_correctives",
                            {{"version", 1},
                             {"features", features},
                             {"weights", weights},
                             {"full", std::vector<double>(targets, 1.0)}}}};
  return extras.dump();
}

}  // namespace cagewrap
