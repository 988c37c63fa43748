#include "core/deform/deformer.h"

#include "core/deform/binding_check.h"

#include <cmath>

#include <algorithm>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <tbb/parallel_for.h>

namespace cagewrap {

Deformer::Deformer(Deformer&&) noexcept = default;
Deformer& Deformer::operator=(Deformer&&) noexcept = default;
Deformer::~Deformer() = default;

namespace {

glm::dmat3 eq2_frame(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& n) {
  return glm::dmat3(b - a, c - a, n);  // columns e1, e2, e3
}

// The rotation of the polar decomposition m = R S (S symmetric, positive semi-definite): the rotation nearest
// to m. For the clamped variant's rigid carrier it depends on the element's map only, not on which corner
// comes first (a frame built from e1 turns with that edge under shear). With det m <= 0 the nearest proper
// rotation (the smallest singular direction flipped). By a 3x3 SVD.
glm::dmat3 polar_rotation_svd(const glm::dmat3& m) {
  Eigen::Matrix3d a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a(r, c) = m[c][r];
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0) u.col(2) *= -1.0;
  const Eigen::Matrix3d rot = u * v.transpose();
  glm::dmat3 out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[c][r] = rot(r, c);
  return out;
}

// The same rotation, usually by the scaled Newton iteration X <- (z X + (z X)^-T) / 2 (Higham), which
// converges quadratically for a well-conditioned m with det m > 0: about 0.1 us against 0.7 us for the
// SVD, per element per cage change. A map that is (nearly) singular or reflecting goes to the SVD.
glm::dmat3 polar_rotation(const glm::dmat3& m) {
  const double det = glm::determinant(m);
  double norm2 = 0.0;
  for (int c = 0; c < 3; ++c) norm2 += glm::dot(m[c], m[c]);
  // det / |m|^3 is about s1 s2 s3 / (s1^2 + s2^2 + s3^2)^1.5: small when any singular value is
  if (!(det > 1e-9 * norm2 * std::sqrt(norm2))) return polar_rotation_svd(m);
  glm::dmat3 x = m;
  for (int it = 0; it < 30; ++it) {
    const glm::dmat3 inv_t = glm::transpose(glm::inverse(x));
    double nx = 0.0, ni = 0.0;
    for (int c = 0; c < 3; ++c) nx += glm::dot(x[c], x[c]), ni += glm::dot(inv_t[c], inv_t[c]);
    const double z = std::sqrt(std::sqrt(ni / nx));  // (|X^-1|_F / |X|_F)^(1/2)
    const glm::dmat3 next = 0.5 * (z * x + inv_t / z);
    double change = 0.0;
    for (int c = 0; c < 3; ++c) change += glm::dot(next[c] - x[c], next[c] - x[c]);
    x = next;
    if (change < 1e-26) return x;
  }
  return polar_rotation_svd(m);
}

void store(Affine& out, const glm::dmat3& m, const glm::dvec3& t) { out = make_affine(m, t); }

}  // namespace

void element_normals(const Binding& b, std::span<const glm::vec3> pos, std::span<const glm::dvec3> fallback,
                     std::vector<glm::dvec3>& ring, std::vector<glm::dvec3>& out) {
  const size_t ne = b.elements.size();
  out.assign(ne, glm::dvec3(0.0));
  ring.assign(pos.size(), glm::dvec3(0.0));
  for (size_t e = 0; e < ne; ++e) {
    if (b.element_status[e] != ElementStatus::kValid) continue;
    const Tri& t = b.elements[e];
    const glm::dvec3 a(pos[t[0]]);
    out[e] = glm::cross(glm::dvec3(pos[t[1]]) - a, glm::dvec3(pos[t[2]]) - a);  // the cross, for now
    for (uint32_t v : t) ring[v] += out[e];
  }
  for (size_t e = 0; e < ne; ++e) {
    if (b.element_status[e] != ElementStatus::kValid) {
      out[e] = fallback[e];
      continue;
    }
    const Tri& t = b.elements[e];
    const glm::dvec3 p0(pos[t[0]]), p1(pos[t[1]]), p2(pos[t[2]]);
    const double longest2 =
        std::max({glm::dot(p1 - p0, p1 - p0), glm::dot(p2 - p0, p2 - p0), glm::dot(p2 - p1, p2 - p1)});
    glm::dvec3 r = ring[t[0]] + ring[t[1]] + ring[t[2]];
    const double rl = glm::length(r);
    r = rl > 0 && std::isfinite(rl) ? r / rl : fallback[e];
    out[e] = lean_normal(out[e], longest2, r);
  }
}

