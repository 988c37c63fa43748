#include "core/export/rig_export.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <numeric>

#include "core/cage/keyposes.h"
#include "core/geometry/mesh_io.h"
#include "core/character/skinning.h"
#include "core/io/gltf_writer.h"
#include "core/export/pose_correctives.h"

#include <meshoptimizer.h>

namespace cagewrap {

const char* export_mode_name(ExportMode m) {
  switch (m) {
    case ExportMode::kBakedAnimation:
      return "baked-animation";
    case ExportMode::kBakedSkin:
      return "baked-skin";
    case ExportMode::kCage:
      return "cage";
  }
  return "?";
}

int corrective_targets(const ExportOptions& options) {
  if (options.max_targets >= 0) return options.max_targets;
  return options.mode == ExportMode::kBakedSkin ? kDefaultMaxTargets : 0;
}

bool parse_export_mode(const std::string& name, ExportMode& out) {
  for (ExportMode m : {ExportMode::kBakedAnimation, ExportMode::kBakedSkin, ExportMode::kCage})
    if (name == export_mode_name(m)) {
      out = m;
      return true;
    }
  return false;
}

std::vector<double> export_frame_times(double duration, double fps) {
  if (!(duration > 0.0) || !(fps > 0.0)) return {0.0};
  const size_t n = std::max<size_t>(1, static_cast<size_t>(std::ceil(duration * fps - 1e-9)));
  std::vector<double> t(n + 1);
  for (size_t k = 0; k <= n; ++k) t[k] = duration * double(k) / double(n);
  return t;
}

namespace {

constexpr size_t kMaxInfluences = 8;  // what FittedWeights holds; the fit keeps ExportOptions::max_influences
constexpr size_t kNearestCageVertices = 8;
constexpr size_t kMaxCandidates = 16;
// The pull of a point's fitted weights towards the character's own (the fit's prior), relative to the mean
// curvature of its data term: what decides the weights of joints the sampled poses never move (an export of
// the arm clips alone would otherwise bind the legs to whichever joint, and an engine's walk would tear them).
// Chosen on the mannequin and the centimetre arms-down demo (docs/algorithm-notes.md): 0 let ill-conditioned
// points overfit (worst vertex 9.0 mm at frames, 98 cm on a held-out walk); 3e-3 gives 1.6 mm and 2.9 mm.
constexpr double kWeightPrior = 3e-3;

// Reports a stage's items as a share of the whole export: the stage covers [from, to).
class StageProgress {
 public:
  explicit StageProgress(const ExportProgress& p) : p_(p) {}
  void begin(const char* stage, double from, double to) {
    stage_ = stage;
    from_ = from;
    to_ = to;
  }
  // False when the export was cancelled.
  bool step(size_t done, size_t total) const {
    if (p_.on_progress)
      p_.on_progress(stage_, done, total,
                     from_ + (to_ - from_) * (total ? double(done) / double(total) : 1.0));
    return !p_.cancelled();
  }

 private:
  const ExportProgress& p_;
  const char* stage_ = "";
  double from_ = 0.0, to_ = 1.0;
};

Error cancelled() {
  return make_error(ErrorCode::kCancelled, "export cancelled");
}

void accumulate(ExportError& e, std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  double sum = e.mean * double(e.samples);
  for (size_t i = 0; i < a.size(); ++i) {
    double d = glm::length(glm::dvec3(a[i]) - glm::dvec3(b[i]));
    sum += d;
    e.max = std::max(e.max, d);
  }
  e.samples += a.size();
  e.mean = e.samples ? sum / double(e.samples) : 0.0;
}

// The residual shapes (#N of #V each, bind space) reduced to their principal components (issue 22): the
// Gram matrix G = D^T D of the 3V x N residual matrix D (in double), its eigen decomposition G = V L V^T,
// component k = D v_k / sqrt(l_k) (orthonormal), shape n's weight on it sqrt(l_k) v_k[n]. The first K
// components are kept: max_k, or with max_error > 0 the fewest whose largest vertex error over the shapes
// is within it (up to max_k).
struct CompressedTargets {
  std::vector<std::vector<glm::vec3>> basis;  // #K x #V
  std::vector<std::vector<float>> weights;    // #N x #K
  size_t rank = 0;                            // components with a non-zero singular value
  double max_error = 0.0;                     // largest |residual - reconstruction| over the shapes and vertices
};

bool compress_targets(const std::vector<std::vector<glm::vec3>>& residuals, size_t max_k, double max_error,
                      const StageProgress& stage, CompressedTargets& out) {
  const size_t n = residuals.size(), nv = n ? residuals[0].size() : 0;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(n));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t a = range.begin(); a != range.end(); ++a)
      for (size_t b = 0; b <= a; ++b) {
        double sum = 0.0;
        const glm::vec3* x = residuals[a].data();
        const glm::vec3* y = residuals[b].data();
        for (size_t i = 0; i < nv; ++i) sum += double(x[i].x) * y[i].x + double(x[i].y) * y[i].y + double(x[i].z) * y[i].z;
        gram(Eigen::Index(a), Eigen::Index(b)) = gram(Eigen::Index(b), Eigen::Index(a)) = sum;
      }
  });
  if (!stage.step(1, 3)) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  // descending; a component whose singular value is below 1e-7 of the largest carries rounding only
  std::vector<Eigen::Index> order;
  const double top = n ? std::max(eig.eigenvalues().maxCoeff(), 0.0) : 0.0;
  for (Eigen::Index k = Eigen::Index(n) - 1; k >= 0; --k)
    if (eig.eigenvalues()(k) > top * 1e-14 && eig.eigenvalues()(k) > 0.0) order.push_back(k);
  out.rank = order.size();
  // the shapes' error as components are added, until it is within max_error or max_k are kept
  std::vector<std::vector<glm::vec3>> left = residuals;
  auto largest = [&] {
    double worst = 0.0;
    for (const auto& shape : left)
      for (const glm::vec3& d : shape) worst = std::max(worst, double(glm::dot(d, d)));
    return std::sqrt(worst);
  };
  out.max_error = largest();
  for (size_t k = 0; k < order.size() && k < max_k; ++k) {
    if (max_error > 0.0 && out.max_error <= max_error) break;
    const Eigen::VectorXd v = eig.eigenvectors().col(order[k]);
    const double sigma = std::sqrt(eig.eigenvalues()(order[k]));
    std::vector<glm::vec3> component(nv);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, nv, 4096), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        glm::dvec3 c(0.0);
        for (size_t a = 0; a < n; ++a) c += v(Eigen::Index(a)) * glm::dvec3(residuals[a][i]);
        component[i] = glm::vec3(c / sigma);
      }
    });
    out.weights.resize(n);
    for (size_t a = 0; a < n; ++a) {
      const float w = static_cast<float>(sigma * v(Eigen::Index(a)));
      out.weights[a].push_back(w);
      for (size_t i = 0; i < nv; ++i) left[a][i] -= w * component[i];
    }
    out.basis.push_back(std::move(component));
    out.max_error = largest();
    if (!stage.step(2, 3)) return false;
  }
  out.weights.resize(n);
  for (auto& w : out.weights) w.resize(out.basis.size(), 0.0f);
  return stage.step(3, 3);
}

