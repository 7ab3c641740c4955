#version 330 core
// 2D disks: one point sprite (or, with QUADS, one instanced quad) per disk. The colour is
// looked up here, once per disk, and passed flat: on llvmpipe every interpolated varying
// costs set-up time per primitive, which dominates for 10^5 small disks.
layout(location = 0) in vec4 a_pos_radius;  // x, y, z (unused), radius in world units
layout(location = 1) in float a_value;      // colour-map coordinate in [0,1]; NaN = no value
uniform mat4 u_view_proj;
uniform float u_pixels_per_unit;
uniform vec2 u_viewport;
uniform sampler2D u_colormap;
uniform vec4 u_flat_colour;  // alpha > 0: draw every disk in this colour
uniform vec3 u_nan_colour;
flat out vec4 v_colour_radius;  // rgb, radius in pixels
#ifdef QUADS
out vec2 v_coord;
#endif
void main() {
  gl_Position = u_view_proj * vec4(a_pos_radius.xy, 0.0, 1.0);
  float radius_px = a_pos_radius.w * u_pixels_per_unit;
  float size_px = 2.0 * radius_px + 2.0;  // one pixel of margin each side for the soft edge
  vec3 c;
  if (u_flat_colour.a > 0.0) c = u_flat_colour.rgb;
  else if (isnan(a_value)) c = u_nan_colour;
  else c = textureLod(u_colormap, vec2(clamp(a_value, 0.0, 1.0), 0.5), 0.0).rgb;
  v_colour_radius = vec4(c, radius_px);
#ifdef QUADS
  vec2 corner = vec2(float(gl_VertexID & 1) * 2.0 - 1.0, float(gl_VertexID >> 1) * 2.0 - 1.0);
  gl_Position.xy += corner * size_px / u_viewport * gl_Position.w;
  v_coord = corner * 0.5 + 0.5;
#else
  gl_PointSize = size_px;
#endif
}
