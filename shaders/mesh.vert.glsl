#version 330 core
// Lit meshes (skin, cage faces): positions and normals in world space.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_color;
uniform mat4 u_view;
uniform mat4 u_projection;
out vec3 v_normal_view;
out vec3 v_position_view;
out vec4 v_color;
void main() {
  vec4 p = u_view * vec4(a_position, 1.0);
  v_position_view = p.xyz;
  v_normal_view = mat3(u_view) * a_normal;
  v_color = a_color;
  gl_Position = u_projection * p;
}
