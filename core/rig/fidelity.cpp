#include "core/rig/fidelity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "core/geometry/mesh.h"
#include "core/deform/part_labels.h"
#include "core/character/skinning.h"

namespace cagewrap {

std::string scene_units(double diagonal) {
  return diagonal >= 0.05 && diagonal <= 50.0 ? "m" : "scene units";
}

std::string format_length(double value, const std::string& units) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g %s", value, units.c_str());
  return buf;
}

std::vector<std::pair<uint32_t, uint32_t>> skin_edges(const Character& character) {
  std::vector<std::pair<uint32_t, uint32_t>> e;
  for (const auto& [a, b] : unique_edges(combined_topology(character))) e.emplace_back(a, b);
  return e;
}

std::vector<int32_t> heaviest_joints(const Character& character) {
  const std::vector<uint32_t> nodes = dominant_joint_nodes(character);
  std::vector<int32_t> out(nodes.size(), -1);
  for (size_t p = 0; p < nodes.size(); ++p)
    if (nodes[p] != PartLabels::kUnlabelled) out[p] = static_cast<int32_t>(nodes[p]);
  return out;
}

namespace {
struct VertexAcc {
  double worst = -1.0, sum2 = 0.0;
  uint32_t vertex = 0;
};
struct EdgeAcc {
  double stretch = 1.0, squash = 1.0;
  size_t edge = 0;
};
}  // namespace

FrameFidelity compare_skins(std::span<const glm::vec3> rig, std::span<const glm::vec3> ref,
                            std::span<const std::pair<uint32_t, uint32_t>> edges, std::span<const int32_t> joints,
                            double diagonal, double min_edge, std::span<float> per_vertex) {
  FrameFidelity f;
  const size_t n = std::min(rig.size(), ref.size());
  if (n == 0 || !(diagonal > 0)) return f;
  const double inv = 1.0 / diagonal;
  VertexAcc v = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 4096), VertexAcc{},
      [&](const tbb::blocked_range<size_t>& r, VertexAcc acc) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const double d = glm::length(glm::dvec3(rig[i]) - glm::dvec3(ref[i])) * inv;
          const double dd = std::isfinite(d) ? d : 1e30;
          if (!per_vertex.empty()) per_vertex[i] = static_cast<float>(dd);
          acc.sum2 += dd * dd;
          if (dd > acc.worst) acc.worst = dd, acc.vertex = static_cast<uint32_t>(i);
        }
        return acc;
      },
      [](VertexAcc a, const VertexAcc& b) {
        a.sum2 += b.sum2;
        if (b.worst > a.worst || (b.worst == a.worst && b.vertex < a.vertex)) a.worst = b.worst, a.vertex = b.vertex;
        return a;
      });
  f.worst = std::max(v.worst, 0.0);
  f.rms = std::sqrt(v.sum2 / double(n));
  f.worst_vertex = v.vertex;
  f.worst_joint = v.vertex < joints.size() ? joints[v.vertex] : -1;
  const double min_len = min_edge * diagonal;
  EdgeAcc e = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, edges.size(), 8192), EdgeAcc{},
      [&](const tbb::blocked_range<size_t>& r, EdgeAcc acc) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const auto [a, b] = edges[i];
          if (a >= n || b >= n) continue;
          const double l_ref = glm::length(glm::dvec3(ref[a]) - glm::dvec3(ref[b]));
          if (!(l_ref >= min_len)) continue;
          const double l_rig = glm::length(glm::dvec3(rig[a]) - glm::dvec3(rig[b]));
          const double s = std::isfinite(l_rig) ? l_rig / l_ref : 1e30;
          if (s > acc.stretch) acc.stretch = s, acc.edge = i;
          const double q = s > 0 ? 1.0 / s : 1e30;
          acc.squash = std::max(acc.squash, q);
        }
        return acc;
      },
      [](EdgeAcc a, const EdgeAcc& b) {
        if (b.stretch > a.stretch || (b.stretch == a.stretch && b.edge < a.edge)) a.stretch = b.stretch, a.edge = b.edge;
        a.squash = std::max(a.squash, b.squash);
        return a;
      });
  f.stretch = e.stretch;
  f.squash = e.squash;
  if (!edges.empty()) {
    f.stretch_edge[0] = edges[e.edge].first;
    f.stretch_edge[1] = edges[e.edge].second;
    f.stretch_joint = f.stretch_edge[0] < joints.size() ? joints[f.stretch_edge[0]] : -1;
  }
  return f;
}

