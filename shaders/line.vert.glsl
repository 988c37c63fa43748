#version 330 core
// Coloured lines and points (cage wire, skeleton, grid, axes).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_point_size;
uniform float u_depth_bias;
out vec4 v_color;
void main() {
  gl_Position = u_projection * u_view * vec4(a_position, 1.0);
  gl_Position.z -= u_depth_bias * gl_Position.w;
  gl_PointSize = u_point_size;
  v_color = a_color;
}
