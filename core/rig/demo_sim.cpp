#include "core/rig/demo_sim.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cagewrap {

PolyMesh grid_sheet(const glm::dvec3& origin, const glm::dvec3& right, const glm::dvec3& down, int cols, int rows) {
  PolyMesh m;
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= cols; ++i)
      m.positions.emplace_back(origin + right * (static_cast<double>(i) / cols) + down * (static_cast<double>(j) / rows));
  auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (cols + 1) + i); };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) m.add_face({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
  return m;
}

SimSettings demo_belly_sim(std::span<const glm::vec3> cage_rest) {
  SimSettings s;
  s.enabled = true;
  s.params.gravity = glm::dvec3(0.0);
  s.params.edges = false;  // each belly vertex its own spring: a membrane pinned all round would barely move
  s.params.damping = 3.0;
  s.params.goal_frequency = 2.0;
  s.vertices.assign(cage_rest.size(), SimVertex{});
  for (size_t v = 0; v < cage_rest.size(); ++v) {
    const glm::vec3 p = cage_rest[v];
    if (p.z < 0.02f) continue;  // the front only
    const double r2 = std::pow(p.x / 0.14, 2.0) + std::pow((p.y - 1.12) / 0.17, 2.0);
    if (r2 >= 1.0) continue;
    // soft in the middle, stiffer toward the region's edge, where it meets the pinned vertices
    s.vertices[v] = {false, 1.0f, static_cast<float>(0.25 + 0.6 * r2)};
  }
  return s;
}

Result<DemoCape> make_demo_cape(const Character& demo, const PolyMesh& body_cage) {
  const int32_t chest_node = demo.skeleton.find("chest");
  if (chest_node < 0 || demo.skins.empty() || demo.primitives.empty())
    return make_error(ErrorCode::kInvalidArgument,
                      "the cape needs the demo character (a skinned mesh with a joint named 'chest')");
  const auto& joints = demo.skins[0].joints;
  const auto it = std::find(joints.begin(), joints.end(), static_cast<uint32_t>(chest_node));
  if (it == joints.end())
    return make_error(ErrorCode::kInvalidArgument, "the character's joint 'chest' is not a joint of its skin");
  const auto chest = static_cast<uint16_t>(it - joints.begin());

  // the cape hangs from behind the shoulders, slanted back; it drapes over the back during the pre-roll
  const glm::dvec3 origin(-0.2, 1.44, -0.16), right(0.4, 0.0, 0.0), down(0.0, -0.85, -0.3);
  DemoCape out;
  out.character = demo;
  out.character.source = "demo character with a cape (generated)";
  const PolyMesh skin = grid_sheet(origin, right, down, 40, 80);
  Primitive cape;
  // a second primitive of the body's mesh (a glTF node holds one mesh)
  cape.mesh_name = demo.primitives[0].mesh_name;
  cape.mesh = demo.primitives[0].mesh;
  cape.primitive = static_cast<uint32_t>(demo.primitives.size());
  cape.node = demo.primitives[0].node;
  cape.skin = 0;
  cape.positions = skin.positions;
  for (size_t f = 0; f < skin.num_faces(); ++f) {
    const auto q = skin.face(f);
    cape.triangles.push_back({q[0], q[1], q[2]});
    cape.triangles.push_back({q[0], q[2], q[3]});
  }
  cape.influence_start.resize(cape.positions.size() + 1);
  for (size_t v = 0; v <= cape.positions.size(); ++v) cape.influence_start[v] = static_cast<uint32_t>(v);
  cape.influence_joint.assign(cape.positions.size(), chest);
  cape.influence_weight.assign(cape.positions.size(), 1.0f);
  out.character.primitives.push_back(std::move(cape));

  const int cols = 6, rows = 10;
  const PolyMesh sheet = grid_sheet(origin, right, down, cols, rows);
  out.cage = body_cage;
  out.first_cape_vertex = static_cast<uint32_t>(body_cage.num_vertices());
  out.cage.positions.insert(out.cage.positions.end(), sheet.positions.begin(), sheet.positions.end());
  for (size_t f = 0; f < sheet.num_faces(); ++f) {
    std::vector<uint32_t> q(sheet.face(f).begin(), sheet.face(f).end());
    for (uint32_t& v : q) v += out.first_cape_vertex;
    out.cage.add_face(q);
  }
  // distances in 2 cm units: the body's elements then never reach the cape (6 cm and more away at
  // rest) and the cape's never reach the body
  out.params.scale = 0.02;

  SimSettings& s = out.sim;
  s.enabled = true;
  s.params.iterations = 2;
  s.params.damping = 1.0;
  s.params.skeleton_colliders = true;
  s.params.collision_margin = 0.03;
  s.params.preroll = 1.0;
  s.vertices.assign(out.cage.num_vertices(), SimVertex{});
  for (size_t v = out.first_cape_vertex + cols + 1; v < out.cage.num_vertices(); ++v)
    s.vertices[v] = {false, 1.0f, 0.0f};
  return out;
}

}  // namespace cagewrap