std::vector<double> fidelity_sample_times(double duration, const FidelityOptions& options) {
  std::vector<double> t;
  if (!(duration > 0) || !std::isfinite(duration)) return {0.0};
  for (double f : options.fractions)
    if (f >= 0 && f <= 1) t.push_back(f * duration);
  if (options.fps > 0 && std::isfinite(options.fps)) {
    const size_t steps = static_cast<size_t>(std::ceil(duration * options.fps - 1e-9));
    const size_t capped = std::min<size_t>(steps, 100000);
    for (size_t i = 0; i <= capped; ++i) t.push_back(duration * double(i) / double(std::max<size_t>(capped, 1)));
  }
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }), t.end());
  return t;
}

bool FidelityReport::passed() const {
  return overall.worst.worst <= thresholds.worst && overall.rms.rms <= thresholds.rms &&
         overall.stretch.stretch <= thresholds.stretch;
}

namespace {
std::string where(const FrameFidelity& f, const std::vector<ClipFidelity>& clips, const Skeleton& sk, uint32_t vertex,
                  int32_t joint) {
  std::string clip = "rest";
  for (const ClipFidelity& c : clips)
    if (c.clip == f.clip) clip = c.name;
  char buf[256];
  const std::string jn = joint >= 0 && size_t(joint) < sk.size() ? sk.node(joint).name : std::string("none");
  if (f.clip < 0)
    std::snprintf(buf, sizeof buf, "the rest pose, vertex %u, joint '%s'", vertex, jn.c_str());
  else
    std::snprintf(buf, sizeof buf, "clip '%s' at %.3g s, vertex %u, joint '%s'", clip.c_str(), f.time, vertex, jn.c_str());
  return buf;
}
}  // namespace

std::vector<std::string> FidelityReport::failures(const Skeleton& sk) const {
  std::vector<std::string> out;
  char buf[512];
  if (overall.worst.worst > thresholds.worst) {
    std::snprintf(buf, sizeof buf, "worst vertex %.2f%% of the diagonal > %.2f%% (%s)", 100 * overall.worst.worst,
                  100 * thresholds.worst,
                  where(overall.worst, clips, sk, overall.worst.worst_vertex, overall.worst.worst_joint).c_str());
    out.push_back(buf);
  }
  if (overall.rms.rms > thresholds.rms) {
    std::snprintf(buf, sizeof buf, "RMS %.2f%% of the diagonal > %.2f%% (%s)", 100 * overall.rms.rms, 100 * thresholds.rms,
                  where(overall.rms, clips, sk, overall.rms.worst_vertex, overall.rms.worst_joint).c_str());
    out.push_back(buf);
  }
  if (overall.stretch.stretch > thresholds.stretch) {
    std::snprintf(buf, sizeof buf, "a skin edge stretched %.2fx > %.2fx (%s)", overall.stretch.stretch,
                  thresholds.stretch,
                  where(overall.stretch, clips, sk, overall.stretch.stretch_edge[0], overall.stretch.stretch_joint).c_str());
    out.push_back(buf);
  }
  return out;
}

namespace {
void merge_frame(ClipFidelity& c, const FrameFidelity& f) {
  if (c.frames == 0 || f.worst > c.worst.worst) c.worst = f;
  if (c.frames == 0 || f.rms > c.rms.rms) c.rms = f;
  if (c.frames == 0 || f.stretch > c.stretch.stretch) c.stretch = f;
  ++c.frames;
}
}  // namespace

