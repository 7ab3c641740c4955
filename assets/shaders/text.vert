#version 330 core
// Glyph quads from the text renderer's atlas: one instance per glyph, positioned in frame
// pixels (top-left origin, whole framebuffer viewport), exactly one texel per pixel.
layout(location = 0) in vec4 a_rect;    // x0, y0, x1, y1 in frame pixels
layout(location = 1) in vec4 a_uv;      // atlas texels: u0, v0, u1, v1
layout(location = 2) in vec4 a_colour;
uniform vec2 u_viewport;
out vec2 v_uv;
out vec4 v_colour;
void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
  vec2 p = mix(a_rect.xy, a_rect.zw, corner);
  gl_Position = vec4(p.x / u_viewport.x * 2.0 - 1.0, 1.0 - p.y / u_viewport.y * 2.0, 0.0, 1.0);
  v_uv = mix(a_uv.xy, a_uv.zw, corner);
  v_colour = a_colour;
}