// Reorders a primitive for the GPU (ExportOptions::optimize): triangles for the vertex cache, vertices in the
// order the triangles first use them (vertices no triangle uses stay, in order, at the end); every per-vertex
// stream and morph target follows and source_index records where each vertex came from. Adds the cache miss
// ratios (transformed vertices, triangles) before and after to `before` and `after`.
void optimize_primitive(Primitive& p, std::array<double, 2>& before, std::array<double, 2>& after) {
  const size_t nv = p.num_vertices(), ni = p.triangles.size() * 3;
  if (ni == 0 || nv >= (size_t(1) << 24)) return;  // source indices are written as floats: exact below 2^24
  std::vector<unsigned int> idx(ni), cached(ni), remap(nv);
  for (size_t t = 0; t < p.triangles.size(); ++t)
    for (size_t k = 0; k < 3; ++k) idx[3 * t + k] = p.triangles[t][k];
  const auto stats = [&](const std::vector<unsigned int>& i, std::array<double, 2>& into) {
    const meshopt_VertexCacheStatistics s = meshopt_analyzeVertexCache(i.data(), i.size(), nv, 32, 0, 0);
    into[0] += double(s.vertices_transformed);
    into[1] += double(i.size() / 3);
  };
  stats(idx, before);
  meshopt_optimizeVertexCache(cached.data(), idx.data(), ni, nv);
  meshopt_optimizeVertexFetchRemap(remap.data(), cached.data(), ni, nv);
  size_t next = 0;  // the used vertices take 0 .. used-1; the others follow in their order
  for (unsigned int r : remap)
    if (r != ~0u) next = std::max<size_t>(next, size_t(r) + 1);
  for (unsigned int& r : remap)
    if (r == ~0u) r = static_cast<unsigned int>(next++);
  std::vector<unsigned int> out_idx(ni);
  meshopt_remapIndexBuffer(out_idx.data(), cached.data(), ni, remap.data());
  stats(out_idx, after);
  for (size_t t = 0; t < p.triangles.size(); ++t)
    for (size_t k = 0; k < 3; ++k) p.triangles[t][k] = out_idx[3 * t + k];
  auto permute = [&](auto& v) {
    auto copy = v;
    for (size_t i = 0; i < nv; ++i) v[remap[i]] = copy[i];
  };
  permute(p.positions);
  for (auto& target : p.morph_targets) permute(target);
  std::vector<uint32_t> source(nv);
  for (size_t i = 0; i < nv; ++i) source[remap[i]] = p.source_index.empty() ? uint32_t(i) : p.source_index[i];
  p.source_index = std::move(source);
  if (!p.influence_start.empty()) {
    std::vector<size_t> from(nv);
    for (size_t i = 0; i < nv; ++i) from[remap[i]] = i;
    std::vector<uint32_t> start{0};
    std::vector<uint16_t> joint;
    std::vector<float> weight;
    for (size_t v = 0; v < nv; ++v) {
      for (uint32_t e = p.influence_start[from[v]]; e < p.influence_start[from[v] + 1]; ++e) {
        joint.push_back(p.influence_joint[e]);
        weight.push_back(p.influence_weight[e]);
      }
      start.push_back(static_cast<uint32_t>(joint.size()));
    }
    p.influence_start = std::move(start);
    p.influence_joint = std::move(joint);
    p.influence_weight = std::move(weight);
  }
}

// ExportOptions::optimize on every primitive of the export, the cache figures into `r`.
void optimize_export(Character& out, const ExportOptions& options, ExportResult& r) {
  if (!options.optimize) return;
  std::array<double, 2> before{0.0, 0.0}, after{0.0, 0.0};
  for (Primitive& p : out.primitives) optimize_primitive(p, before, after);
  r.acmr_before = before[1] > 0 ? before[0] / before[1] : 0.0;
  r.acmr_after = after[1] > 0 ? after[0] / after[1] : 0.0;
}

// Keys `weights` (#frames x #K, the clip's frames from `first`) on the clip's frame times.
// ExportOptions::quantize: the plan the writer follows, and the character snapped to it so that what is measured
// next is what the file holds.
void quantize_export(Character& out, const ExportOptions& options, ExportResult& r) {
  if (!options.quantize) return;
  r.quantization = plan_glb_quantization(out);
  snap_to_glb_quantization(out, *r.quantization);
}

AnimationSampler basis_weights(const std::vector<double>& times, size_t first, const std::vector<std::vector<float>>& weights) {
  AnimationSampler s;
  s.interpolation = Interpolation::kLinear;
  const size_t k = weights.empty() ? 0 : weights[0].size();
  s.components = static_cast<uint32_t>(k);
  s.times.assign(times.begin(), times.end());
  for (size_t f = 0; f < times.size(); ++f) s.values.insert(s.values.end(), weights[first + f].begin(), weights[first + f].end());
  return s;
}

// Keys one-hot morph weights over `total` targets: key k sets target first + k to 1.
AnimationSampler one_hot_weights(const std::vector<double>& times, size_t first, size_t total) {
  AnimationSampler s;
  s.interpolation = Interpolation::kLinear;
  s.components = static_cast<uint32_t>(total);
  s.times.assign(times.begin(), times.end());
  s.values.assign(times.size() * total, 0.0f);
  for (size_t k = 0; k < times.size(); ++k) s.values[k * total + first + k] = 1.0f;
  return s;
}

