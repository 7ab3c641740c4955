#version 330 core
// Coverage from the R8 glyph atlas (FreeType's anti-aliased bitmaps) times the text colour.
uniform sampler2D u_atlas;
in vec2 v_uv;
in vec4 v_colour;
out vec4 frag_colour;
void main() {
  float coverage = texelFetch(u_atlas, ivec2(floor(v_uv)), 0).r;
  if (coverage <= 0.0) discard;
  frag_colour = vec4(v_colour.rgb, v_colour.a * coverage);
}
