#include "core/deform/patch_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <map>
#include <set>

namespace cagewrap {

namespace {

Error bad(const std::string& m) {
  return make_error(ErrorCode::kInvalidArgument, m);
}
std::string face_name(uint32_t f) {
  return "cage face " + std::to_string(f);
}

// In quad `q` (4 corners in ring order) holding the edge x-y: the corner next to x that is not y.
uint32_t across(std::span<const uint32_t> q, uint32_t x, uint32_t y) {
  for (size_t k = 0; k < 4; ++k)
    if (q[k] == x) return q[(k + 1) % 4] == y ? q[(k + 3) % 4] : q[(k + 1) % 4];
  return UINT32_MAX;
}

}  // namespace

Result<QuadGrid> quad_grid_of_faces(const PolyMesh& cage, std::span<const uint32_t> faces_in) {
  std::vector<uint32_t> faces(faces_in.begin(), faces_in.end());
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  if (faces.empty())
    return bad("no cage faces are selected; select a rectangle of quads to fit a patch grid to");
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edge_faces;
  std::map<uint32_t, uint32_t> valence;  // selected faces at each vertex
  for (uint32_t f : faces) {
    if (f >= cage.num_faces())
      return bad(face_name(f) + " does not exist (the cage has " + std::to_string(cage.num_faces()) +
                 " faces)");
    auto q = cage.face(f);
    if (q.size() != 4)
      return bad(face_name(f) + " has " + std::to_string(q.size()) +
                 " corners; a patch grid is fitted to a rectangle of quads (4 corners each)");
    for (size_t k = 0; k < 4; ++k) {
      const uint32_t a = q[k], b = q[(k + 1) % 4];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
      ++valence[a];
    }
  }
  for (const auto& [e, fs] : edge_faces)
    if (fs.size() > 2)
      return bad("the edge between cage vertices " + std::to_string(e.first) + " and " +
                 std::to_string(e.second) + " is shared by " + std::to_string(fs.size()) +
                 " selected faces; select a rectangle of quads");
  auto other_face = [&](uint32_t x, uint32_t y, uint32_t not_this) -> uint32_t {
    const auto& fs = edge_faces[{std::min(x, y), std::max(x, y)}];
    for (uint32_t f : fs)
      if (f != not_this) return f;
    return UINT32_MAX;
  };
  // start at a corner of the rectangle: a vertex of a single selected face (lowest face first)
  uint32_t f0 = UINT32_MAX, k0 = 0;
  for (uint32_t f : faces) {
    auto q = cage.face(f);
    for (uint32_t k = 0; k < 4 && f0 == UINT32_MAX; ++k)
      if (valence[q[k]] == 1) f0 = f, k0 = k;
    if (f0 != UINT32_MAX) break;
  }
  if (f0 == UINT32_MAX)
    return bad(
        "the selected faces have no corner (a vertex of only one selected face): they close into a ring or "
        "a tube; select an open rectangle of quads");
  auto q0 = cage.face(f0);
  QuadGrid g;
  // rows of vertices grow as the walk goes; V[i] has cols + 1 entries once row 0 is known
  std::vector<std::vector<uint32_t>> V(2);
  std::vector<std::vector<uint32_t>> F(1);
  std::set<uint32_t> used{f0};
  V[0] = {q0[k0], q0[(k0 + 1) % 4]};
  V[1] = {q0[(k0 + 3) % 4], q0[(k0 + 2) % 4]};
  F[0] = {f0};
  // row 0: walk along u across the right-hand edges
  for (;;) {
    const uint32_t x = V[0].back(), y = V[1].back();
    const uint32_t f = other_face(x, y, F[0].back());
    if (f == UINT32_MAX) break;
    if (!used.insert(f).second)
      return bad("the selected faces close into a ring at " + face_name(f) +
                 "; select an open rectangle of quads");
    auto q = cage.face(f);
    V[0].push_back(across(q, x, y));
    V[1].push_back(across(q, y, x));
    F[0].push_back(f);
  }
  const size_t cols = F[0].size();
  // the next rows: across the bottom edges of the row above
  for (size_t i = 1;; ++i) {
    std::vector<uint32_t> row_faces, next(cols + 1, UINT32_MAX);
    for (size_t j = 0; j < cols; ++j) {
      const uint32_t x = V[i][j], y = V[i][j + 1];
      const uint32_t f = other_face(x, y, F[i - 1][j]);
      if (f == UINT32_MAX) {
        if (j == 0) break;
        return bad("the selected faces are not a rectangle: row " + std::to_string(i) +
                   " of the grid ends after " + std::to_string(j) + " of " + std::to_string(cols) +
                   " faces (next to " + face_name(F[i - 1][j]) + ")");
      }
      if (!used.insert(f).second)
        return bad("the selected faces close into a ring at " + face_name(f) +
                   "; select an open rectangle of quads");
      auto q = cage.face(f);
      const uint32_t a = across(q, x, y), b = across(q, y, x);
      if (next[j] != UINT32_MAX && next[j] != a)
        return bad("the selected faces are not a rectangle of quads around " + face_name(f) +
                   " (a vertex where more or fewer than four faces meet)");
      next[j] = a;
      next[j + 1] = b;
      row_faces.push_back(f);
    }
    if (row_faces.empty()) break;  // a shorter row returned above
    F.push_back(std::move(row_faces));
    V.push_back(std::move(next));
  }
  if (used.size() != faces.size()) {
    for (uint32_t f : faces)
      if (!used.count(f))
        return bad("the selected faces are not one rectangle of quads: " + face_name(f) + " is not in the " +
                   std::to_string(F.size()) + " x " + std::to_string(cols) + " rectangle that starts at " +
                   face_name(f0));
  }
  g.rows = static_cast<uint32_t>(F.size());
  g.cols = static_cast<uint32_t>(cols);
  std::set<uint32_t> seen;
  for (const auto& row : V)
    for (uint32_t v : row) {
      if (!seen.insert(v).second)
        return bad("the selected faces meet themselves at cage vertex " + std::to_string(v) +
                   " (a ring or a fold); select an open rectangle of quads");
      g.vertices.push_back(v);
    }
  for (const auto& row : F) g.faces.insert(g.faces.end(), row.begin(), row.end());
  return g;
}

namespace {

// Least squares along one direction: n control points of a clamped uniform cubic B-spline through
// m data points at uniform parameters, with second differences weighted by `smoothing`. Returns the
// n x m matrix that maps data to control points.
Eigen::MatrixXd fit_operator(uint32_t n, uint32_t m, double smoothing) {
  const double spans = n - 3;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, n);
  for (uint32_t j = 0; j < m; ++j) {
    const double t = m > 1 ? spans * j / (m - 1) : 0.0;
    const CubicBasis b = cubic_basis(PatchBasis::kBSpline, n, t);
    for (int k = 0; k < 4; ++k) A(j, b.first + k) = b.value[k];
  }
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n - 2, n);
  for (uint32_t k = 0; k + 2 < n; ++k) L(k, k) = 1, L(k, k + 1) = -2, L(k, k + 2) = 1;
  const Eigen::MatrixXd normal = A.transpose() * A + smoothing * L.transpose() * L;
  return normal.colPivHouseholderQr().solve(A.transpose());
}

}  // namespace

