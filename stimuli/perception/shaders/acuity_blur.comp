#version 450
// Luidolt 2020, section 5.3.1 (stimuli/perception/acuity_loss.h): the separable blur of L* with a
// Gaussian whose sigma each output pixel takes from its lightness (Eq. 5.15 with Eq. 5.14's
// resolvable frequency, or Eq. 5.16), zero where L* >= 1, capped at uMaxSigma, kernel size
// 2 floor(3 sigma) + 1 normalised to sum 1, edges clamped.
//   uPass 0: horizontal, lab[].x -> lightness[].
//   uPass 1: vertical, lightness[] -> L*, sigma from lightness[] (step 3, filtered lightness) or
//            from lab[].x (Fig. 5.9); then back to linear Rec.709 with a*, b* kept into result[].
//            A pixel whose L* is unchanged keeps its input bit for bit, as in the reference.
//
// Float32: Eq. 5.14's R(Y) = 17.25 atan(u) + 25.72 loses up to 20x to cancellation in the dark
// (R = 1.2 at u = -6.6, atan(u) = -1.42). atan is evaluated as k pi / 4 + atan(x), |x| <= tan(pi/8),
// with Cephes' atanf polynomial (relative error 1.9e-7), and 25.72 + 17.25 k pi / 4 comes from the
// host in double (uResolvableBase), so only the small remainder is rounded. Y of L* < 1 is the
// linear branch of CIE Lab, Y = Y_n 3 delta^2 L* / 116, formed without the reference's
// (L* + 16) / 116 - 4/29. The kernel weights use GLSL exp with |argument| <= 4.5.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Lab { vec4 lab[]; };
layout(std430, binding = 1) buffer Lightness { float lightness[]; };
layout(std430, binding = 2) readonly buffer Frame { vec4 frame[]; };
layout(std430, binding = 3) writeonly buffer Result { vec4 result[]; };
uniform int uWidth;
uniform int uHeight;
uniform int uPass;
uniform bool uSecondPassFiltered;  // SecondPassSigma::filtered_lightness
uniform bool uLuidoltLinear;       // AcuitySigmaForm::luidolt_linear (Eq. 5.16)
uniform float uMaxSigma;           // px
uniform float uSigmaNumerator;     // pixels per degree / (1.86 sqrt(2)), Eq. 5.15
uniform float uLuminancePerLightness;  // Y_n 3 delta^2 / 116, cd/m2 per unit of L* below L* = 8
uniform float uResolvableBase[5];  // 25.72 + 17.25 k pi / 4, k = -2..2
uniform vec3 uWhite;               // (X_n, Y_n, Z_n) in cd/m2

const float kDelta = 6.0 / 29.0;
const int kMaxRadius = 30;  // max_sigma_px <= 10

// XYZ to linear Rec.709, rows (lab_colour.cpp, kXyzToRgb).
const vec3 kToR = vec3(3.24096994190452134, -1.53738317757009346, -0.49861076029300328);
const vec3 kToG = vec3(-0.96924363628087983, 1.87596750150772067, 0.04155505740717561);
const vec3 kToB = vec3(0.05563007969699361, -0.20397695888897657, 1.05697151424287856);

// Cephes atanf on |x| <= tan(pi/8).
float atan_reduced(float x) {
  const float z = x * x;
  return (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1) * z * x + x;
}

// Eq. 5.14, cycles per degree: 17.25 atan(u) + 25.72 with atan(u) = k pi / 4 + atan(x).
float resolvable_frequency(float luminance) {
  const float u = 1.4 * (log2(luminance) * 0.30102999566398120) + 0.35;
  const float a = abs(u);
  int k;
  float x;
  if (a > 2.414213562373095) {
    k = 2;
    x = -1.0 / a;
  } else if (a > 0.4142135623730950) {
    k = 1;
    x = (a - 1.0) / (a + 1.0);
  } else {
    k = 0;
    x = a;
  }
  if (u < 0.0) {
    k = -k;
    x = -x;
  }
  return uResolvableBase[k + 2] + 17.25 * atan_reduced(x);
}

// acuity_loss.cpp, acuity_sigma_px.
float sigma_px(float l) {
  if (!(l < 1.0)) return 0.0;  // Eq. 5.16's support
  float sigma;
  if (uLuidoltLinear) {
    sigma = max(1.0 - l, 0.0);  // Eq. 5.16
  } else {
    const float luminance = uLuminancePerLightness * max(l, 0.0);
    const float r = luminance > 0.0 ? resolvable_frequency(luminance) : -1.0;
    sigma = r > 0.0 ? uSigmaNumerator / r : uMaxSigma;  // Eq. 5.15; nothing resolvable: the cap
  }
  return min(sigma, uMaxSigma);
}

float lab_g_inverse(float g) {  // t of g = f(t) - 4/29
  if (g > kDelta - 4.0 / 29.0) {
    const float f = g + 4.0 / 29.0;
    return f * f * f;
  }
  return 3.0 * kDelta * kDelta * g;
}

float source_at(int x, int y) { return uPass == 0 ? lab[y * uWidth + x].x : lightness[y * uWidth + x]; }

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uWidth || p.y >= uHeight) return;
  const int i = p.y * uWidth + p.x;
  const float own = source_at(p.x, p.y);
  const float sigma = sigma_px(uPass == 0 || uSecondPassFiltered ? own : lab[i].x);
  const int radius = min(int(floor(3.0 * sigma)), kMaxRadius);
  float blurred = own;  // the kernel {1}
  if (radius > 0) {
    const float inv_two_sigma2 = 1.0 / (2.0 * sigma * sigma);
    float weights = 0.0, sum = 0.0;
    // Two loops rather than one with a per-tap choice of buffer, so that each tap loads one value.
    if (uPass == 0) {
      for (int k = -radius; k <= radius; ++k) {
        const float w = exp(-float(k * k) * inv_two_sigma2);
        weights += w;
        sum += w * lab[p.y * uWidth + clamp(p.x + k, 0, uWidth - 1)].x;
      }
    } else {
      for (int k = -radius; k <= radius; ++k) {
        const float w = exp(-float(k * k) * inv_two_sigma2);
        weights += w;
        sum += w * lightness[clamp(p.y + k, 0, uHeight - 1) * uWidth + p.x];
      }
    }
    blurred = sum / weights;
  }
  if (uPass == 0) {
    lightness[i] = blurred;
    return;
  }
  const vec4 lab_colour = lab[i];
  if (blurred == lab_colour.x) {
    result[i] = frame[i];
    return;
  }
  const float gy = blurred / 116.0;
  const vec3 xyz = uWhite * vec3(lab_g_inverse(gy + lab_colour.y), lab_g_inverse(gy), lab_g_inverse(gy - lab_colour.z));
  result[i] = vec4(dot(kToR, xyz), dot(kToG, xyz), dot(kToB, xyz), frame[i].a);
}
