#include "render/viewport_renderer.h"

#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>

namespace cagewrap::render {

namespace {
const glm::vec4 kSkinColor(0.78f, 0.62f, 0.52f, 1.0f);
const glm::vec4 kCageFaceColor(0.35f, 0.62f, 0.95f, 1.0f);
const glm::vec4 kCageEdgeColor(0.30f, 0.70f, 1.00f, 0.95f);
const glm::vec4 kSelectedColor(1.00f, 0.62f, 0.10f, 1.0f);
const glm::vec4 kSoftColor(1.00f, 0.95f, 0.25f, 1.0f);  // soft selection: edge colour -> this -> selected
const glm::vec4 kCagePointColor(0.15f, 0.45f, 0.85f, 1.0f);
const glm::vec4 kSkinPointColor(1.00f, 0.35f, 0.55f, 1.0f);
const glm::vec4 kFlaggedPointColor(0.95f, 0.10f, 0.10f, 1.0f);

glm::vec4 weight_color(float w, const glm::vec4& base) {
  if (w >= 0.999f) return kSelectedColor;
  if (w <= 0.0f) return base;
  return glm::mix(base, kSoftColor, 0.35f + 0.65f * w);
}
const glm::vec4 kBoneColor(0.95f, 0.95f, 0.35f, 1.0f);
const glm::vec4 kNetColor(0.25f, 0.85f, 0.95f, 1.0f);  // a parametric driver's control net
const glm::vec4 kJointColor(0.95f, 0.80f, 0.20f, 1.0f);
}  // namespace

bool ViewportRenderer::init(std::string& log) {
  if (!mesh_program_.build("mesh.vert.glsl", "mesh.frag.glsl", log)) return false;
  if (!line_program_.build("line.vert.glsl", "line.frag.glsl", log)) return false;
  skin_ = std::make_unique<TriangleBuffer>();
  cage_faces_ = std::make_unique<TriangleBuffer>();
  cage_selected_faces_ = std::make_unique<TriangleBuffer>();
  skin_points_ = std::make_unique<LineBuffer>();
  cage_edges_ = std::make_unique<LineBuffer>();
  cage_points_ = std::make_unique<LineBuffer>();
  bones_ = std::make_unique<LineBuffer>();
  joints_ = std::make_unique<LineBuffer>();
  grid_ = std::make_unique<LineBuffer>();
  axes_ = std::make_unique<LineBuffer>();
  net_edges_ = std::make_unique<LineBuffer>();
  net_points_ = std::make_unique<LineBuffer>();
  net_samples_ = std::make_unique<LineBuffer>();
  other_cages_ = std::make_unique<LineBuffer>();
  return true;
}

void ViewportRenderer::set_skin_topology(size_t num_vertices, std::span<const Tri> triangles) {
  skin_->upload_indices(triangles);
  skin_normals_ = NormalComputer(num_vertices, triangles);
  skin_normal_data_.assign(num_vertices, glm::vec3(0.f));
}

void ViewportRenderer::update_skin(std::span<const glm::vec3> positions) {
  skin_normals_.compute(positions, skin_normal_data_);
  skin_->upload_positions(positions, skin_normal_data_);
}

void ViewportRenderer::set_skin_colors(std::span<const glm::vec4> colors) { skin_->upload_colors(colors); }

void ViewportRenderer::set_cage_topology(const PolyMesh& polygons, std::span<const Tri> elements,
                                         std::span<const uint32_t> element_face) {
  cage_faces_->upload_indices(elements);
  cage_elements_.assign(elements.begin(), elements.end());
  element_face_.assign(element_face.begin(), element_face.end());
  uploaded_face_mask_.assign(1, 2);  // forces the highlight to be rebuilt
  cage_normals_ = NormalComputer(polygons.num_vertices(), elements);
  cage_normal_data_.assign(polygons.num_vertices(), glm::vec3(0.f));
  cage_edge_list_ = unique_edges(polygons);  // polygon edges only: no triangulation diagonals
}

void ViewportRenderer::update_cage(std::span<const glm::vec3> positions, std::span<const float> weights,
                                   std::span<const uint8_t> selected_faces, std::span<const glm::vec4> base_colors) {
  cage_normals_.compute(positions, cage_normal_data_);
  cage_faces_->upload_positions(positions, cage_normal_data_);
  if (!std::equal(selected_faces.begin(), selected_faces.end(), uploaded_face_mask_.begin(), uploaded_face_mask_.end())) {
    selected_elements_.clear();
    for (size_t e = 0; e < cage_elements_.size() && e < element_face_.size(); ++e)
      if (element_face_[e] < selected_faces.size() && selected_faces[element_face_[e]]) selected_elements_.push_back(cage_elements_[e]);
    cage_selected_faces_->upload_indices(selected_elements_);
    uploaded_face_mask_.assign(selected_faces.begin(), selected_faces.end());
  }
  if (!selected_elements_.empty()) cage_selected_faces_->upload_positions(positions, cage_normal_data_);
  auto w = [&](uint32_t v) { return v < weights.size() ? weights[v] : 0.0f; };
  scratch_positions_.clear();
  scratch_colors_.clear();
  for (auto [a, b] : cage_edge_list_) {
    scratch_positions_.push_back(positions[a]);
    scratch_positions_.push_back(positions[b]);
    scratch_colors_.push_back(weight_color(w(a), a < base_colors.size() ? base_colors[a] : kCageEdgeColor));
    scratch_colors_.push_back(weight_color(w(b), b < base_colors.size() ? base_colors[b] : kCageEdgeColor));
  }
  cage_edges_->upload(scratch_positions_, scratch_colors_);
  scratch_colors_.resize(positions.size());
  for (size_t i = 0; i < positions.size(); ++i)
    scratch_colors_[i] = weight_color(w(static_cast<uint32_t>(i)), i < base_colors.size() ? base_colors[i] : kCagePointColor);
  cage_points_->upload(positions, scratch_colors_);
}

void ViewportRenderer::update_skin_points(std::span<const glm::vec3> skin_positions, std::span<const uint32_t> selected,
                                          std::span<const uint32_t> flagged) {
  scratch_positions_.clear();
  scratch_colors_.clear();
  for (uint32_t v : flagged)
    if (v < skin_positions.size()) {
      scratch_positions_.push_back(skin_positions[v]);
      scratch_colors_.push_back(kFlaggedPointColor);
    }
  for (uint32_t v : selected)
    if (v < skin_positions.size()) {
      scratch_positions_.push_back(skin_positions[v]);
      scratch_colors_.push_back(kSkinPointColor);
    }
  skin_points_->upload(scratch_positions_, scratch_colors_);
}

void ViewportRenderer::update_control_net(std::span<const glm::vec3> points,
                                          std::span<const std::array<uint32_t, 2>> edges, int selected,
                                          std::span<const glm::vec3> samples, std::span<const uint8_t> sample_states) {
  scratch_positions_.clear();
  scratch_colors_.clear();
  for (const auto& [a, b] : edges)
    if (a < points.size() && b < points.size()) {
      scratch_positions_.insert(scratch_positions_.end(), {points[a], points[b]});
      scratch_colors_.insert(scratch_colors_.end(), 2, kNetColor);
    }
  net_edges_->upload(scratch_positions_, scratch_colors_);
  scratch_colors_.assign(points.size(), kNetColor);
  if (selected >= 0 && size_t(selected) < points.size()) scratch_colors_[size_t(selected)] = kSelectedColor;
  net_points_->upload(points, scratch_colors_);
  const glm::vec4 sample_colors[3] = {glm::vec4(0.80f, 0.85f, 0.90f, 0.9f), glm::vec4(0.35f, 0.95f, 0.35f, 1.0f), kSelectedColor};
  scratch_colors_.assign(samples.size(), sample_colors[0]);
  for (size_t i = 0; i < samples.size() && i < sample_states.size(); ++i) scratch_colors_[i] = sample_colors[std::min<uint8_t>(sample_states[i], 2)];
  net_samples_->upload(samples, scratch_colors_);
}

void ViewportRenderer::update_other_cages(std::span<const glm::vec3> segments) {
  scratch_colors_.assign(segments.size(), glm::vec4(0.55f, 0.75f, 0.95f, 0.55f));
  other_cages_->upload(segments, scratch_colors_);
}

void ViewportRenderer::update_skeleton(std::span<const glm::vec3> heads, std::span<const std::array<uint32_t, 2>> bones,
                                       std::span<const uint8_t> selected) {
  scratch_positions_.clear();
  scratch_colors_.clear();
  for (auto [a, b] : bones) {
    scratch_positions_.push_back(heads[a]);
    scratch_positions_.push_back(heads[b]);
    scratch_colors_.push_back(kBoneColor);
    scratch_colors_.push_back(kBoneColor * glm::vec4(0.7f, 0.7f, 0.7f, 1.0f));
  }
  bones_->upload(scratch_positions_, scratch_colors_);
  scratch_colors_.assign(heads.size(), kJointColor);
  for (size_t j = 0; j < selected.size() && j < heads.size(); ++j)
    if (selected[j]) scratch_colors_[j] = kSelectedColor;
  joints_->upload(heads, scratch_colors_);
}

void ViewportRenderer::draw_grid(const ViewParams& v) {
  if (v.grid_spacing != grid_built_spacing_ || v.grid_lines != grid_built_lines_) {
    scratch_positions_.clear();
    scratch_colors_.clear();
    const float ext = v.grid_spacing * v.grid_lines;
    for (int i = -v.grid_lines; i <= v.grid_lines; ++i) {
      float c = v.grid_spacing * i;
      glm::vec4 col = i == 0 ? glm::vec4(0.45f, 0.45f, 0.48f, 1.f)
                             : (i % 5 == 0 ? glm::vec4(0.33f, 0.33f, 0.36f, 1.f) : glm::vec4(0.26f, 0.26f, 0.28f, 1.f));
      scratch_positions_.insert(scratch_positions_.end(), {{c, 0, -ext}, {c, 0, ext}, {-ext, 0, c}, {ext, 0, c}});
      scratch_colors_.insert(scratch_colors_.end(), {col, col, col, col});
    }
    grid_->upload(scratch_positions_, scratch_colors_);
    grid_built_spacing_ = v.grid_spacing;
    grid_built_lines_ = v.grid_lines;
  }
  grid_->draw(GL_LINES);
}

void ViewportRenderer::draw_axes(const ViewParams& v) {
  // a small indicator in the lower-left corner, rotating with the view
  const int size = std::min(90, std::min(v.width, v.height) / 4);
  glViewport(v.x + 8, v.y + 8, size, size);
  glm::mat4 rot = v.view;
  rot[3] = glm::vec4(0, 0, -3, 1);
  line_program_.set("u_view", rot);
  line_program_.set("u_projection", glm::perspective(glm::radians(30.0f), 1.0f, 0.1f, 10.0f));
  const glm::vec3 o(0.f);
  const glm::vec3 pts[6] = {o, {0.75f, 0, 0}, o, {0, 0.75f, 0}, o, {0, 0, 0.75f}};
  const glm::vec4 cols[6] = {{0.95f, 0.3f, 0.3f, 1}, {0.95f, 0.3f, 0.3f, 1}, {0.4f, 0.9f, 0.4f, 1},
                             {0.4f, 0.9f, 0.4f, 1},  {0.35f, 0.55f, 1, 1},   {0.35f, 0.55f, 1, 1}};
  axes_->upload(pts, cols);
  glDisable(GL_DEPTH_TEST);
  axes_->draw(GL_LINES);
  glEnable(GL_DEPTH_TEST);
  glViewport(v.x, v.y, v.width, v.height);
}

// Points drawn as discs of `size` pixels with the line program (already in use).
void ViewportRenderer::draw_round_points(LineBuffer& points, float size) {
  line_program_.set("u_point_size", size);
  line_program_.set("u_round_points", 1);
  points.draw(GL_POINTS);
  line_program_.set("u_round_points", 0);
}

void ViewportRenderer::draw(const ViewParams& v, const ViewportStyle& style) {
  glViewport(v.x, v.y, v.width, v.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glEnable(GL_LINE_SMOOTH);

  line_program_.use();
  line_program_.set("u_view", v.view);
  line_program_.set("u_projection", v.projection);
  line_program_.set("u_point_size", 1.0f);
  line_program_.set("u_depth_bias", 0.0f);
  line_program_.set("u_round_points", 0);
  if (style.show_grid) draw_grid(v);

  mesh_program_.use();
  mesh_program_.set("u_view", v.view);
  mesh_program_.set("u_projection", v.projection);
  mesh_program_.set("u_lit", 1);
  if (style.show_skin) {
    mesh_program_.set("u_use_vertex_color", skin_->has_colors() ? 1 : 0);
    glm::vec4 color = kSkinColor;
    if (style.xray) {
      color.w = 0.35f;
      glDepthMask(GL_FALSE);
    }
    mesh_program_.set("u_color", color);
    if (style.wireframe) glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    skin_->draw();
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDepthMask(GL_TRUE);
  }
  const bool on_top = style.xray;
  if (style.show_cage) {
    mesh_program_.set("u_use_vertex_color", 0);
    mesh_program_.set("u_color", glm::vec4(glm::vec3(kCageFaceColor), style.cage_opacity));
    glDepthMask(GL_FALSE);
    cage_faces_->draw();
    if (!selected_elements_.empty()) {
      mesh_program_.set("u_color", glm::vec4(glm::vec3(kSelectedColor), 0.45f));
      cage_selected_faces_->draw();
    }
    glDepthMask(GL_TRUE);
    line_program_.use();
    line_program_.set("u_depth_bias", on_top ? 1.0f : 0.0005f);
    glLineWidth(1.5f);
    cage_edges_->draw(GL_LINES);
    draw_round_points(*cage_points_, 5.0f);
  }
  if (style.show_other_cages && other_cages_->size() > 0) {
    line_program_.use();
    line_program_.set("u_depth_bias", on_top ? 1.0f : 0.0005f);
    glLineWidth(1.0f);
    other_cages_->draw(GL_LINES);
  }
  if (skin_points_->size() > 0) {
    line_program_.use();
    line_program_.set("u_depth_bias", on_top ? 1.0f : 0.0005f);
    draw_round_points(*skin_points_, 6.0f);
  }
  if (net_points_->size() > 0) {  // the control net is the driver: always on top, like the skeleton
    line_program_.use();
    line_program_.set("u_depth_bias", 1.0f);
    glLineWidth(2.0f);
    net_edges_->draw(GL_LINES);
    draw_round_points(*net_points_, 8.0f);
    if (net_samples_->size() > 0) draw_round_points(*net_samples_, 6.0f);
  }
  if (style.show_skeleton) {
    line_program_.use();
    line_program_.set("u_depth_bias", 1.0f);  // the skeleton is inside the skin: always on top
    glLineWidth(2.5f);
    bones_->draw(GL_LINES);
    draw_round_points(*joints_, 9.0f);
  }
  glLineWidth(1.0f);
  line_program_.use();
  line_program_.set("u_depth_bias", 0.0f);
  draw_axes(v);
}

}  // namespace cagewrap::render
