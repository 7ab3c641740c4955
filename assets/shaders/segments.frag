#version 330 core
in vec4 v_colour;
in float v_across;
in float v_half_px;
out vec4 frag_colour;
void main() {
  float d = abs(v_across) * v_half_px;            // pixels from the centre line
  float coverage = clamp(v_half_px - d, 0.0, 1.0);
  frag_colour = vec4(v_colour.rgb, v_colour.a * coverage);
}
