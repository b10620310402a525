#version 450
// Luidolt 2020, section 5.3 (stimuli/perception/lab_colour.h): CIE L*a*b* of each pixel (linear
// Rec.709 in cd/m2, reference white Y_n from the host) for the acuity loss, which blurs L* and
// keeps a*, b*. lab[] holds (L*, a* / 500, b* / 200, 0).
//
// Float32: L*a*b* is carried as g = f(t) - 4/29 per axis, so that dark pixels do not lose their
// lightness to cancellation: in the linear branch g = t / (3 delta^2) exactly (the reference's
// 116 f - 16 with f near 4/29 would keep only 1e-6 of an L* of 0.01), and
// L* = 116 g_y, a* / 500 = g_x - g_y, b* / 200 = g_y - g_z. The cube root is exp2(log2(t) / 3)
// refined by one Newton step (GLSL has no cbrt; pow's error grows with |log2 t|).
// The lightness of the dark pixels (t <= delta^3, L* <= 8) is formed in double and rounded once:
// their own L* sets their blur (Eqs. 5.15, 5.16), and beside a bright pixel the rounding of it
// reaches the output multiplied by up to 9 (k^2 / sigma^2 in the kernel weight of the bright tap).
// Three products and a sum per pixel; no double transcendental is needed in that branch.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Frame { vec4 frame[]; };
layout(std430, binding = 1) writeonly buffer Lab { vec4 lab[]; };
uniform int uWidth;
uniform int uHeight;
uniform vec3 uInvWhite;  // 1 / (X_n, Y_n, Z_n) in cd/m2 (Rec.709's D65 white scaled to Y_n)
uniform double uInvWhiteY;  // 1 / Y_n in double

const float kDelta = 6.0 / 29.0;

// IEC 61966-2-1 linear Rec.709 to XYZ, rows (lab_colour.cpp, kRgbToXyz).
const vec3 kToX = vec3(0.41239079926595948, 0.35758433938387796, 0.18048078840183429);
const vec3 kToY = vec3(0.21263900587151036, 0.71516867876775593, 0.07219231536073372);
const vec3 kToZ = vec3(0.01933081871559185, 0.11919477979462599, 0.95053215224966058);
const dvec3 kToYDouble = dvec3(0.21263900587151036lf, 0.71516867876775593lf, 0.07219231536073372lf);

float cube_root(float t) {
  float c = exp2(log2(t) / 3.0);
  return c - (c * c * c - t) / (3.0 * c * c);
}

// f(t) - 4/29 of CIE 1976.
float lab_g(float t) {
  if (t > kDelta * kDelta * kDelta) return cube_root(t) - 4.0 / 29.0;
  return t / (3.0 * kDelta * kDelta);
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uWidth || p.y >= uHeight) return;
  const int i = p.y * uWidth + p.x;
  const vec3 rgb = frame[i].rgb;
  const vec3 t = vec3(dot(kToX, rgb), dot(kToY, rgb), dot(kToZ, rgb)) * uInvWhite;
  vec3 g = vec3(lab_g(t.x), lab_g(t.y), lab_g(t.z));
  float lightness = 116.0 * g.y;
  const double ty = dot(kToYDouble, dvec3(rgb)) * uInvWhiteY;
  if (ty <= double(kDelta * kDelta * kDelta)) {
    const double gy = ty / (3.0lf * (6.0lf / 29.0lf) * (6.0lf / 29.0lf));
    g.y = float(gy);
    lightness = float(116.0lf * gy);
  }
  lab[i] = vec4(lightness, g.x - g.y, g.y - g.z, 0.0);
}
