#version 330 core
// Colour-mapped scalar field. u_field (RG32F, one texel per bin): r = value already
// normalised to the colour range, g = 1 for a valid bin, 0 for a masked or non-finite one.
// A fragment whose own bin is invalid gets exactly u_nan_colour. Bilinear mode interpolates
// between bin centres over the valid neighbours only, so neither the neutral colour nor
// a masked bin's undefined value leaks into valid bins (and no colour into masked ones).
// The one exception is a masked bin at a solid circle (u_solids: centre, radius): the
// bin's centre is inside the obstacle but its corners poke out; outside the circle and
// within a bin diagonal of it, a smooth map takes the valid neighbours' colour, so the
// map meets the round obstacle instead of drawing square teeth around it.
uniform sampler2D u_field;
uniform sampler2D u_colormap;  // 256 × 1 RGBA8, linear
uniform vec2 u_lo;
uniform vec2 u_hi;
uniform int u_bilinear;
uniform vec3 u_nan_colour;
uniform int u_n_solids;
uniform vec3 u_solids[8];
in vec2 v_world;
out vec4 frag_colour;
void main() {
  ivec2 n = textureSize(u_field, 0);
  vec2 g = (v_world - u_lo) / (u_hi - u_lo) * vec2(n);
  ivec2 cell = clamp(ivec2(floor(g)), ivec2(0), n - 1);
  vec2 own = texelFetch(u_field, cell, 0).rg;
  bool at_solid = false;
  if (own.g < 0.5 && u_bilinear != 0) {
    float diagonal = length((u_hi - u_lo) / vec2(n));
    bool inside = false;
    for (int i = 0; i < u_n_solids; ++i) {
      float d = length(v_world - u_solids[i].xy) - u_solids[i].z;
      inside = inside || d < 0.0;
      at_solid = at_solid || d < diagonal;
    }
    at_solid = at_solid && !inside;
  }
  if (own.g < 0.5 && !at_solid) {
    frag_colour = vec4(u_nan_colour, 1.0);
    return;
  }
  float t = own.r;
  if (at_solid) {
    // The valid bins of the 3 × 3 around this one, each weighed by its nearness.
    float sw = 0.0, sv = 0.0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 c = clamp(cell + ivec2(dx, dy), ivec2(0), n - 1);
        vec2 s = texelFetch(u_field, c, 0).rg;
        float w = s.g / (0.25 + dot(vec2(c) + 0.5 - g, vec2(c) + 0.5 - g));
        sw += w;
        sv += w * s.r;
      }
    if (sw <= 0.0) {
      frag_colour = vec4(u_nan_colour, 1.0);
      return;
    }
    t = sv / sw;
  } else if (u_bilinear != 0) {
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