Affine make_affine(const glm::dmat3& m, const glm::dvec3& t) {
  Affine out;
  for (int r = 0; r < 3; ++r) {
    out.m[4 * r + 0] = static_cast<float>(m[0][r]);
    out.m[4 * r + 1] = static_cast<float>(m[1][r]);
    out.m[4 * r + 2] = static_cast<float>(m[2][r]);
    out.m[4 * r + 3] = static_cast<float>(t[r]);
  }
  out.m[12] = out.m[13] = out.m[14] = out.m[15] = 0.f;
  return out;
}

Result<Deformer> Deformer::create(const Binding& b, std::span<const glm::vec3> skin_rest, TableFormat format) {
  if (skin_rest.size() != b.num_points)
    return make_error(ErrorCode::kTopologyMismatch, "the binding was made for " + std::to_string(b.num_points) +
                                                        " skin points but the skin has " +
                                                        std::to_string(skin_rest.size()));
  // table sizes and every index (element corners, stencil ids, fallback points and elements)
  if (auto v = validate_binding(b); !v) return v.error();

  Deformer d;
  d.binding_ = &b;
  d.skin_ = skin_rest;
  d.format_ = format;
  if (format == TableFormat::kCompact) d.table_ = make_kernel_table(b);
  const size_t ne = b.elements.size();
  d.rest_frame_inv_.assign(ne, glm::dmat3(1.0));
  const std::vector<glm::dvec3> up(ne, glm::dvec3(0, 0, 1));
  element_normals(b, b.rest_cage, up, d.ring_, d.rest_normal_);
  for (size_t e = 0; e < ne; ++e) {
    if (b.element_status[e] != ElementStatus::kValid) continue;
    const Tri& t = b.elements[e];
    glm::dvec3 p0 = glm::dvec3(b.rest_cage[t[0]]) - b.origin, p1 = glm::dvec3(b.rest_cage[t[1]]) - b.origin,
               p2 = glm::dvec3(b.rest_cage[t[2]]) - b.origin;
    d.rest_frame_inv_[e] = glm::inverse(eq2_frame(p0, p1, p2, d.rest_normal_[e]));
  }
  std::vector<uint8_t> used(b.num_cage_vertices, 0);
  for (size_t e = 0; e < ne; ++e)
    if (b.element_status[e] == ElementStatus::kValid)
      for (uint32_t v : b.elements[e]) used[v] = 1;
  for (uint32_t v = 0; v < b.num_cage_vertices; ++v)
    if (used[v]) d.used_vertices_.push_back(v);
  d.need_rigid_ = b.params.variant == Variant::kClamped || !b.rigid_points.empty();
  if (b.params.variant == Variant::kExtended) {
    d.maps_.resize(b.num_cage_vertices);
    d.vertex_linear_.resize(b.num_cage_vertices);
    std::vector<Tri> valid;
    for (size_t e = 0; e < ne; ++e)
      if (b.element_status[e] == ElementStatus::kValid) valid.push_back(b.elements[e]);
    d.fit_ = std::make_unique<OneRingFit>(b.rest_cage, valid);
  } else {
    d.maps_.resize(ne);
  }
  if (d.need_rigid_) d.rigid_maps_.resize(ne);
  return d;
}