// The source clip's node channels (morph weight channels dropped: their meshes are not exported)
// plus, when `weights` has keys, a channel on `mesh_node` stepping through the frame targets.
Clip export_clip(const Clip& src, bool keep_nodes, uint32_t mesh_node, const AnimationSampler* weights) {
  Clip c;
  c.name = src.name;
  c.duration = src.duration;
  if (keep_nodes) {
    std::vector<int> index(src.samplers.size(), -1);
    for (const AnimationChannel& ch : src.channels) {
      if (ch.path == ChannelPath::kWeights) continue;
      if (index[ch.sampler] < 0) {
        index[ch.sampler] = static_cast<int>(c.samplers.size());
        c.samplers.push_back(src.samplers[ch.sampler]);
      }
      c.channels.push_back({ch.node, ch.path, static_cast<uint32_t>(index[ch.sampler])});
    }
  }
  if (weights) {
    c.channels.push_back({mesh_node, ChannelPath::kWeights, static_cast<uint32_t>(c.samplers.size())});
    c.samplers.push_back(*weights);
  }
  return c;
}

// The source's nodes plus a root node with identity transform for the exported mesh.
Result<Skeleton> skeleton_with_mesh_node(const Skeleton* source, const std::string& name) {
  std::vector<SkeletonNode> nodes = source ? source->nodes() : std::vector<SkeletonNode>{};
  SkeletonNode n;
  n.name = name;
  n.parent = -1;
  nodes.push_back(n);
  return Skeleton::create(std::move(nodes), "export");
}

// Copies of the character's primitives as one mesh on `node`.
std::vector<Primitive> export_primitives(const Character& ch, uint32_t node) {
  std::vector<Primitive> out;
  for (size_t i = 0; i < ch.primitives.size(); ++i) {
    const Primitive& p = ch.primitives[i];
    Primitive q;
    q.mesh_name = "skin";
    q.mesh = 0;
    q.primitive = static_cast<uint32_t>(i);
    q.node = node;
    q.positions = p.positions;
    q.triangles = p.triangles;
    out.push_back(std::move(q));
  }
  return out;
}

// Euclidean projection onto the simplex {w >= 0, sum w = 1} (Duchi et al., ICML 2008).
void project_simplex(Eigen::VectorXd& w) {
  Eigen::VectorXd u = w;
  std::sort(u.data(), u.data() + u.size(), std::greater<double>());
  double cum = 0.0, theta = 0.0;
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    cum += u[i];
    double t = (cum - 1.0) / double(i + 1);
    if (u[i] - t > 0.0) theta = t;
  }
  for (Eigen::Index i = 0; i < w.size(); ++i) w[i] = std::max(0.0, w[i] - theta);
}

// argmin over the simplex of w^T G w - 2 h^T w: FISTA with step 1 / (2 lambda_max(G)).
Eigen::VectorXd fit_simplex(const Eigen::MatrixXd& G, const Eigen::VectorXd& h, int iterations) {
  const Eigen::Index k = h.size();
  Eigen::VectorXd w = Eigen::VectorXd::Constant(k, 1.0 / double(k));
  if (k == 1) return w;
  Eigen::VectorXd v = Eigen::VectorXd::Ones(k);
  double lambda = 0.0;
  for (int i = 0; i < 30; ++i) {
    Eigen::VectorXd g = G * v;
    lambda = g.norm();
    if (!(lambda > 0.0)) return w;
    v = g / lambda;
  }
  const double step = 1.0 / (2.0 * lambda * 1.01);
  Eigen::VectorXd y = w, prev = w;
  double t = 1.0;
  for (int it = 0; it < iterations; ++it) {
    Eigen::VectorXd next = y - step * 2.0 * (G * y - h);
    project_simplex(next);
    double tn = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
    y = next + ((t - 1.0) / tn) * (next - prev);
    prev = next;
    t = tn;
  }
  return prev;
}

// The same problem solved exactly on a small support (k <= 8): the equality-constrained least squares on the
// active set (KKT system, its least-norm solution when G is singular), dropping the most negative weight
// until none is negative. Returns whichever of it and `start` (a feasible point) has the lower objective
// w^T G w - 2 h^T w: FISTA's 300 steps stop short on ill-conditioned G (joints that move together).
Eigen::VectorXd refine_simplex(const Eigen::MatrixXd& G, const Eigen::VectorXd& h, const Eigen::VectorXd& start) {
  const Eigen::Index k = h.size();
  auto objective = [&](const Eigen::VectorXd& w) { return w.dot(G * w) - 2.0 * h.dot(w); };
  std::vector<Eigen::Index> active(static_cast<size_t>(k));
  std::iota(active.begin(), active.end(), Eigen::Index(0));
  Eigen::VectorXd best = start;
  while (!active.empty()) {
    const Eigen::Index a = static_cast<Eigen::Index>(active.size());
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(a + 1, a + 1);
    Eigen::VectorXd rhs(a + 1);
    for (Eigen::Index i = 0; i < a; ++i) {
      for (Eigen::Index j = 0; j < a; ++j) kkt(i, j) = 2.0 * G(active[size_t(i)], active[size_t(j)]);
      kkt(i, a) = kkt(a, i) = 1.0;
      rhs(i) = 2.0 * h(active[size_t(i)]);
    }
    rhs(a) = 1.0;
    const Eigen::VectorXd x = kkt.completeOrthogonalDecomposition().solve(rhs);
    Eigen::Index worst = -1;
    for (Eigen::Index i = 0; i < a; ++i)
      if (!std::isfinite(x(i))) return best;
      else if (x(i) < 0.0 && (worst < 0 || x(i) < x(worst))) worst = i;
    if (worst < 0) {
      Eigen::VectorXd w = Eigen::VectorXd::Zero(k);
      for (Eigen::Index i = 0; i < a; ++i) w(active[size_t(i)]) = x(i);
      if (std::abs(w.sum() - 1.0) < 1e-9 && objective(w) < objective(best)) best = w;
      return best;
    }
    active.erase(active.begin() + worst);
  }
  return best;
}

// Weights (sorted, largest first) with sum exactly 1 in float32, summed in order as a reader would:
// the last (smallest) becomes 1 - (the sum of the others). That partial sum is at least 3/4 (the
// smallest of at most 4 weights is at most 1/4), so by Sterbenz's lemma 1 - partial is exact and
// partial + (1 - partial) = 1 exactly; the smallest weight moves by a rounding error (~1e-7).
void float_weights_summing_to_one(std::vector<float>& w) {
  if (w.size() == 1) {
    w[0] = 1.0f;
    return;
  }
  float partial = 0.0f;
  for (size_t i = 0; i + 1 < w.size(); ++i) partial += w[i];
  w.back() = std::max(0.0f, 1.0f - partial);
}

