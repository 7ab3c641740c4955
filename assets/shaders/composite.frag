#version 330 core
// Draws a premultiplied-alpha RGBA8 texture over the whole viewport (texel = pixel).
uniform sampler2D u_image;
out vec4 frag_colour;
void main() {
  frag_colour = texelFetch(u_image, ivec2(gl_FragCoord.xy), 0);
}
