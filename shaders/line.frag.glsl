#version 330 core
in vec4 v_color;
uniform int u_round_points;
out vec4 frag_color;
void main() {
  if (u_round_points != 0) {
    vec2 d = gl_PointCoord - vec2(0.5);
    if (dot(d, d) > 0.25) discard;
  }
  frag_color = v_color;
}