// LBS influences of every exported vertex (#P), at most kMaxInfluences, largest first, 0 = unused.
struct FittedWeights {
  std::vector<std::array<uint16_t, kMaxInfluences>> joint;
  std::vector<std::array<float, kMaxInfluences>> weight;
};

// The fit (see rig_export.h) of every skin point to the sampled poses: sample s has the skin's
// joint matrices joints[s] (#J) and the rig's positions x[s] (#P). Candidates: the point's own LBS
// joints (`original`), then the attachment joints of its nearest rest cage vertices. Runs in
// chunks of points so that progress is reported and cancel is seen; false when cancelled.
bool fit_weights(std::span<const glm::vec3> rest_skin, const std::vector<std::vector<uint32_t>>& original,
                 const std::vector<std::vector<float>>& original_weight, std::span<const glm::vec3> cage_rest, const CageAttachment& att,
                 const std::vector<const std::vector<glm::mat4>*>& joints,
                 const std::vector<const std::vector<glm::vec3>*>& x, size_t max_influences, StageProgress& progress,
                 FittedWeights& out) {
  const size_t np = rest_skin.size(), S = x.size();
  out.joint.assign(np, {});
  out.weight.assign(np, {});
  auto fit_point = [&](size_t v, std::vector<std::pair<float, uint32_t>>& near) {
    // Candidates: the vertex's own LBS joints, then the joints of its nearest cage vertices.
    std::vector<uint32_t> cand = original[v];
    near.clear();
    for (uint32_t c = 0; c < cage_rest.size(); ++c) {
      glm::vec3 d = cage_rest[c] - rest_skin[v];
      near.push_back({glm::dot(d, d), c});
    }
    const size_t kn = std::min(kNearestCageVertices, near.size());
    std::partial_sort(near.begin(), near.begin() + kn, near.end());
    for (size_t i = 0; i < kn; ++i)
      for (uint32_t e = att.influence_start[near[i].second]; e < att.influence_start[near[i].second + 1]; ++e)
        cand.push_back(att.influence_joint[e]);
    std::vector<uint32_t> uniq;
    for (uint32_t j : cand)
      if (std::find(uniq.begin(), uniq.end(), j) == uniq.end() && uniq.size() < kMaxCandidates)
        uniq.push_back(j);
    // the normal equations of the fit over joints `js`
    auto normal_equations = [&](const std::vector<uint32_t>& js, Eigen::MatrixXd& G, Eigen::VectorXd& h) {
      const Eigen::Index k = static_cast<Eigen::Index>(js.size());
      G = Eigen::MatrixXd::Zero(k, k);
      h = Eigen::VectorXd::Zero(k);
      std::vector<glm::dvec3> a(js.size());
      const glm::vec4 p(rest_skin[v], 1.0f);
      for (size_t s = 0; s < S; ++s) {
        for (size_t i = 0; i < js.size(); ++i) a[i] = glm::dvec3((*joints[s])[js[i]] * p);
        const glm::dvec3 xs((*x[s])[v]);
        for (Eigen::Index i = 0; i < k; ++i) {
          h[i] += glm::dot(a[i], xs);
          for (Eigen::Index j = i; j < k; ++j) G(i, j) += glm::dot(a[i], a[j]);
        }
      }
      G.triangularView<Eigen::StrictlyLower>() = G.transpose();
      // the prior: the character's own weights, which decide what the poses leave open (joints that never move in
      // them); kWeightPrior of the data's mean curvature elsewhere
      const double mu = kWeightPrior * std::max(G.trace() / double(std::max<Eigen::Index>(1, k)), 1e-300);
      for (Eigen::Index i = 0; i < k; ++i) {
        G(i, i) += mu;
        for (size_t o = 0; o < original[v].size(); ++o)
          if (original[v][o] == js[size_t(i)]) h[i] += mu * original_weight[v][o];
      }
    };
    auto solve = [&](const std::vector<uint32_t>& js) {
      Eigen::MatrixXd G;
      Eigen::VectorXd h;
      normal_equations(js, G, h);
      return fit_simplex(G, h, 300);
    };
    auto refine = [&](const std::vector<uint32_t>& js, const Eigen::VectorXd& start) {
      Eigen::MatrixXd G;
      Eigen::VectorXd h;
      normal_equations(js, G, h);
      return refine_simplex(G, h, start);
    };
    Eigen::VectorXd w = solve(uniq);
    std::vector<size_t> order(uniq.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return w[a] > w[b]; });
    std::vector<uint32_t> best;
    for (size_t i = 0; i < order.size() && best.size() < max_influences; ++i)
      if (best.empty() || w[order[i]] > 1e-6) best.push_back(uniq[order[i]]);
    Eigen::VectorXd wb = best.size() < uniq.size() ? solve(best) : Eigen::VectorXd();
    if (wb.size() == 0) {
      wb.resize(best.size());
      for (size_t i = 0; i < best.size(); ++i) wb[i] = w[order[i]];
    }
    wb = refine(best, wb);
    std::vector<std::pair<float, uint32_t>> kept;
    for (size_t i = 0; i < best.size(); ++i)
      if (wb[i] > 1e-6) kept.push_back({static_cast<float>(wb[i]), best[i]});
    if (kept.empty()) kept.push_back({1.0f, best[0]});
    std::sort(kept.begin(), kept.end(), [](auto& a, auto& b) { return a.first > b.first; });
    float sum = 0.0f;
    for (auto& [wt, j] : kept) sum += wt;
    std::vector<float> fw;
    for (auto& [wt, j] : kept) fw.push_back(wt / sum);
    float_weights_summing_to_one(fw);
    for (size_t i = 0; i < kept.size(); ++i) {
      out.joint[v][i] = static_cast<uint16_t>(kept[i].second);
      out.weight[v][i] = fw[i];
    }
  };
  constexpr size_t kChunk = 2048;
  for (size_t begin = 0; begin < np; begin += kChunk) {
    const size_t end = std::min(np, begin + kChunk);
    tbb::parallel_for(tbb::blocked_range<size_t>(begin, end, 64),
                      [&](const tbb::blocked_range<size_t>& range) {
                        std::vector<std::pair<float, uint32_t>> near;
                        for (size_t v = range.begin(); v != range.end(); ++v) fit_point(v, near);
                      });
    if (!progress.step(end, np)) return false;
  }
  return true;
}

