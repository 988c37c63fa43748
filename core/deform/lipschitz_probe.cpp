#include "core/deform/lipschitz_probe.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include <glm/geometric.hpp>

#include "core/deform/deformer.h"
#include "core/geometry/geometry.h"

namespace cagewrap {

namespace {

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// The centre of the bounding box of the finite points (the origin when there is none). The time
// probe's skin and cages are expressed relative to it before they are rounded to float, so that the
// float positions the deformer works with are as exact as the scene's size allows, wherever it lies.
glm::dvec3 finite_center(std::span<const glm::vec3> points) {
  Aabb box;
  for (const glm::vec3& p : points)
    if (finite(glm::dvec3(p))) box.extend(glm::dvec3(p));
  return box.empty() ? glm::dvec3(0.0) : box.center();
}

std::vector<glm::vec3> shifted(std::span<const glm::vec3> points, const glm::dvec3& by) {
  std::vector<glm::vec3> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) out[i] = glm::vec3(glm::dvec3(points[i]) - by);
  return out;
}

// Appends `count` points of `line` (shifted by -`by`), with its edit on each when it has one.
void append_line(ProbeSkin& skin, const ProbeLine& line, uint32_t count, const glm::dvec3& by) {
  for (uint32_t i = 0; i < count; ++i) {
    const double t = double(i) / (count - 1);
    if (line.edit) {
      SetEdit e = *line.edit;
      e.point = static_cast<uint32_t>(skin.points.size());
      skin.edits.push_back(std::move(e));
    }
    skin.points.push_back(glm::vec3(line.a + t * (line.b - line.a) - by));
  }
}

Status check_lines(std::span<const ProbeLine> lines, uint32_t samples, size_t points_per_line) {
  if (lines.empty()) return make_error(ErrorCode::kEmpty, "there are no probe lines");
  if (samples < 3 || samples > kMaxProbeSamples)
    return make_error(ErrorCode::kInvalidArgument, "the samples per probe line must be between 3 and " +
                                                       std::to_string(kMaxProbeSamples) + ", not " +
                                                       std::to_string(samples));
  if (lines.size() > kMaxProbePoints / points_per_line)
    return make_error(ErrorCode::kInvalidArgument,
                      std::to_string(lines.size()) + " probe lines of " + std::to_string(samples) +
                          " samples make more than " + std::to_string(kMaxProbePoints) + " probe points");
  for (size_t i = 0; i < lines.size(); ++i) {
    const ProbeLine& l = lines[i];
    if (!finite(l.a) || !finite(l.b) || !(glm::length(l.b - l.a) > 0.0))
      return make_error(ErrorCode::kInvalidArgument, "probe line " + std::to_string(i) + " (" + l.what +
                                                         ") is not a finite segment of non-zero length");
  }
  return Ok{};
}

Status check_cages(const Cage& cage, std::span<const glm::vec3> rest, std::span<const glm::vec3> posed) {
  if (rest.size() != cage.num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "the rest positions have " + std::to_string(rest.size()) +
                                                        " vertices but the cage has " +
                                                        std::to_string(cage.num_vertices()));
  if (posed.size() != cage.num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "the posed cage has " + std::to_string(posed.size()) +
                                                        " vertices but the cage has " +
                                                        std::to_string(cage.num_vertices()));
  return Ok{};
}

// Whether `candidate` is a worse figure than `current`: larger, or NaN (which stays the worst).
bool worse(double candidate, double current) {
  return std::isnan(candidate) ? !std::isnan(current) : candidate > current;
}

double elapsed_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

double probe_scale(const Cage& cage, std::span<const glm::vec3> rest_positions, const BindParams& params) {
  if (params.scale > 0) return params.scale;
  PolyMesh rest = cage.polygons;
  rest.positions.assign(rest_positions.begin(), rest_positions.end());
  return mean_edge_length(rest);
}

std::vector<ProbeLine> automatic_probe_lines(const Cage& cage, std::span<const glm::vec3> rest,
                                             const BindParams& params, double h, std::span<const glm::vec3> skin,
                                             std::span<const SetEdit> edits, const ProbeLineOptions& options) {
  std::vector<ProbeLine> lines;
  if (rest.size() != cage.num_vertices() || !(h > 0) || !std::isfinite(h)) return lines;
  const std::vector<ElementStatus> status = classify_elements(cage, rest);
  std::vector<uint32_t> valid;
  for (uint32_t e = 0; e < status.size(); ++e)
    if (status[e] == ElementStatus::kValid) valid.push_back(e);
  if (valid.empty()) return lines;
  auto pos = [&](uint32_t v) { return glm::dvec3(rest[v]); };
  const char* axis_name[3] = {"x", "y", "z"};

  // (a) through the interior: the box of the vertices valid elements use
  Aabb box;
  for (uint32_t e : valid)
    for (uint32_t v : cage.elements[e]) box.extend(pos(v));
  const glm::dvec3 c = box.center();
  for (int axis = 0; axis < 3; ++axis) {
    ProbeLine l;
    l.what = std::string("interior along ") + axis_name[axis] + " through the box centre";
    l.a = l.b = c;
    l.a[axis] = box.lo[axis] - 0.5 * h;
    l.b[axis] = box.hi[axis] + 0.5 * h;
    lines.push_back(std::move(l));
  }
  // ... and through each of the largest shells (connected pieces of the valid elements)
  std::vector<uint32_t> parent(cage.num_vertices());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (uint32_t e : valid) {
    const Tri& t = cage.elements[e];
    for (int k = 1; k < 3; ++k) {
      uint32_t a = find(t[0]), b = find(t[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  struct Shell {
    uint32_t root, elements = 0;
    Aabb box;
  };
  std::vector<Shell> shells;
  std::vector<int64_t> shell_of(cage.num_vertices(), -1);
  for (uint32_t e : valid) {
    const uint32_t r = find(cage.elements[e][0]);
    if (shell_of[r] < 0) {
      shell_of[r] = static_cast<int64_t>(shells.size());
      shells.push_back({r, 0, Aabb{}});
    }
    Shell& s = shells[shell_of[r]];
    ++s.elements;
    for (uint32_t v : cage.elements[e]) s.box.extend(pos(v));
  }
  if (shells.size() > 1) {
    std::stable_sort(shells.begin(), shells.end(), [](const Shell& a, const Shell& b) { return a.elements > b.elements; });
    for (size_t i = 0; i < shells.size() && i < options.shells; ++i) {
      const Shell& s = shells[i];
      const glm::dvec3 size = s.box.hi - s.box.lo;
      const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
      ProbeLine l;
      l.what = "interior of shell " + std::to_string(i + 1) + " (" + std::to_string(s.elements) +
               " elements) along its longest side (" + axis_name[axis] + ")";
      l.a = l.b = s.box.center();
      l.a[axis] = s.box.lo[axis] - 0.5 * h;
      l.b[axis] = s.box.hi[axis] + 0.5 * h;
      lines.push_back(std::move(l));
    }
  }

  // (b) across the vertices of highest valence
  std::vector<uint32_t> valence(cage.num_vertices(), 0);
  std::vector<glm::dvec3> normal(cage.num_vertices(), glm::dvec3(0.0));
  for (uint32_t e : valid) {
    const Tri& t = cage.elements[e];
    const glm::dvec3 n = glm::cross(pos(t[1]) - pos(t[0]), pos(t[2]) - pos(t[0]));
    for (uint32_t v : t) ++valence[v], normal[v] += n;
  }
  std::vector<uint32_t> order(cage.num_vertices());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return valence[a] > valence[b]; });
  std::vector<uint32_t> chosen;
  for (uint32_t v : order) {
    if (chosen.size() >= options.valence_vertices || valence[v] == 0) break;
    if (glm::length(normal[v]) > 0 && finite(normal[v])) chosen.push_back(v);
  }
  for (uint32_t v : chosen) {
    const glm::dvec3 p = pos(v), n = glm::normalize(normal[v]);
    const std::string name = "vertex " + std::to_string(v) + " (valence " + std::to_string(valence[v]) + ")";
    lines.push_back({"across " + name + " along its normal", p - 0.5 * h * n, p + 0.5 * h * n, std::nullopt});
    // a tangent: n crossed with the axis least aligned with it
    const glm::dvec3 an = glm::abs(n);
    const glm::dvec3 axis = an.x <= an.y && an.x <= an.z ? glm::dvec3(1, 0, 0)
                            : an.y <= an.z               ? glm::dvec3(0, 1, 0)
                                                         : glm::dvec3(0, 0, 1);
    const glm::dvec3 t = glm::normalize(glm::cross(n, axis));
    const glm::dvec3 q = p - 0.1 * h * n;
    lines.push_back({"across " + name + ", tangent 0.1 h inside", q - 0.5 * h * t, q + 0.5 * h * t, std::nullopt});
  }

  // (c) across the max-distance boundary
  if (params.max_distance > 0) {
    const double md = params.max_distance;
    for (size_t i = 0; i < chosen.size() && i < options.max_distance_lines; ++i) {
      const uint32_t v = chosen[i];
      const glm::dvec3 p = pos(v), n = glm::normalize(normal[v]);
      lines.push_back({"beyond vertex " + std::to_string(v) + " across the max distance " + fmt("%g", md),
                       p + 0.5 * md * n, p + 1.5 * md * n, std::nullopt});
    }
  }

  // (d) through edited points
  if (!skin.empty() && !edits.empty() && options.edited_points > 0) {
    const size_t count = std::min<size_t>(options.edited_points, edits.size());
    for (size_t k = 0; k < count; ++k) {
      const SetEdit& edit = edits[k * edits.size() / count];
      if (edit.point >= skin.size()) continue;
      const glm::dvec3 p(skin[edit.point]);
      if (!finite(p)) continue;
      double best = INFINITY;
      glm::dvec3 n(0.0);
      for (uint32_t e : valid) {
        const Tri& t = cage.elements[e];
        const ClosestPoint cp = closest_point_on_triangle(p, pos(t[0]), pos(t[1]), pos(t[2]));
        if (cp.dist2 < best) best = cp.dist2, n = glm::cross(pos(t[1]) - pos(t[0]), pos(t[2]) - pos(t[0]));
      }
      if (!(glm::length(n) > 0)) continue;
      n = glm::normalize(n);
      lines.push_back({"through edited point " + std::to_string(edit.point) + " along the nearest element's normal",
                       p - 0.5 * h * n, p + 0.5 * h * n, edit});
    }
  }
  return lines;
}

CageStretch cage_stretch(const Cage& cage, std::span<const glm::vec3> rest, std::span<const glm::vec3> posed) {
  CageStretch out;
  if (rest.size() != cage.num_vertices() || posed.size() != cage.num_vertices()) return out;
  const std::vector<ElementStatus> status = classify_elements(cage, rest);
  for (uint32_t e = 0; e < status.size(); ++e) {
    if (status[e] != ElementStatus::kValid) continue;
    const Tri& t = cage.elements[e];
    const glm::dvec3 A(rest[t[0]]), B(rest[t[1]]), C(rest[t[2]]);
    const glm::dvec3 A2(posed[t[0]]), B2(posed[t[1]]), C2(posed[t[2]]);
    if (!finite(A2) || !finite(B2) || !finite(C2)) continue;
    // the rest edges in an orthonormal basis (u, w) of their plane: R = [[r11, r12], [0, r22]]
    const glm::dvec3 e1 = B - A, e2 = C - A;
    const double r11 = glm::length(e1);
    const glm::dvec3 u = e1 / r11;
    const double r12 = glm::dot(e2, u);
    const glm::dvec3 w_raw = e2 - r12 * u;
    const double r22 = glm::length(w_raw);
    if (!(r11 > 0) || !(r22 > 0)) continue;
    // M = [e1' e2'] R^-1, a 3 x 2 map; its largest singular value from the 2 x 2 Gram matrix
    const glm::dvec3 f1 = B2 - A2, f2 = C2 - A2;
    const glm::dvec3 m1 = f1 / r11;                      // first column
    const glm::dvec3 m2 = (f2 - (r12 / r11) * f1) / r22;  // second column
    const double g11 = glm::dot(m1, m1), g12 = glm::dot(m1, m2), g22 = glm::dot(m2, m2);
    const double half_trace = 0.5 * (g11 + g22);
    const double disc = std::sqrt(0.25 * (g11 - g22) * (g11 - g22) + g12 * g12);
    const double sigma = std::sqrt(std::max(0.0, half_trace + disc));
    if (sigma > out.stretch) out.stretch = sigma, out.element = e;
  }
  return out;
}

LargestStep largest_step(std::span<const glm::vec3> points) {
  LargestStep out;
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const double d = glm::length(glm::dvec3(points[i + 1]) - glm::dvec3(points[i]));
    if (d > out.step || !std::isfinite(d)) {
      out.step = d, out.at = i;
      if (!std::isfinite(d)) break;  // a NaN must never hide behind a comparison
    }
  }
  return out;
}

double ProbeReport::figure() const {
  if (cage.stretch > 0) return worst_ratio / cage.stretch;
  return worst_ratio > 0 ? INFINITY : 0.0;
}

bool ratio_passes(const ProbeReport& r, const ProbeLimits& limits) { return r.figure() <= limits.max_ratio; }
bool continuity_passes(const ProbeReport& r, const ProbeLimits& limits) { return r.worst_shrink <= limits.max_shrink; }
bool time_passes(const TimeProbeReport& r, const ProbeLimits& limits) { return r.worst_ratio <= limits.max_time_ratio; }

Result<ProbeSkin> probe_line_points(std::span<const ProbeLine> lines, uint32_t samples) {
  if (auto s = check_lines(lines, samples, samples); !s) return s.error();
  ProbeSkin skin;
  skin.points.reserve(lines.size() * samples);
  for (const ProbeLine& l : lines) append_line(skin, l, samples, glm::dvec3(0.0));
  return skin;
}

Result<ProbeReport> probe_lipschitz(const Cage& cage, std::span<const glm::vec3> rest, std::span<const glm::vec3> posed,
                                    const BindParams& params, std::span<const ProbeLine> lines, uint32_t samples,
                                    const BindProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (auto v = validate(params); !v) return v.error();
  if (auto s = check_cages(cage, rest, posed); !s) return s.error();
  // per line: `samples` points at the spacing, then 2 samples - 1 at half of it
  const size_t per_line = size_t(samples) + (2 * size_t(samples) - 1);
  if (auto s = check_lines(lines, samples, per_line); !s) return s.error();

  ProbeReport r;
  r.variant = params.variant;
  r.samples = samples;
  r.cage = cage_stretch(cage, rest, posed);
  std::vector<glm::vec3> rest_s(rest.size()), posed_s(posed.size()), out;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (progress.cancel && progress.cancel->load()) return make_error(ErrorCode::kCancelled, "the probe was cancelled");
    const ProbeLine& l = lines[i];
    // One bind per line, everything relative to the line's middle (rest) and to where it goes (posed):
    // the deformer works in float, whose rounding of positions as large as the scene would otherwise
    // be a sizeable share of steps a 2000th of the line long.
    const glm::dvec3 m = 0.5 * (l.a + l.b);
    for (size_t v = 0; v < rest.size(); ++v) rest_s[v] = glm::vec3(glm::dvec3(rest[v]) - m);
    ProbeSkin skin;
    skin.points.reserve(per_line);
    append_line(skin, l, samples, m);
    append_line(skin, l, 2 * samples - 1, m);
    BindProgress line_progress;
    line_progress.cancel = progress.cancel;
    if (progress.on_progress)
      line_progress.on_progress = [&progress, i, n = lines.size()](double f) { progress.on_progress((i + f) / n); };
    auto binding = bind_skin(skin.points, cage, rest_s, params, skin.edits, line_progress);
    if (!binding) return binding.error();
    auto deformer = Deformer::create(*binding, skin.points);
    if (!deformer) return deformer.error();
    out.resize(skin.points.size());
    // first where the line's middle goes, then again relative to that
    glm::dvec3 moved(0.0);
    for (int pass = 0; pass < 2; ++pass) {
      for (size_t v = 0; v < posed.size(); ++v) posed_s[v] = glm::vec3(glm::dvec3(posed[v]) - m - moved);
      if (auto s = deformer->deform(posed_s, out); !s) return s.error();
      const glm::dvec3 middle = 0.5 * (glm::dvec3(out[samples / 2]) + glm::dvec3(out[(samples - 1) / 2]));
      if (finite(middle)) moved += middle;
    }
    if (i == 0) r.h = binding->h;
    r.rigid_points += static_cast<uint32_t>(binding->rigid_points.size());

    const std::span<const glm::vec3> deformed(out);
    const std::span<const glm::vec3> at_s = deformed.subspan(0, samples);
    const std::span<const glm::vec3> at_half = deformed.subspan(samples, 2 * samples - 1);
    LineProbe p;
    p.what = l.what;
    p.a = l.a, p.b = l.b;
    p.edited = l.edit.has_value();
    p.spacing = glm::length(l.b - l.a) / (samples - 1);
    const LargestStep s = largest_step(at_s), half = largest_step(at_half);
    p.step_ratio = s.step / p.spacing;
    p.half_step_ratio = half.step / (0.5 * p.spacing);
    p.at_t = (s.at + 0.5) / (samples - 1);
    p.at = l.a + p.at_t * (l.b - l.a);
    p.shrink = s.step > 0 ? half.step / s.step : (half.step > 0 ? INFINITY : 0.0);
    const double ratio = std::max(p.step_ratio, p.half_step_ratio);
    if (worse(ratio, r.worst_ratio)) r.worst_ratio = ratio, r.worst_line = i;
    if (worse(p.shrink, r.worst_shrink)) r.worst_shrink = p.shrink, r.worst_shrink_line = i;
    r.lines.push_back(std::move(p));
  }
  if (progress.on_progress) progress.on_progress(1.0);
  r.seconds = elapsed_since(start);
  return r;
}

Result<TimeProbeReport> probe_time_steps(const Cage& cage, std::span<const glm::vec3> rest,
                                         std::span<const glm::vec3> posed, const BindParams& params,
                                         std::span<const glm::vec3> skin, std::span<const SetEdit> edits,
                                         uint32_t steps, double min_path, const BindProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (auto v = validate(params); !v) return v.error();
  if (auto s = check_cages(cage, rest, posed); !s) return s.error();
  if (steps < 1 || steps > 100000)
    return make_error(ErrorCode::kInvalidArgument,
                      "the time probe's steps must be between 1 and 100000, not " + std::to_string(steps));
  if (!(min_path >= 0) || !std::isfinite(min_path))
    return make_error(ErrorCode::kInvalidArgument, "the time probe's minimum path must be finite and >= 0");
  if (auto s = check_skin(skin); !s) return s.error();

  const glm::dvec3 rest_c = finite_center(rest), posed_c = finite_center(posed);
  const std::vector<glm::vec3> rest_s = shifted(rest, rest_c), skin_s = shifted(skin, rest_c);
  BindProgress bind_progress;
  bind_progress.cancel = progress.cancel;
  if (progress.on_progress) bind_progress.on_progress = [&progress](double f) { progress.on_progress(0.5 * f); };
  auto binding = bind_skin(skin_s, cage, rest_s, params, edits, bind_progress);
  if (!binding) return binding.error();
  auto deformer = Deformer::create(*binding, skin_s);
  if (!deformer) return deformer.error();

  const size_t n = skin.size();
  std::vector<glm::vec3> state(rest.size()), prev(n), out(n);
  std::vector<double> path(n, 0.0), largest(n, 0.0);
  std::vector<uint32_t> largest_at(n, 0);
  glm::dvec3 prev_c(0.0);
  for (uint32_t k = 0; k <= steps; ++k) {
    if (progress.cancel && progress.cancel->load()) return make_error(ErrorCode::kCancelled, "the time probe was cancelled");
    const double t = double(k) / steps;
    // each frame relative to its own centre, for float precision; added back to the steps in double
    const glm::dvec3 c = glm::mix(rest_c, posed_c, t);
    for (size_t v = 0; v < rest.size(); ++v)
      state[v] = glm::vec3(glm::mix(glm::dvec3(rest[v]), glm::dvec3(posed[v]), t) - c);
    if (auto s = deformer->deform(state, out); !s) return s.error();
    if (k > 0) {
      const glm::dvec3 dc = c - prev_c;
      for (size_t i = 0; i < n; ++i) {
        const double d = glm::length(glm::dvec3(out[i]) - glm::dvec3(prev[i]) + dc);
        path[i] += d;
        if (d > largest[i] || !std::isfinite(d)) largest[i] = d, largest_at[i] = k;
      }
    }
    std::swap(prev, out);
    prev_c = c;
    if (progress.on_progress) progress.on_progress(0.5 + 0.5 * double(k) / steps);
  }

  TimeProbeReport r;
  r.steps = steps;
  r.points = n;
  const double floor = min_path * bounding_box(rest).diagonal();
  for (size_t i = 0; i < n; ++i) {
    if (std::isfinite(path[i]) && !(path[i] > 0 && path[i] >= floor)) continue;
    ++r.measured;
    const double ratio = largest[i] / (path[i] / steps);
    if (worse(ratio, r.worst_ratio)) {
      r.worst_ratio = ratio, r.worst_point = static_cast<uint32_t>(i), r.worst_step = largest_at[i];
      r.worst_rest = glm::dvec3(skin[i]);
    }
  }
  r.seconds = elapsed_since(start);
  return r;
}

}  // namespace cagewrap
