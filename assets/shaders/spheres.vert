#version 330 core
// 3D sphere impostors: a screen-aligned sprite (point or, with QUADS, instanced quad)
// large enough to cover the sphere's silhouette; the fragment shader ray-casts it.
layout(location = 0) in vec4 a_pos_radius;  // centre (world), radius
layout(location = 1) in float a_value;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform vec2 u_viewport;
flat out vec3 v_centre_view;
flat out float v_radius;
flat out float v_value;
#ifdef QUADS
out vec2 v_coord;
#endif
void main() {
  vec4 c = u_view * vec4(a_pos_radius.xyz, 1.0);
  v_centre_view = c.xyz;
  v_radius = a_pos_radius.w;
  v_value = a_value;
  gl_Position = u_proj * c;
  // Projected diameter in pixels. Orthographic (w = 1): exact. Perspective: a sphere at
  // distance D subtends a disk of radius f·R/sqrt(D² − R²) on axis; off axis the outline
  // stretches by 1/cos θ (≤ 1.05 for the ≤ 35° field of view we use); w ≤ D keeps the
  // bound conservative. Every extra pixel is paid per sphere by the software rasteriser.
  bool ortho = u_proj[3][3] > 0.5;
  float w = gl_Position.w, r = a_pos_radius.w;
  float size_px = ortho ? 2.0 * r * u_proj[1][1] * 0.5 * u_viewport.y
                        : 1.06 * 2.0 * r * u_proj[1][1] * 0.5 * u_viewport.y / sqrt(max(w * w - r * r, 1e-8));
  size_px += 2.0;
#ifdef QUADS
  vec2 corner = vec2(float(gl_VertexID & 1) * 2.0 - 1.0, float(gl_VertexID >> 1) * 2.0 - 1.0);
  gl_Position.xy += corner * size_px / u_viewport * gl_Position.w;
  v_coord = corner * 0.5 + 0.5;
#else
  gl_PointSize = size_px;
#endif
}