// The export's pose at a pose of the source character: its nodes' local transforms (the export
// adds a mesh node after them), the mesh's morph weights left at their defaults (no clip plays).
Pose export_pose_at(const Character& exported, const Pose& source) {
  Pose p = sample_pose(exported, -1, 0.0);
  for (size_t i = 0; i < source.local.size() && i < p.local.size(); ++i) p.local[i] = source.local[i];
  return p;
}

}  // namespace

Result<std::vector<ExportClipFrames>> export_clip_frames(const Character& ch, const ExportOptions& options) {
  if (!(options.fps > 0.0) || !std::isfinite(options.fps))
    return make_error(ErrorCode::kInvalidArgument,
                      "the frame rate must be a positive number of frames per second");
  std::vector<int32_t> clips = options.clips;
  if (clips.empty())
    for (size_t i = 0; i < ch.clips.size(); ++i) clips.push_back(static_cast<int32_t>(i));
  std::vector<ExportClipFrames> frames;
  size_t total = 0;
  for (int32_t c : clips) {
    if (c < 0 || c >= static_cast<int32_t>(ch.clips.size()))
      return make_error(ErrorCode::kInvalidArgument, "clip " + std::to_string(c) +
                                                         " is out of range (the character has " +
                                                         std::to_string(ch.clips.size()) + ")");
    frames.push_back({c, export_frame_times(ch.clips[c].duration, options.fps), total});
    total += frames.back().times.size();
  }
  return frames;
}

std::vector<std::string> obj_sequence_paths(const Character& ch, std::span<const ExportClipFrames> frames,
                                            const std::string& out) {
  namespace fs = std::filesystem;
  const bool stem = has_extension(out, ".obj");
  const fs::path folder = stem ? fs::path(out).parent_path() : fs::path(out);
  const std::string prefix = stem ? fs::path(out).stem().string() + "_" : std::string();
  std::vector<std::string> names, paths;
  for (const ExportClipFrames& cf : frames) {
    std::string name =
        cf.clip >= 0 && cf.clip < static_cast<int32_t>(ch.clips.size()) ? ch.clips[cf.clip].name : "";
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    if (name.empty() || name == "." || name == ".." ||
        std::find(names.begin(), names.end(), name) != names.end())
      name = "clip" + std::to_string(cf.clip);
    names.push_back(name);
    const int digits = std::max<int>(4, static_cast<int>(std::to_string(cf.times.size() - 1).size()));
    for (size_t k = 0; k < cf.times.size(); ++k) {
      std::string index = std::to_string(k);
      index.insert(0, static_cast<size_t>(std::max<int>(0, digits - static_cast<int>(index.size()))), '0');
      paths.push_back((folder / (prefix + name + "_" + index + ".obj")).string());
    }
  }
  return paths;
}

Result<ObjSequence> export_obj_sequence(const Document& doc, Rig& rig, const ExportOptions& options,
                                        const std::string& out, const ExportProgress& progress) {
  namespace fs = std::filesystem;
  if (!doc.character || !doc.cage)
    return make_error(ErrorCode::kInvalidArgument,
                      "the document needs a character and a cage to export its rig");
  const Character& ch = *doc.character;
  auto clip_frames = export_clip_frames(ch, options);
  if (!clip_frames) return clip_frames.error();
  const std::vector<ExportClipFrames>& frames = *clip_frames;
  ObjSequence r;
  r.files = obj_sequence_paths(ch, frames, out);
  r.frames = r.files.size();
  if (!has_extension(out, ".obj")) {
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec || !fs::is_directory(out))
      return make_error(ErrorCode::kWrite, out + ": the folder for the OBJ files cannot be made (" +
                                               (ec ? ec.message() : std::string("a file is in the way")) +
                                               ")");
  }
  const bool cage = options.mode == ExportMode::kCage;
  const PolyMesh topology = cage ? doc.cage->polygons : combined_topology(ch);
  std::vector<glm::vec3> skin(rig.num_skin_points());
  PosedCage posed;
  StageProgress stage(progress);
  stage.begin("writing", 0.0, 1.0);
  // On failure or cancel the files written so far go: no partial sequence is left behind.
  auto fail = [&](size_t written, Error e) {
    for (size_t i = 0; i < written; ++i) {
      std::error_code ec;
      fs::remove(r.files[i], ec);
    }
    return e;
  };
  for (const ExportClipFrames& cf : frames)
    for (size_t k = 0; k < cf.times.size(); ++k) {
      const size_t f = cf.first + k;
      if (auto s = rig.pose_clip(doc, cf.clip, cf.times[k], {}, posed, skin); !s)
        return fail(f, s.error());
      const std::string& path = r.files[f];
      if (auto s = save_obj(
              path, cage ? std::span<const glm::vec3>(posed.positions) : std::span<const glm::vec3>(skin),
              topology);
          !s)
        return fail(f, s.error());  // not ours to remove: the file may have been there before
      std::error_code ec;
      r.bytes += fs::file_size(path, ec);
      if (!stage.step(f + 1, r.frames)) return fail(f + 1, cancelled());
    }
  return r;
}

std::vector<Pose> keypose_sweep_poses(const Character& ch, std::span<const KeyposeSet> sets, int steps) {
  std::vector<Pose> poses;
  const Pose rest = ch.skeleton.rest_pose();
  for (size_t i = 0; i < sets.size(); ++i) {
    const KeyposeSet& set = sets[i];
    if (!keypose_set_active(sets, i) || !validate_keypose_set(set, ch.skeleton.size(), SIZE_MAX)) continue;
    for (const KeyposeKey& key : set.keys) {
      if (std::all_of(key.values.begin(), key.values.end(), [](double v) { return v == 0.0; })) continue;
      for (int s = 1; s <= steps; ++s) {
        std::vector<double> values = key.values;
        for (double& v : values) v *= double(s) / double(steps);
        poses.push_back(pose_at_driver_values(set, values, ch.skeleton, rest));
      }
    }
  }
  return poses;
}

