#version 330 core
// Thick line segments with a width in pixels: one instanced quad per segment, expanded in
// screen space. Serves outlines, box edges, streamlines and arrows.
layout(location = 0) in vec3 a_p0;
layout(location = 1) in vec3 a_p1;
layout(location = 2) in vec4 a_colour;
layout(location = 3) in float a_width_px;
uniform mat4 u_view_proj;
uniform vec2 u_viewport;
out vec4 v_colour;
out float v_across;  // -1..1 across the segment, for the soft edge
out float v_half_px;
void main() {
  vec4 c0 = u_view_proj * vec4(a_p0, 1.0);
  vec4 c1 = u_view_proj * vec4(a_p1, 1.0);
  vec2 s0 = c0.xy / c0.w * 0.5 * u_viewport;
  vec2 s1 = c1.xy / c1.w * 0.5 * u_viewport;
  vec2 dir = s1 - s0;
  float len = length(dir);
  dir = len > 1e-6 ? dir / len : vec2(1.0, 0.0);
  vec2 nrm = vec2(-dir.y, dir.x);
  float along = float(gl_VertexID & 1);          // 0 at p0, 1 at p1
  float side = float(gl_VertexID >> 1) * 2.0 - 1.0;
  v_half_px = 0.5 * a_width_px + 0.5;
  vec4 c = along < 0.5 ? c0 : c1;
  // Extend by half a width at the ends so consecutive segments join without gaps.
  vec2 offset_px = side * v_half_px * nrm + (along * 2.0 - 1.0) * 0.5 * a_width_px * dir;
  gl_Position = c + vec4(offset_px / (0.5 * u_viewport) * c.w, 0.0, 0.0);
  v_colour = a_colour;
  v_across = side;
}
