#version 330 core
// Draws a premultiplied-alpha RGBA8 texture over the whole viewport (texel = pixel).
// u_origin: the viewport's lower-left corner in window pixels (a panel of a multi-panel
// frame); zero for a full-frame viewport.
uniform sampler2D u_image;
uniform vec2 u_origin;
out vec4 frag_colour;
void main() {
  frag_colour = texelFetch(u_image, ivec2(gl_FragCoord.xy - u_origin), 0);
}
