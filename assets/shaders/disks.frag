#version 330 core
// Anti-aliased disk with a thin darker rim so touching disks stay distinguishable.
flat in vec4 v_colour_radius;
#ifdef QUADS
in vec2 v_coord;
#endif
out vec4 frag_colour;
void main() {
#ifdef QUADS
  vec2 pc = v_coord;
#else
  vec2 pc = gl_PointCoord;
#endif
  float radius_px = v_colour_radius.w;
  float r = length((pc - 0.5) * (2.0 * radius_px + 2.0));
  float coverage = clamp(radius_px - r + 0.5, 0.0, 1.0);
  if (coverage <= 0.0) discard;
  vec3 c = v_colour_radius.rgb;
  // Rim only where the disk is large enough on screen to carry one.
  if (radius_px > 3.0) {
    float rim_px = max(0.6, 0.12 * radius_px);
    c *= 1.0 - 0.45 * smoothstep(radius_px - rim_px - 0.5, radius_px - rim_px + 0.5, r);
  }
  frag_colour = vec4(c, coverage);
}
