#version 330 core
// Colour-mapped scalar field. u_field (RG32F, one texel per bin): r = value already
// normalised to the colour range, g = 1 for a valid bin, 0 for a masked or non-finite one.
// A fragment whose own bin is invalid gets exactly u_nan_colour. Bilinear mode interpolates
// between bin centres over the valid neighbours only, so neither the neutral colour nor
// a masked bin's undefined value leaks into valid bins (and no colour into masked ones).
uniform sampler2D u_field;
uniform sampler2D u_colormap;  // 256 × 1 RGBA8, linear
uniform vec2 u_lo;
uniform vec2 u_hi;
uniform int u_bilinear;
uniform vec3 u_nan_colour;
in vec2 v_world;
out vec4 frag_colour;
void main() {
  ivec2 n = textureSize(u_field, 0);
  vec2 g = (v_world - u_lo) / (u_hi - u_lo) * vec2(n);
  ivec2 cell = clamp(ivec2(floor(g)), ivec2(0), n - 1);
  vec2 own = texelFetch(u_field, cell, 0).rg;
  if (own.g < 0.5) {
    frag_colour = vec4(u_nan_colour, 1.0);
    return;
  }
  float t = own.r;
  if (u_bilinear != 0) {
    vec2 q = g - 0.5;
    vec2 base = floor(q);
    vec2 f = q - base;
    ivec2 i0 = ivec2(base);
    float sw = 0.0, sv = 0.0;
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx) {
        vec2 s = texelFetch(u_field, clamp(i0 + ivec2(dx, dy), ivec2(0), n - 1), 0).rg;
        float w = (dx == 1 ? f.x : 1.0 - f.x) * (dy == 1 ? f.y : 1.0 - f.y) * s.g;
        sw += w;
        sv += w * s.r;
      }
    if (sw > 0.0) t = sv / sw;
  }
  float u = (clamp(t, 0.0, 1.0) * 255.0 + 0.5) / 256.0;
  frag_colour = vec4(texture(u_colormap, vec2(u, 0.5)).rgb, 1.0);
}