Result<ExportResult> export_rig(const Document& doc, Rig& rig, const ExportOptions& options,
                                const ExportProgress& progress) {
  if (!doc.character || !doc.cage)
    return make_error(ErrorCode::kInvalidArgument,
                      "the document needs a character and a cage to export its rig");
  const Character& ch = *doc.character;
  const CageAttachment* att = rig.attachment();
  if (options.mode != ExportMode::kBakedAnimation && !att)
    return make_error(
        ErrorCode::kInvalidArgument,
        std::string(export_mode_name(options.mode)) +
            " needs a skeleton the cage follows; the character has no skin (use baked-animation)");
  auto clip_frames = export_clip_frames(ch, options);
  if (!clip_frames) return clip_frames.error();
  const std::vector<ExportClipFrames>& frames = *clip_frames;

  ExportResult r;
  for (const ExportClipFrames& cf : frames) r.frames += cf.times.size();
  const bool pose_driven = options.correctives == ExportOptions::Correctives::kPoseDriven;
  if (pose_driven && options.mode != ExportMode::kBakedSkin)
    return make_error(ErrorCode::kInvalidArgument, "pose-driven correctives are for baked-skin: they ride on its fitted skeleton");
  // the held-out clip's frames [held_first, held_end) are left out of every fit
  size_t held_first = 0, held_end = 0;
  if (options.hold_out >= 0) {
    if (!pose_driven)
      return make_error(ErrorCode::kInvalidArgument, "holding a clip out is for pose-driven correctives (--correctives pose-driven)");
    auto held = std::find_if(frames.begin(), frames.end(), [&](const ExportClipFrames& cf) { return cf.clip == options.hold_out; });
    const std::string name = size_t(options.hold_out) < ch.clips.size() ? "'" + ch.clips[options.hold_out].name + "'"
                                                                         : std::to_string(options.hold_out);
    if (held == frames.end())
      return make_error(ErrorCode::kInvalidArgument, "the held-out clip " + name + " is not one of the exported clips");
    if (frames.size() < 2)
      return make_error(ErrorCode::kInvalidArgument, "holding out " + name + ", the only exported clip, leaves nothing to fit");
    held_first = held->first;
    held_end = held->first + held->times.size();
  }
  auto held_out = [&](size_t f) { return f >= held_first && f < held_end; };
  if (!doc.keyposes.empty() && options.mode == ExportMode::kCage)
    r.warnings.push_back("the cage export leaves out the " + std::to_string(doc.keyposes.size()) +
                         " keypose set(s): a skinned cage cannot carry them");
  // Shares of the whole export by stage (posing the rig dominates; the fit is next).
  const bool skin_fit = options.mode == ExportMode::kBakedSkin;
  const double posed_until = skin_fit ? 0.35 : options.mode == ExportMode::kCage ? 0.8 : 0.6;
  StageProgress stage(progress);

  // The rig at every frame and every keypose pose (#F + #K x #P), its posed cages (#Vc) and the
  // skin's joint matrices (#J).
  const std::vector<Pose> keypose_poses = options.mode == ExportMode::kBakedAnimation || !att
                                              ? std::vector<Pose>{}
                                              : keypose_sweep_poses(ch, doc.keyposes, options.keypose_steps);
  r.keypose_poses = keypose_poses.size();
  const size_t np = rig.num_skin_points(), posed_count = r.frames + r.keypose_poses;
  std::vector<std::vector<glm::vec3>> skins(posed_count, std::vector<glm::vec3>(np));
  std::vector<std::vector<glm::vec3>> cages(posed_count);
  std::vector<std::vector<glm::mat4>> joints(posed_count);
  {
    PosedCage posed;
    // a clip frame (clip >= 0: with the cage's simulation when it is on) or a keypose pose
    auto pose_rig = [&](int32_t clip, double t, const Pose* pose, size_t f) -> Status {
      if (auto s = pose ? rig.pose(doc, *pose, posed, skins[f]) : rig.pose_clip(doc, clip, t, {}, posed, skins[f]); !s)
        return s.error();
      cages[f] = posed.positions;
      if (att) {
        joints[f].resize(ch.skins[att->skin].joints.size());
        joint_matrices(ch.skins[att->skin], posed.globals, joints[f]);
      }
      return Ok{};
    };
    stage.begin("posing", 0.0, posed_until * double(r.frames) / double(std::max<size_t>(1, posed_count)));
    for (const ExportClipFrames& cf : frames)
      for (size_t k = 0; k < cf.times.size(); ++k) {
        if (auto s = pose_rig(cf.clip, cf.times[k], nullptr, cf.first + k); !s)
          return s.error();
        if (!stage.step(cf.first + k + 1, r.frames)) return cancelled();
      }
    stage.begin("keyposes", posed_until * double(r.frames) / double(std::max<size_t>(1, posed_count)),
                posed_until);
    for (size_t k = 0; k < keypose_poses.size(); ++k) {
      if (auto s = pose_rig(-1, 0.0, &keypose_poses[k], r.frames + k); !s) return s.error();
      if (!stage.step(k + 1, keypose_poses.size())) return cancelled();
    }
  }

  const std::string node_name = options.mode == ExportMode::kCage ? "cage" : "skin";
  auto sk = skeleton_with_mesh_node(options.mode == ExportMode::kBakedAnimation ? nullptr : &ch.skeleton,
                                    node_name);
  if (!sk) return sk.error();
  Character& out = r.character;
  out.source = "cagewrap export (" + std::string(export_mode_name(options.mode)) + ") of " + ch.source;
  out.skeleton = std::move(sk).value();
  const uint32_t mesh_node = static_cast<uint32_t>(out.skeleton.size() - 1);
  if (options.mode != ExportMode::kBakedAnimation) out.skins = ch.skins;
  // the reports' scale (every mode, the cage's too)
  const Aabb rest_box = bounding_box(rig.skin_rest());
  r.diagonal = rest_box.empty() ? 0.0 : rest_box.diagonal();

  if (options.mode == ExportMode::kCage) {
    Primitive p;
    p.mesh_name = "cage";
    p.node = mesh_node;
    p.skin = static_cast<int32_t>(att->skin);
    Pose rest = ch.skeleton.rest_pose();
    PosedCage posed;
    pose_document_cage(doc, att, rest, posed);
    p.positions = posed.driver_rest;
    p.triangles = doc.cage->elements;
    p.influence_start = att->influence_start;
    p.influence_joint.assign(att->influence_joint.begin(), att->influence_joint.end());
    p.influence_weight = att->influence_weight;
    out.primitives.push_back(std::move(p));
    for (const ExportClipFrames& cf : frames)
      out.clips.push_back(export_clip(ch.clips[cf.clip], true, mesh_node, nullptr));
    quantize_export(out, options, r);
    stage.begin("measuring", posed_until, 1.0);
    for (size_t c = 0; c < frames.size(); ++c)
      for (size_t k = 0; k < frames[c].times.size(); ++k) {
        Pose pose = sample_pose(out, static_cast<int32_t>(c), frames[c].times[k]);
        accumulate(r.at_frames, skin_character(out, pose), cages[frames[c].first + k]);
        if (!stage.step(frames[c].first + k + 1, posed_count)) return cancelled();
      }
    for (size_t k = 0; k < keypose_poses.size(); ++k) {
      accumulate(r.at_keyposes, skin_character(out, export_pose_at(out, keypose_poses[k])),
                 cages[r.frames + k]);
      if (!stage.step(r.frames + k + 1, posed_count)) return cancelled();
    }
    r.fitted = r.at_frames;
    optimize_export(out, options, r);
    const GlbPartSizes sizes = glb_part_sizes(out, r.quantization ? &*r.quantization : nullptr);
    r.sizes = {sizes.mesh, sizes.skin, sizes.targets, sizes.animation};
    return r;
  }

  out.primitives = export_primitives(ch, mesh_node);
  const std::vector<glm::vec3> rest_skin(rig.skin_rest().begin(), rig.skin_rest().end());
  // Skinning of every exported vertex (empty for baked-animation: identity).
  FittedWeights fitted;

  if (skin_fit) {
    const Skin& skin = ch.skins[att->skin];
    const size_t nj = skin.joints.size();
    // Fitting samples: the rest pose, every frame and (unless told not to) the keypose sweep.
    std::vector<glm::mat4> rest_joints(nj);
    joint_matrices(skin, ch.skeleton.global_transforms(ch.skeleton.rest_pose()), rest_joints);
    std::vector<glm::vec3> rest_rig(np);
    {
      PosedCage posed;
      if (auto s = rig.pose(doc, ch.skeleton.rest_pose(), posed, rest_rig); !s) return s.error();
    }
    std::vector<const std::vector<glm::mat4>*> sample_joints{&rest_joints};
    std::vector<const std::vector<glm::vec3>*> sample_x{&rest_rig};
    const size_t fitted_poses = options.fit_keyposes ? posed_count : r.frames;
    for (size_t f = 0; f < fitted_poses; ++f) {
      if (held_out(f)) continue;
      sample_joints.push_back(&joints[f]);
      sample_x.push_back(&skins[f]);
    }
    // Original LBS joints and weights per point (when the primitive uses the cage's skin).
    std::vector<std::vector<uint32_t>> original(np);
    std::vector<std::vector<float>> original_weight(np);
    {
      size_t off = 0;
      for (const Primitive& p : ch.primitives) {
        if (p.skin == static_cast<int32_t>(att->skin) && !p.influence_start.empty())
          for (size_t v = 0; v < p.num_vertices(); ++v)
            for (uint32_t e = p.influence_start[v]; e < p.influence_start[v + 1]; ++e) {
              original[off + v].push_back(p.influence_joint[e]);
              original_weight[off + v].push_back(p.influence_weight[e]);
            }
        off += p.num_vertices();
      }
    }
    stage.begin("fitting", posed_until, 0.7);
    if (!fit_weights(rest_skin, original, original_weight, doc.cage_positions(), *att, sample_joints, sample_x,
                     std::clamp<size_t>(size_t(options.max_influences), 1, kMaxInfluences), stage, fitted))
      return cancelled();
    size_t off = 0;
    for (Primitive& p : out.primitives) {
      p.skin = static_cast<int32_t>(att->skin);
      p.influence_start.assign(1, 0);
      for (size_t v = 0; v < p.num_vertices(); ++v) {
        for (size_t i = 0; i < kMaxInfluences; ++i)
          if (fitted.weight[off + v][i] > 0.0f) {
            p.influence_joint.push_back(fitted.joint[off + v][i]);
            p.influence_weight.push_back(fitted.weight[off + v][i]);
          }
        p.influence_start.push_back(static_cast<uint32_t>(p.influence_joint.size()));
        r.influences = std::max<size_t>(r.influences, p.num_influences(v));
      }
      off += p.num_vertices();
    }
  }

  // The residual of each frame (and, compressed, of each fitted keypose pose): what takes the exported mesh
  // (unskinned, or skinned with the fitted weights) to the rig's skin there, in bind space.
  const size_t max_targets = static_cast<size_t>(std::max(0, corrective_targets(options)));
  const bool compress = max_targets > 0;
  const size_t shapes = pose_driven || (compress && skin_fit && options.fit_keyposes) ? posed_count : r.frames;
  std::vector<std::vector<glm::vec3>> residuals(shapes, std::vector<glm::vec3>(np));
  const double targets_until = skin_fit ? 0.8 : 0.7;
  stage.begin("correctives", skin_fit ? 0.7 : posed_until, compress ? (skin_fit ? 0.74 : 0.64) : targets_until);
  for (size_t f = 0; f < shapes; ++f) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, np, 1024), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        if (fitted.joint.empty()) {
          residuals[f][i] = skins[f][i] - rest_skin[i];
          continue;
        }
        glm::dmat4 m(0.0);
        for (size_t k = 0; k < kMaxInfluences; ++k)
          if (fitted.weight[i][k] > 0.0f) m += double(fitted.weight[i][k]) * glm::dmat4(joints[f][fitted.joint[i][k]]);
        const glm::dvec3 lbs(m * glm::dvec4(glm::dvec3(rest_skin[i]), 1.0));
        const glm::dvec3 residual = glm::dvec3(skins[f][i]) - lbs;
        const glm::dmat3 l(m);
        const double det = glm::determinant(l);
        residuals[f][i] = glm::vec3(std::abs(det) > 1e-12 ? glm::inverse(l) * residual : residual);
      }
    });
    if (!stage.step(f + 1, shapes)) return cancelled();
  }
  // the targets: one per frame, or the residuals' first principal components with each frame's weights
  std::vector<std::vector<glm::vec3>> targets;
  CompressedTargets basis;
  std::string mesh_extras;
  if (pose_driven) {
    stage.begin("pose correctives", 0.74, targets_until);
    const Skin& skin = ch.skins[att->skin];
    std::vector<Pose> poses;
    for (const ExportClipFrames& cf : frames)
      for (double t : cf.times) poses.push_back(sample_pose(ch, cf.clip, t));
    poses.insert(poses.end(), keypose_poses.begin(), keypose_poses.end());
    std::vector<bool> fit(posed_count);
    for (size_t f = 0; f < posed_count; ++f) fit[f] = !held_out(f) && (f < r.frames || options.fit_keyposes);
    // each point's nodes: those of its fitted joints and their children
    std::vector<std::vector<uint32_t>> point_nodes(np);
    for (size_t i = 0; i < np; ++i) {
      for (size_t k = 0; k < kMaxInfluences; ++k) {
        if (fitted.weight[i][k] <= 0.0f || fitted.joint[i][k] >= skin.joints.size()) continue;
        const uint32_t node = skin.joints[fitted.joint[i][k]];
        point_nodes[i].push_back(node);
        for (uint32_t c : ch.skeleton.children(node)) point_nodes[i].push_back(c);
      }
    }
    const std::vector<JointDriver> drivers = pose_corrective_drivers(doc.keyposes, skin.joints);
    PoseCorrectiveFit pf;
    if (!fit_pose_correctives(ch.skeleton, drivers, poses, residuals, fit, point_nodes, max_targets ? max_targets : kDefaultMaxTargets,
                              [&](size_t done, size_t total) { return stage.step(done, total); }, pf))
      return cancelled();
    mesh_extras = pose_correctives_extras(ch.skeleton, pf);
    targets = std::move(pf.targets);
    basis.weights = std::move(pf.weights);
    r.residual_rank = pf.rank;
    for (const PoseFeature& f : pf.features) r.pose_features.push_back(f.name);

  } else if (compress) {
    stage.begin("compressing", skin_fit ? 0.74 : 0.64, targets_until);
    if (!compress_targets(residuals, max_targets, options.max_error, stage, basis)) return cancelled();
    targets = std::move(basis.basis);
    r.residual_rank = basis.rank;
    r.basis_error = basis.max_error;
    if (options.max_error > 0.0 && basis.max_error > options.max_error)
      r.warnings.push_back("the " + std::to_string(targets.size()) + " corrective targets allowed (--max-targets) leave " +
                           std::to_string(basis.max_error) + " of error over the frames, more than --max-error " +
                           std::to_string(options.max_error) + "; allow more targets");
  } else {
    residuals.resize(r.frames);
    targets = std::move(residuals);
  }
  r.morph_targets = targets.size();
  {
    size_t off = 0;
    for (Primitive& p : out.primitives) {
      p.morph_targets.assign(targets.size(), std::vector<glm::vec3>(p.num_vertices()));
      p.morph_weights.assign(targets.size(), 0.0f);
      for (size_t t = 0; t < targets.size(); ++t)
        std::copy(targets[t].begin() + std::ptrdiff_t(off), targets[t].begin() + std::ptrdiff_t(off + p.num_vertices()),
                  p.morph_targets[t].begin());
      off += p.num_vertices();
    }
  }
  targets = {};
  if (!out.primitives.empty()) out.primitives[0].mesh_extras = mesh_extras;
  for (const ExportClipFrames& cf : frames) {
    AnimationSampler w = compress || pose_driven ? basis_weights(cf.times, cf.first, basis.weights) : one_hot_weights(cf.times, cf.first, r.frames);
    const bool keyed = r.morph_targets > 0;
    out.clips.push_back(export_clip(ch.clips[cf.clip], skin_fit, mesh_node, keyed ? &w : nullptr));
    out.clips.back().duration = std::max(out.clips.back().duration, cf.times.back());
  }

  quantize_export(out, options, r);
  // Errors against the rig, measured on the exported character itself (what a loader sees, quantized
  // when asked), and against the file's own skinning at the same frames.
  stage.begin("measuring", targets_until, 1.0);
  PosedCage posed;
  std::vector<glm::vec3> live(np);
  for (size_t c = 0; c < frames.size(); ++c) {
    const ExportClipFrames& cf = frames[c];
    ExportResult::ClipErrors& clip_errors = r.clips.emplace_back();
    clip_errors.name = ch.clips[cf.clip].name;
    clip_errors.frames = cf.times.size();
    clip_errors.held_out = held_out(cf.first);
    for (size_t k = 0; k < cf.times.size(); ++k) {
      Pose pose = sample_pose(out, static_cast<int32_t>(c), cf.times[k]);
      const std::vector<glm::vec3> exported = skin_character(out, pose);
      accumulate(r.at_frames, exported, skins[cf.first + k]);
      accumulate(clip_errors.at_frames, exported, skins[cf.first + k]);
      if (!ch.skins.empty()) accumulate(r.vs_file, exported, skin_character(ch, sample_pose(ch, cf.clip, cf.times[k])));
      if (skin_fit) {
        pose.morph_weights[mesh_node].assign(r.morph_targets, 0.0f);
        const std::vector<glm::vec3> alone = skin_character(out, pose);
        accumulate(r.fitted, alone, skins[cf.first + k]);
        accumulate(clip_errors.fitted, alone, skins[cf.first + k]);
      }
      if (k + 1 < cf.times.size()) {
        const double mid = 0.5 * (cf.times[k] + cf.times[k + 1]);
        if (auto s = rig.pose_clip(doc, cf.clip, mid, {}, posed, live); !s) return s.error();
        const std::vector<glm::vec3> between = skin_character(out, sample_pose(out, static_cast<int32_t>(c), mid));
        accumulate(r.between_frames, between, live);
        accumulate(clip_errors.between_frames, between, live);
      }
      if (!stage.step(cf.first + k + 1, posed_count)) return cancelled();
    }
  }
  for (size_t k = 0; k < keypose_poses.size(); ++k) {
    Pose pose = export_pose_at(out, keypose_poses[k]);
    if (pose_driven) pose.morph_weights[mesh_node] = basis.weights[r.frames + k];  // the drivers' weights there
    accumulate(r.at_keyposes, skin_character(out, pose), skins[r.frames + k]);
    if (!stage.step(r.frames + k + 1, posed_count)) return cancelled();
  }
  if (options.mode == ExportMode::kBakedAnimation) r.fitted = r.at_frames;
  optimize_export(out, options, r);
  const GlbPartSizes sizes = glb_part_sizes(out, r.quantization ? &*r.quantization : nullptr);
  r.sizes = {sizes.mesh, sizes.skin, sizes.targets, sizes.animation};
  return r;
}

}  // namespace cagewrap
