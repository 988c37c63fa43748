// Draws the editor's 3-D view from core data: the skin (lit, normals recomputed as it deforms), the
// cage as polygons (wire without the triangulation diagonals, translucent faces, vertices), the
// skeleton (bones and pickable joints), a ground grid and an axis indicator. No ImGui here.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/geometry/mesh.h"
#include "core/geometry/mesh_normals.h"
#include "render/gl_program.h"
#include "render/gpu_buffers.h"

namespace cagewrap::render {

struct ViewportStyle {
  bool show_skin = true;
  bool show_cage = true;
  bool show_other_cages = true;  // the other deformers' cages (update_other_cages)
  bool show_skeleton = true;
  bool show_grid = true;
  bool wireframe = false;  // skin as wireframe
  bool xray = false;       // skin translucent, cage and skeleton on top
  float cage_opacity = 0.07f;
};

struct ViewParams {
  glm::mat4 view{1.0f}, projection{1.0f};
  int x = 0, y = 0, width = 1, height = 1;  // viewport in framebuffer pixels
  float grid_spacing = 0.1f;
  int grid_lines = 20;  // each side of the origin
};

class ViewportRenderer {
 public:
  bool init(std::string& log);

  void set_skin_topology(size_t num_vertices, std::span<const Tri> triangles);
  void update_skin(std::span<const glm::vec3> positions);
  // The skin's vertex buffers, for a kernel that writes them on the GPU instead (render/gpu_deformer.h).
  TriangleBuffer& skin_buffer() { return *skin_; }
  // Per-vertex colours over the skin (heat maps); empty to return to the plain material.
  void set_skin_colors(std::span<const glm::vec4> colors);

  // element_face: #E polygon of each element (Cage::element_face), for face highlights.
  void set_cage_topology(const PolyMesh& polygons, std::span<const Tri> elements, std::span<const uint32_t> element_face);
  // `weights` (#Vc, may be empty) colour cage vertices: 1 = selected, (0, 1) = soft selection share.
  // `selected_faces` (#polygons, may be empty) highlights polygons.
  // `base_colors` (#Vc, may be empty) replace the plain vertex and edge colour (e.g. by bone).
  void update_cage(std::span<const glm::vec3> positions, std::span<const float> weights,
                   std::span<const uint8_t> selected_faces, std::span<const glm::vec4> base_colors = {});
  // Skin vertices drawn as points over the skin: the selection (pink) and flagged points (red, e.g.
  // those failing the cage-quality test).
  void update_skin_points(std::span<const glm::vec3> skin_positions, std::span<const uint32_t> selected,
                          std::span<const uint32_t> flagged);

  // A parametric driver's control net (core/deform/patch_surface.h), drawn on top: `points` (#C control
  // points), `edges` (pairs of control point indices), `selected` (a control point or -1)
  // highlighted. Empty `points` hide it. `samples` (may be empty): the driver's samples, drawn as small dots
  // coloured by `sample_states` (#samples: 0 plain, 1 driving the selected skin vertices, 2 picked).
  void update_control_net(std::span<const glm::vec3> points, std::span<const std::array<uint32_t, 2>> edges,
                          int selected, std::span<const glm::vec3> samples = {}, std::span<const uint8_t> sample_states = {});

  // The cages of the other deformers of the stack (issue 21), as line segments (pairs of points), drawn
  // fainter than the active cage when the cage is shown; empty hides them.
  void update_other_cages(std::span<const glm::vec3> segments);

  // Joint heads (#J) and bones as joint index pairs; `selected` (#J mask, may be empty) highlighted.
  void update_skeleton(std::span<const glm::vec3> heads, std::span<const std::array<uint32_t, 2>> bones,
                       std::span<const uint8_t> selected);

  void draw(const ViewParams& view, const ViewportStyle& style);

 private:
  void draw_round_points(LineBuffer& points, float size);
  void draw_grid(const ViewParams& v);
  void draw_axes(const ViewParams& v);

  GlProgram mesh_program_, line_program_;
  std::unique_ptr<TriangleBuffer> skin_, cage_faces_, cage_selected_faces_;
  std::unique_ptr<LineBuffer> cage_edges_, cage_points_, skin_points_, bones_, joints_, grid_, axes_;
  std::unique_ptr<LineBuffer> net_edges_, net_points_, net_samples_, other_cages_;
  std::vector<Tri> cage_elements_, selected_elements_;
  std::vector<uint32_t> element_face_;
  std::vector<uint8_t> uploaded_face_mask_;
  NormalComputer skin_normals_, cage_normals_;
  std::vector<glm::vec3> skin_normal_data_, cage_normal_data_;
  std::vector<std::array<uint32_t, 2>> cage_edge_list_;
  std::vector<glm::vec3> scratch_positions_;
  std::vector<glm::vec4> scratch_colors_;
  float grid_built_spacing_ = -1.0f;
  int grid_built_lines_ = -1;
};

}  // namespace cagewrap::render