Result<FidelityReport> check_fidelity(const Document& doc, Rig& rig, const FidelityOptions& options,
                                      const FidelityProgress& progress) {
  if (!doc.character) return make_error(ErrorCode::kInvalidArgument, "the document has no character");
  const Character& ch = *doc.character;
  FidelityReport report;
  report.thresholds = options.thresholds;
  const std::span<const glm::vec3> bind = rig.skin_rest();
  report.vertices = bind.size();
  if (bind.size() != ch.num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "the rig's skin has " + std::to_string(bind.size()) +
                                                         " points, the character " + std::to_string(ch.num_vertices()));
  report.diagonal = bounding_box(bind).diagonal();
  report.units = scene_units(report.diagonal);
  auto edges = skin_edges(ch);
  // a region: the points outside it are given the reference's position (no error), the edges leaving
  // it are not judged, and the RMS is over the region's points
  std::vector<uint8_t> outside;
  double rms_scale = 1.0;
  if (!options.region.empty()) {
    if (options.region.size() != bind.size())
      return make_error(ErrorCode::kInvalidArgument, "the region has " + std::to_string(options.region.size()) +
                                                         " weights but the skin has " + std::to_string(bind.size()) + " points");
    outside.resize(bind.size());
    size_t inside = 0;
    for (size_t i = 0; i < bind.size(); ++i) {
      outside[i] = !(options.region[i] > 0.5f);
      inside += outside[i] ? 0 : 1;
    }
    if (inside == 0) return make_error(ErrorCode::kInvalidArgument, "the region holds no skin point");
    std::erase_if(edges, [&](const std::pair<uint32_t, uint32_t>& e) { return outside[e.first] || outside[e.second]; });
    rms_scale = std::sqrt(double(bind.size()) / double(inside));
    report.vertices = inside;
  }
  const auto joints = heaviest_joints(ch);
  // how many edges are judged (rest lengths are close enough to tell)
  for (const auto& [a, b] : edges)
    if (glm::length(bind[a] - bind[b]) >= options.min_edge * report.diagonal) ++report.edges_judged;

  std::vector<int32_t> clips = options.clips;
  if (clips.empty())
    for (size_t i = 0; i < ch.clips.size(); ++i) clips.push_back(static_cast<int32_t>(i));
  for (int32_t c : clips)
    if (c < 0 || size_t(c) >= ch.clips.size())
      return make_error(ErrorCode::kIndexOutOfRange, "clip " + std::to_string(c) + " does not exist (the character has " +
                                                         std::to_string(ch.clips.size()) + ")");
  struct Job {
    int32_t clip;
    std::vector<double> times;
  };
  std::vector<Job> jobs;
  if (options.rest) jobs.push_back({-1, {0.0}});
  for (int32_t c : clips) jobs.push_back({c, fidelity_sample_times(ch.clips[c].duration, options)});
  size_t total = 0, done = 0;
  for (const Job& j : jobs) total += j.times.size();

  std::vector<glm::vec3> skin(bind.size());
  PosedCage cage;
  report.overall.name = "all";
  for (const Job& j : jobs) {
    ClipFidelity cf;
    cf.clip = j.clip;
    cf.name = j.clip < 0 ? "rest" : ch.clips[j.clip].name;
    double sum2 = 0.0;
    for (double t : j.times) {
      if (progress.cancel && progress.cancel->load()) return make_error(ErrorCode::kCancelled, "the check was cancelled");
      if (auto s = rig.pose_clip(doc, j.clip, t, {}, cage, skin); !s) return s.error();
      const std::vector<glm::vec3> ref = skin_character(ch, compose_pose(ch, j.clip, t, false));
      for (size_t i = 0; i < outside.size(); ++i)
        if (outside[i]) skin[i] = ref[i];
      FrameFidelity f = compare_skins(skin, ref, edges, joints, report.diagonal, options.min_edge);
      f.rms *= rms_scale;
      f.clip = j.clip;
      f.time = t;
      sum2 += f.rms * f.rms;
      merge_frame(cf, f);
      merge_frame(report.overall, f);
      ++done;
      if (progress.on_progress) progress.on_progress(double(done) / double(std::max<size_t>(total, 1)));
    }
    cf.rms_all = cf.frames ? std::sqrt(sum2 / double(cf.frames)) : 0.0;
    report.clips.push_back(std::move(cf));
  }
  double sum2 = 0.0;
  size_t frames = 0;
  for (const ClipFidelity& c : report.clips) sum2 += c.rms_all * c.rms_all * double(c.frames), frames += c.frames;
  report.overall.rms_all = frames ? std::sqrt(sum2 / double(frames)) : 0.0;
  return report;
}

}  // namespace cagewrap