Result<PatchGrid> fit_patch_to_faces(const PolyMesh& cage, std::span<const glm::vec3> positions,
                                     std::span<const uint32_t> faces, const PatchFitOptions& options) {
  if (positions.size() != cage.num_vertices())
    return bad("the cage has " + std::to_string(cage.num_vertices()) + " vertices but " +
               std::to_string(positions.size()) + " positions were given");
  for (uint32_t n : {options.rows, options.cols})
    if (n != 0 && (n < 4 || n > 256))
      return bad("a fitted grid needs 4 to 256 control points a side (asked for " + std::to_string(n) + ")");
  if (!(options.smoothing > 0 && options.smoothing < 1e6))
    return bad("the fit's smoothing must be a positive number");
  auto grid = quad_grid_of_faces(cage, faces);
  if (!grid) return grid.error();
  const uint32_t mr = grid->rows + 1, mc = grid->cols + 1;  // data lines
  for (uint32_t v : grid->vertices) {
    const glm::vec3& p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return make_error(ErrorCode::kNonFinite,
                        "cage vertex " + std::to_string(v) + " has a non-finite coordinate");
  }
  PatchGrid out;
  out.basis = PatchBasis::kBSpline;
  out.rows = options.rows ? options.rows : std::max<uint32_t>(4, mr);
  out.cols = options.cols ? options.cols : std::max<uint32_t>(4, mc);
  Eigen::MatrixXd D(mr, 3 * mc);  // data: row i, then x, y, z blocks of columns
  for (uint32_t i = 0; i < mr; ++i)
    for (uint32_t j = 0; j < mc; ++j)
      for (int k = 0; k < 3; ++k) D(i, k * mc + j) = positions[grid->vertices[size_t(i) * mc + j]][k];
  const Eigen::MatrixXd fu = fit_operator(out.cols, mc, options.smoothing);  // cols x mc
  const Eigen::MatrixXd fv = fit_operator(out.rows, mr, options.smoothing);  // rows x mr
  out.points.resize(size_t(out.rows) * out.cols);
  for (int k = 0; k < 3; ++k) {
    const Eigen::MatrixXd P = fv * D.middleCols(k * mc, mc) * fu.transpose();  // rows x cols
    for (uint32_t r = 0; r < out.rows; ++r)
      for (uint32_t c = 0; c < out.cols; ++c) out.points[size_t(r) * out.cols + c][k] = P(r, c);
  }
  return out;
}

}  // namespace cagewrap