Status Deformer::stencil_changed(std::span<const uint32_t> points) {
  if (auto v = validate_binding(*binding_); !v) return v.error();
  if (!(table_ && !points.empty() && update_kernel_table(*table_, *binding_, points))) {
    table_.reset();
    if (format_ == TableFormat::kCompact) table_ = make_kernel_table(*binding_);
  }
  need_rigid_ = binding_->params.variant == Variant::kClamped || !binding_->rigid_points.empty();
  if (need_rigid_) rigid_maps_.resize(binding_->elements.size());
  return Ok{};
}

Status Deformer::check_cage(std::span<const glm::vec3> posed) const {
  if (posed.size() != binding_->num_cage_vertices)
    return make_error(ErrorCode::kTopologyMismatch,
                      "the posed cage has " + std::to_string(posed.size()) + " vertices but the bound cage has " +
                          std::to_string(binding_->num_cage_vertices));
  for (uint32_t i : used_vertices_)
    if (!std::isfinite(posed[i].x) || !std::isfinite(posed[i].y) || !std::isfinite(posed[i].z))
      return make_error(ErrorCode::kNonFinite, "posed cage vertex " + std::to_string(i) + " has a non-finite coordinate");
  return Ok{};
}

void Deformer::build_element_maps(std::span<const glm::vec3> posed) {
  const Binding& b = *binding_;
  element_normals(b, posed, rest_normal_, ring_, normal_);
  for (size_t e = 0; e < b.elements.size(); ++e) {
    if (b.element_status[e] != ElementStatus::kValid) {
      store(maps_[e], glm::dmat3(1.0), glm::dvec3(0.0));
      continue;
    }
    const Tri& t = b.elements[e];
    glm::dvec3 q0 = glm::dvec3(posed[t[0]]) - b.origin, q1 = glm::dvec3(posed[t[1]]) - b.origin,
               q2 = glm::dvec3(posed[t[2]]) - b.origin;
    glm::dmat3 m = eq2_frame(q0, q1, q2, normal_[e]) * rest_frame_inv_[e];
    glm::dvec3 p0 = glm::dvec3(b.rest_cage[t[0]]) - b.origin;
    store(maps_[e], m, q0 - m * p0);
  }
}

void Deformer::build_rigid_maps(std::span<const glm::vec3> posed) {
  const Binding& b = *binding_;
  if (b.params.variant != Variant::kBasic) element_normals(b, posed, rest_normal_, ring_, normal_);
  for (size_t e = 0; e < b.elements.size(); ++e) {
    RigidMap& a = rigid_maps_[e];
    glm::dmat3 g(1.0);
    glm::dvec3 q[3]{glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
    if (b.element_status[e] == ElementStatus::kValid) {
      const Tri& t = b.elements[e];
      glm::dvec3 v[3], p[3];
      for (size_t i = 0; i < 3; ++i) {
        v[i] = glm::dvec3(posed[t[i]]) - b.origin;
        p[i] = glm::dvec3(b.rest_cage[t[i]]) - b.origin;
      }
      g = polar_rotation(eq2_frame(v[0], v[1], v[2], normal_[e]) * rest_frame_inv_[e]);
      for (size_t i = 0; i < 3; ++i) q[i] = v[i] - g * p[i];
    }
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) a.g[3 * r + col] = static_cast<float>(g[col][r]);
    for (int k = 0; k < 3; ++k) {
      a.q0[k] = static_cast<float>(q[0][k]);
      a.d1[k] = static_cast<float>(q[1][k] - q[0][k]);
      a.d2[k] = static_cast<float>(q[2][k] - q[0][k]);
    }
    a.pad[0] = a.pad[1] = 0.f;
  }
}

void Deformer::build_vertex_maps(std::span<const glm::vec3> posed, std::span<const glm::dmat3> vertex_linear) {
  const Binding& b = *binding_;
  std::span<const glm::dmat3> lin = vertex_linear;
  if (lin.empty()) {
    fit_->fit(posed, vertex_linear_);
    lin = vertex_linear_;
  }
  for (size_t v = 0; v < b.num_cage_vertices; ++v) {
    glm::dvec3 q = glm::dvec3(posed[v]) - b.origin, p = glm::dvec3(b.rest_cage[v]) - b.origin;
    store(maps_[v], lin[v], q - lin[v] * p);
  }
}

