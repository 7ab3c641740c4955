#version 330 core
// One quad over the field's grid rectangle [u_lo, u_hi] (world units).
uniform mat4 u_view_proj;
uniform vec2 u_lo;
uniform vec2 u_hi;
out vec2 v_world;
void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
  v_world = mix(u_lo, u_hi, corner);
  gl_Position = u_view_proj * vec4(v_world, 0.0, 1.0);
}
