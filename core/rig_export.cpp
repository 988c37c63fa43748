#include "core/rig_export.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <numeric>

#include "core/skinning.h"

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

constexpr size_t kMaxInfluences = 4;
constexpr size_t kNearestCageVertices = 8;
constexpr size_t kMaxCandidates = 16;

struct ClipFrames {
  int32_t clip;               // index in the source character
  std::vector<double> times;  // export_frame_times
  size_t first_target;        // its frames' morph targets start here
};

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

}  // namespace

Result<ExportResult> export_rig(const Document& doc, Rig& rig, const ExportOptions& options) {
  if (!doc.character || !doc.cage)
    return make_error(ErrorCode::kInvalidArgument,
                      "the document needs a character and a cage to export its rig");
  if (!(options.fps > 0.0) || !std::isfinite(options.fps))
    return make_error(ErrorCode::kInvalidArgument,
                      "the frame rate must be a positive number of frames per second");
  const Character& ch = *doc.character;
  const CageAttachment* att = rig.attachment();
  if (options.mode != ExportMode::kBakedAnimation && !att)
    return make_error(
        ErrorCode::kInvalidArgument,
        std::string(export_mode_name(options.mode)) +
            " needs a skeleton the cage follows; the character has no skin (use baked-animation)");
  std::vector<int32_t> clips = options.clips;
  if (clips.empty())
    for (size_t i = 0; i < ch.clips.size(); ++i) clips.push_back(static_cast<int32_t>(i));
  for (int32_t c : clips)
    if (c < 0 || c >= static_cast<int32_t>(ch.clips.size()))
      return make_error(ErrorCode::kInvalidArgument, "clip " + std::to_string(c) +
                                                         " is out of range (the character has " +
                                                         std::to_string(ch.clips.size()) + ")");

  ExportResult r;
  std::vector<ClipFrames> frames;
  for (int32_t c : clips) {
    frames.push_back({c, export_frame_times(ch.clips[c].duration, options.fps), r.frames});
    r.frames += frames.back().times.size();
  }
  if (!doc.keyposes.empty() && options.mode == ExportMode::kCage)
    r.warnings.push_back("the cage export leaves out the " + std::to_string(doc.keyposes.size()) +
                         " keypose set(s): a skinned cage cannot carry them");

  // The rig at every frame (#F x #P) and its posed cages (#F x #Vc).
  const size_t np = rig.num_skin_points();
  std::vector<std::vector<glm::vec3>> skins(r.frames, std::vector<glm::vec3>(np));
  std::vector<std::vector<glm::vec3>> cages(r.frames);
  std::vector<std::vector<glm::mat4>> joints(r.frames);
  {
    PosedCage posed;
    for (const ClipFrames& cf : frames)
      for (size_t k = 0; k < cf.times.size(); ++k) {
        const size_t f = cf.first_target + k;
        Pose pose = compose_pose(ch, cf.clip, cf.times[k], false);
        if (auto s = rig.pose(doc, pose, posed, skins[f]); !s) return s.error();
        cages[f] = posed.positions;
        if (att) {
          joints[f].resize(ch.skins[att->skin].joints.size());
          joint_matrices(ch.skins[att->skin], posed.globals, joints[f]);
        }
      }
  }

  const bool baked = options.mode != ExportMode::kCage;
  const std::string node_name = options.mode == ExportMode::kCage ? "cage" : "skin";
  auto sk = skeleton_with_mesh_node(options.mode == ExportMode::kBakedAnimation ? nullptr : &ch.skeleton,
                                    node_name);
  if (!sk) return sk.error();
  Character& out = r.character;
  out.source = "cagewrap export (" + std::string(export_mode_name(options.mode)) + ") of " + ch.source;
  out.skeleton = std::move(sk).value();
  const uint32_t mesh_node = static_cast<uint32_t>(out.skeleton.size() - 1);
  if (options.mode != ExportMode::kBakedAnimation) out.skins = ch.skins;

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
    for (const ClipFrames& cf : frames)
      out.clips.push_back(export_clip(ch.clips[cf.clip], true, mesh_node, nullptr));
    for (size_t c = 0; c < frames.size(); ++c)
      for (size_t k = 0; k < frames[c].times.size(); ++k) {
        Pose pose = sample_pose(out, static_cast<int32_t>(c), frames[c].times[k]);
        std::vector<glm::vec3> mine = skin_character(out, pose);
        accumulate(r.at_frames, mine, cages[frames[c].first_target + k]);
      }
    r.fitted = r.at_frames;
    return r;
  }

  out.primitives = export_primitives(ch, mesh_node);
  const std::vector<glm::vec3> rest_skin(rig.skin_rest().begin(), rig.skin_rest().end());
  // Skinning of every exported vertex (#P; empty for baked-animation: identity).
  std::vector<std::array<uint16_t, kMaxInfluences>> inf_joint;
  std::vector<std::array<float, kMaxInfluences>> inf_weight;

  if (options.mode == ExportMode::kBakedSkin) {
    const Skin& skin = ch.skins[att->skin];
    const size_t nj = skin.joints.size();
    // Fitting samples: the rest pose and every frame.
    std::vector<std::vector<glm::mat4>> sample_joints = joints;
    std::vector<const std::vector<glm::vec3>*> sample_x;
    for (auto& s : skins) sample_x.push_back(&s);
    {
      std::vector<glm::mat4> rj(nj);
      joint_matrices(skin, ch.skeleton.global_transforms(ch.skeleton.rest_pose()), rj);
      sample_joints.push_back(rj);
    }
    std::vector<glm::vec3> rest_rig(np);
    {
      PosedCage posed;
      if (auto s = rig.pose(doc, ch.skeleton.rest_pose(), posed, rest_rig); !s) return s.error();
    }
    sample_x.push_back(&rest_rig);
    const size_t S = sample_x.size();
    // Original LBS joints per point (when the primitive uses the cage's skin).
    std::vector<std::vector<uint32_t>> original(np);
    {
      size_t off = 0;
      for (const Primitive& p : ch.primitives) {
        if (p.skin == static_cast<int32_t>(att->skin) && !p.influence_start.empty())
          for (size_t v = 0; v < p.num_vertices(); ++v)
            for (uint32_t e = p.influence_start[v]; e < p.influence_start[v + 1]; ++e)
              original[off + v].push_back(p.influence_joint[e]);
        off += p.num_vertices();
      }
    }
    const auto cage_rest = doc.cage_positions();
    inf_joint.resize(np);
    inf_weight.resize(np);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, np, 256), [&](const tbb::blocked_range<size_t>& range) {
      std::vector<std::pair<float, uint32_t>> near;
      for (size_t v = range.begin(); v != range.end(); ++v) {
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
          for (uint32_t e = att->influence_start[near[i].second];
               e < att->influence_start[near[i].second + 1]; ++e)
            cand.push_back(att->influence_joint[e]);
        std::vector<uint32_t> uniq;
        for (uint32_t j : cand)
          if (std::find(uniq.begin(), uniq.end(), j) == uniq.end() && uniq.size() < kMaxCandidates)
            uniq.push_back(j);
        auto solve = [&](const std::vector<uint32_t>& js) {
          const Eigen::Index k = static_cast<Eigen::Index>(js.size());
          Eigen::MatrixXd G = Eigen::MatrixXd::Zero(k, k);
          Eigen::VectorXd h = Eigen::VectorXd::Zero(k);
          std::vector<glm::dvec3> a(js.size());
          const glm::vec4 p(rest_skin[v], 1.0f);
          for (size_t s = 0; s < S; ++s) {
            for (size_t i = 0; i < js.size(); ++i) a[i] = glm::dvec3(sample_joints[s][js[i]] * p);
            const glm::dvec3 x((*sample_x[s])[v]);
            for (Eigen::Index i = 0; i < k; ++i) {
              h[i] += glm::dot(a[i], x);
              for (Eigen::Index j = i; j < k; ++j) G(i, j) += glm::dot(a[i], a[j]);
            }
          }
          G.triangularView<Eigen::StrictlyLower>() = G.transpose();
          return fit_simplex(G, h, 300);
        };
        Eigen::VectorXd w = solve(uniq);
        std::vector<size_t> order(uniq.size());
        std::iota(order.begin(), order.end(), 0);
        std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return w[a] > w[b]; });
        std::vector<uint32_t> best;
        for (size_t i = 0; i < order.size() && best.size() < kMaxInfluences; ++i)
          if (best.empty() || w[order[i]] > 1e-6) best.push_back(uniq[order[i]]);
        Eigen::VectorXd wb = best.size() < uniq.size() ? solve(best) : Eigen::VectorXd();
        if (wb.size() == 0) {
          wb.resize(best.size());
          for (size_t i = 0; i < best.size(); ++i) wb[i] = w[order[i]];
        }
        std::vector<std::pair<float, uint32_t>> kept;
        for (size_t i = 0; i < best.size(); ++i)
          if (wb[i] > 1e-6) kept.push_back({static_cast<float>(wb[i]), best[i]});
        if (kept.empty()) kept.push_back({1.0f, best[0]});
        std::sort(kept.begin(), kept.end(), [](auto& a, auto& b) { return a.first > b.first; });
        float sum = 0.0f;
        for (auto& [x, j] : kept) sum += x;
        std::vector<float> fw;
        for (auto& [x, j] : kept) fw.push_back(x / sum);
        float_weights_summing_to_one(fw);
        inf_joint[v].fill(0);
        inf_weight[v].fill(0.0f);
        for (size_t i = 0; i < kept.size(); ++i) {
          inf_joint[v][i] = static_cast<uint16_t>(kept[i].second);
          inf_weight[v][i] = fw[i];
        }
      }
    });
    size_t off = 0;
    for (Primitive& p : out.primitives) {
      p.skin = static_cast<int32_t>(att->skin);
      p.influence_start.assign(1, 0);
      for (size_t v = 0; v < p.num_vertices(); ++v) {
        for (size_t i = 0; i < kMaxInfluences; ++i)
          if (inf_weight[off + v][i] > 0.0f) {
            p.influence_joint.push_back(inf_joint[off + v][i]);
            p.influence_weight.push_back(inf_weight[off + v][i]);
          }
        p.influence_start.push_back(static_cast<uint32_t>(p.influence_joint.size()));
      }
      off += p.num_vertices();
    }
  }

  // One morph target per frame: what takes the exported mesh (unskinned, or skinned with the fitted
  // weights) to the rig's skin at that frame, in bind space.
  r.morph_targets = r.frames;
  for (Primitive& p : out.primitives) {
    p.morph_targets.assign(r.frames, std::vector<glm::vec3>(p.num_vertices()));
    p.morph_weights.assign(r.frames, 0.0f);
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, r.frames), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t f = range.begin(); f != range.end(); ++f) {
      size_t off = 0;
      for (Primitive& p : out.primitives) {
        for (size_t v = 0; v < p.num_vertices(); ++v) {
          const size_t i = off + v;
          if (inf_joint.empty()) {
            p.morph_targets[f][v] = skins[f][i] - rest_skin[i];
            continue;
          }
          glm::dmat4 m(0.0);
          for (size_t k = 0; k < kMaxInfluences; ++k)
            if (inf_weight[i][k] > 0.0f)
              m += double(inf_weight[i][k]) * glm::dmat4(joints[f][inf_joint[i][k]]);
          const glm::dvec3 lbs(m * glm::dvec4(glm::dvec3(rest_skin[i]), 1.0));
          const glm::dvec3 residual = glm::dvec3(skins[f][i]) - lbs;
          const glm::dmat3 l(m);
          const double det = glm::determinant(l);
          p.morph_targets[f][v] = glm::vec3(std::abs(det) > 1e-12 ? glm::inverse(l) * residual : residual);
        }
        off += p.num_vertices();
      }
    }
  });
  for (const ClipFrames& cf : frames) {
    AnimationSampler w = one_hot_weights(cf.times, cf.first_target, r.frames);
    out.clips.push_back(
        export_clip(ch.clips[cf.clip], options.mode == ExportMode::kBakedSkin, mesh_node, &w));
    out.clips.back().duration = std::max(out.clips.back().duration, cf.times.back());
  }

  // Errors against the rig, measured on the exported character itself (what a loader sees).
  PosedCage posed;
  std::vector<glm::vec3> live(np);
  for (size_t c = 0; c < frames.size(); ++c) {
    const ClipFrames& cf = frames[c];
    for (size_t k = 0; k < cf.times.size(); ++k) {
      Pose pose = sample_pose(out, static_cast<int32_t>(c), cf.times[k]);
      accumulate(r.at_frames, skin_character(out, pose), skins[cf.first_target + k]);
      if (baked && options.mode == ExportMode::kBakedSkin) {
        pose.morph_weights[mesh_node].assign(r.frames, 0.0f);
        accumulate(r.fitted, skin_character(out, pose), skins[cf.first_target + k]);
      }
      if (k + 1 < cf.times.size()) {
        const double mid = 0.5 * (cf.times[k] + cf.times[k + 1]);
        if (auto s = rig.pose(doc, compose_pose(ch, cf.clip, mid, false), posed, live); !s) return s.error();
        accumulate(r.between_frames, skin_character(out, sample_pose(out, static_cast<int32_t>(c), mid)),
                   live);
      }
    }
  }
  if (options.mode == ExportMode::kBakedAnimation) r.fitted = r.at_frames;
  return r;
}

}  // namespace cagewrap