namespace {

inline void apply_rigid(const RigidMap& r, float b1, float b2, const float p[3], float out[3]) {
  for (int k = 0; k < 3; ++k)
    out[k] = r.g[3 * k] * p[0] + r.g[3 * k + 1] * p[1] + r.g[3 * k + 2] * p[2] + r.q0[k] + b1 * r.d1[k] + b2 * r.d2[k];
}

}  // namespace

Status Deformer::update_maps(std::span<const glm::vec3> posed, std::span<const glm::dmat3> vertex_linear) {
  const Binding& b = *binding_;
  if (b.num_samples > 0)
    return make_error(ErrorCode::kInvalidArgument,
                      "the binding drives the skin by a parametric driver's samples; deform it through the driver");
  if (auto s = check_cage(posed); !s) return s;
  const Variant variant = b.params.variant;
  if (!vertex_linear.empty() && (variant != Variant::kExtended || vertex_linear.size() != b.num_cage_vertices))
    return make_error(ErrorCode::kInvalidArgument,
                      "vertex frames are for the extended variant and need one per cage vertex (" +
                          std::to_string(b.num_cage_vertices) + ")");
  if (variant == Variant::kBasic) build_element_maps(posed);
  if (variant == Variant::kExtended) build_vertex_maps(posed, vertex_linear);
  if (need_rigid_) build_rigid_maps(posed);
  return Ok{};
}

std::span<const Affine> Deformer::affine_maps() const {
  if (binding_->params.variant == Variant::kClamped) return {};
  return maps_;
}

Status Deformer::deform(std::span<const glm::vec3> posed, std::span<glm::vec3> out,
                        std::span<const glm::dmat3> vertex_linear) {
  const Binding& b = *binding_;
  if (out.size() != b.num_points)
    return make_error(ErrorCode::kInvalidArgument, "output holds " + std::to_string(out.size()) +
                                                       " points but the skin has " + std::to_string(b.num_points));
  if (auto s = update_maps(posed, vertex_linear); !s) return s;
  apply_table(maps_, out);
  return Ok{};
}

Status Deformer::deform_with_maps(std::span<const Affine> maps, std::span<glm::vec3> out) {
  const Binding& b = *binding_;
  if (b.num_samples == 0)
    return make_error(ErrorCode::kInvalidArgument, "the binding is to a cage, not to a parametric driver's samples");
  if (maps.size() != b.num_samples)
    return make_error(ErrorCode::kTopologyMismatch, "the driver gives " + std::to_string(maps.size()) +
                                                        " sample maps but the binding has " +
                                                        std::to_string(b.num_samples) + " samples");
  if (out.size() != b.num_points)
    return make_error(ErrorCode::kInvalidArgument, "output holds " + std::to_string(out.size()) +
                                                       " points but the skin has " + std::to_string(b.num_points));
  apply_table(maps, out);
  return Ok{};
}

