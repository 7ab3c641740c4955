#version 330 core
// Ray–sphere intersection per pixel: exact silhouette and depth (gl_FragDepth), so
// spheres intersect each other correctly; Blinn–Phong light from the upper left.
flat in vec3 v_centre_view;
flat in float v_radius;
flat in float v_value;
#ifdef QUADS
in vec2 v_coord;
#endif
uniform mat4 u_proj;
uniform mat4 u_inv_proj;
uniform mat4 u_inv_view;   // view → world, for the cut at the box
uniform vec3 u_clip_lo;    // periodic images: the surface outside [lo, hi] is cut away
uniform vec3 u_clip_hi;
uniform vec2 u_viewport;
uniform vec2 u_viewport_origin;  // window position of the viewport (panels)
uniform sampler2D u_colormap;
uniform vec4 u_flat_colour;
uniform vec3 u_nan_colour;
out vec4 frag_colour;
void main() {
  vec2 ndc = (gl_FragCoord.xy - u_viewport_origin) / u_viewport * 2.0 - 1.0;
  vec4 pn = u_inv_proj * vec4(ndc, -1.0, 1.0);
  vec4 pf = u_inv_proj * vec4(ndc, 1.0, 1.0);
  vec3 o = pn.xyz / pn.w;
  vec3 d = normalize(pf.xyz / pf.w - o);
  vec3 oc = o - v_centre_view;
  float b = dot(oc, d);
  float c = dot(oc, oc) - v_radius * v_radius;
  float disc = b * b - c;
  if (disc < 0.0) discard;
  float t = -b - sqrt(disc);
  vec3 hit = o + t * d;
  vec3 n = (hit - v_centre_view) / v_radius;
  // Cut at the box (a sphere across a periodic face and its image): where the front
  // surface lies outside, the inside of the far surface shows through the cut, darker.
  float inner = 1.0;
  vec3 w = (u_inv_view * vec4(hit, 1.0)).xyz;
  if (any(lessThan(w, u_clip_lo)) || any(greaterThan(w, u_clip_hi))) {
    t = -b + sqrt(disc);
    hit = o + t * d;
    w = (u_inv_view * vec4(hit, 1.0)).xyz;
    if (any(lessThan(w, u_clip_lo)) || any(greaterThan(w, u_clip_hi))) discard;
    n = (v_centre_view - hit) / v_radius;
    inner = 0.55;
  }
  vec4 clip = u_proj * vec4(hit, 1.0);
  gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;

  vec3 base;
  if (u_flat_colour.a > 0.0) base = u_flat_colour.rgb;
  else if (isnan(v_value)) base = u_nan_colour;
  else base = texture(u_colormap, vec2(clamp(v_value, 0.0, 1.0), 0.5)).rgb;
  vec3 l = normalize(vec3(-0.4, 0.6, 0.7));
  vec3 h = normalize(l - d);
  float diffuse = max(dot(n, l), 0.0);
  float spec = pow(max(dot(n, h), 0.0), 48.0);
  vec3 colour = inner * (base * (0.28 + 0.72 * diffuse) + vec3(0.25) * spec);
  frag_colour = vec4(colour, 1.0);
}
