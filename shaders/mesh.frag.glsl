#version 330 core
// Key light over the camera's shoulder, a cool fill from below, a rim to separate the silhouette;
// two-sided so open cages and inner faces read. u_use_vertex_color picks per-vertex colours.
in vec3 v_normal_view;
in vec3 v_position_view;
in vec4 v_color;
uniform vec4 u_color;
uniform int u_use_vertex_color;
uniform int u_lit;
out vec4 frag_color;
void main() {
  vec4 base = u_use_vertex_color != 0 ? v_color : u_color;
  if (u_lit == 0) { frag_color = base; return; }
  vec3 n = normalize(v_normal_view);
  vec3 view_dir = normalize(-v_position_view);
  if (dot(n, view_dir) < 0.0) n = -n;
  vec3 key_dir = normalize(vec3(0.45, 0.65, 0.6));
  vec3 fill_dir = normalize(vec3(-0.6, -0.3, 0.4));
  float key = max(dot(n, key_dir), 0.0);
  float fill = max(dot(n, fill_dir), 0.0);
  float rim = pow(1.0 - max(dot(n, view_dir), 0.0), 3.0);
  vec3 h = normalize(key_dir + view_dir);
  float spec = pow(max(dot(n, h), 0.0), 32.0) * 0.25;
  vec3 c = base.rgb * (0.22 + 0.85 * key + 0.25 * fill * vec3(0.8, 0.9, 1.1)) + vec3(spec) + 0.18 * rim;
  frag_color = vec4(c, base.a);
}