void Deformer::apply_table(std::span<const Affine> affine, std::span<glm::vec3> out) const {
  const Binding& b = *binding_;
  const Variant variant = b.params.variant;

  const glm::vec3 origin(b.origin);
  const uint32_t* offsets = b.offsets.data();
  const uint32_t* ids = b.ids.data();
  const float* weights = b.weights.data();
  const float* bary = b.bary.data();
  const glm::vec3* skin = skin_.data();
  glm::vec3* dst = out.data();

  if (table_ && variant == Variant::kClamped) {
    apply_kernel_rigid(*table_, rigid_maps_, skin_, origin, out);
  } else if (table_) {
    apply_kernel_affine(*table_, affine, skin_, origin, out);
  } else if (variant == Variant::kClamped) {
    const RigidMap* maps = rigid_maps_.data();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, b.num_points, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const float p[3] = {skin[i].x - origin.x, skin[i].y - origin.y, skin[i].z - origin.z};
        float acc[3] = {0, 0, 0};
        for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
          float y[3];
          apply_rigid(maps[ids[e]], bary[2 * e], bary[2 * e + 1], p, y);
          const float w = weights[e];
          acc[0] += w * y[0];
          acc[1] += w * y[1];
          acc[2] += w * y[2];
        }
        dst[i] = glm::vec3(acc[0], acc[1], acc[2]) + origin;
      }
    });
  } else {
    const Affine* maps = affine.data();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, b.num_points, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        // blend the affine maps first (12 multiply-adds per entry, vectorizable), then apply once
        float m[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
        for (uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
          const float w = weights[e];
          const float* a = maps[ids[e]].m;
          for (int k = 0; k < 12; ++k) m[k] += w * a[k];
        }
        const float x = skin[i].x - origin.x, y = skin[i].y - origin.y, z = skin[i].z - origin.z;
        dst[i] = glm::vec3(m[0] * x + m[1] * y + m[2] * z + m[3], m[4] * x + m[5] * y + m[6] * z + m[7],
                           m[8] * x + m[9] * y + m[10] * z + m[11]) +
                 origin;
      }
    });
  }
  // points with an empty contributing set follow their nearest valid element rigidly
  for (size_t k = 0; k < b.rigid_points.size(); ++k) {
    const uint32_t i = b.rigid_points[k];
    const float p[3] = {skin[i].x - origin.x, skin[i].y - origin.y, skin[i].z - origin.z};
    float y[3];
    apply_rigid(rigid_maps_[b.rigid_element[k]], b.rigid_bary[2 * k], b.rigid_bary[2 * k + 1], p, y);
    dst[i] = glm::vec3(y[0], y[1], y[2]) + origin;
  }
}

size_t Deformer::table_bytes() const {
  return table_ ? table_->bytes() : float_table_bytes(*binding_);
}

size_t Deformer::bytes_read_per_call() const {
  const Binding& b = *binding_;
  return table_bytes() + size_t(b.num_points) * sizeof(glm::vec3) + maps_.size() * sizeof(Affine) +
         rigid_maps_.size() * sizeof(RigidMap) + b.rigid_points.size() * 16;
}

Status combine_displacements(std::span<const glm::vec3> rest, std::span<const std::span<const glm::vec3>> deformed,
                             CombineMode mode, double m, std::span<glm::vec3> out) {
  if (mode == CombineMode::kWeighted && !(m >= 0 && std::isfinite(m)))
    return make_error(ErrorCode::kInvalidArgument,
                      "the Wires blend's exponent m must be a finite number >= 0, not " + std::to_string(m));
  if (out.size() != rest.size())
    return make_error(ErrorCode::kInvalidArgument, "the output has " + std::to_string(out.size()) +
                                                       " points but the skin has " + std::to_string(rest.size()));
  for (size_t k = 0; k < deformed.size(); ++k)
    if (deformed[k].size() != rest.size())
      return make_error(ErrorCode::kInvalidArgument, "deformer " + std::to_string(k) + " gives " +
                                                         std::to_string(deformed[k].size()) + " points but the skin has " +
                                                         std::to_string(rest.size()));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rest.size(), 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const glm::dvec3 p(rest[i]);
      glm::dvec3 sum(0.0);
      if (mode == CombineMode::kSum) {
        for (const auto& d : deformed) sum += glm::dvec3(d[i]) - p;
      } else {
        double largest = 0.0;
        for (const auto& d : deformed) largest = std::max(largest, glm::length(glm::dvec3(d[i]) - p));
        if (largest > 0.0) {
          double wsum = 0.0;
          for (const auto& d : deformed) {
            const glm::dvec3 dp = glm::dvec3(d[i]) - p;
            const double w = m == 0.0 ? 1.0 : std::pow(glm::length(dp) / largest, m);  // in [0, 1], the largest 1
            sum += w * dp;
            wsum += w;
          }
          sum /= wsum;  // >= 1
        }
      }
      out[i] = glm::vec3(p + sum);
    }
  });
  return Ok{};
}

}  // namespace cagewrap
