#version 450
// One wavelength of the spectral PSF with longitudinal chromatic aberration (docs/REFRACTION.md,
// glare/wave/chromatic_psf.h): the power spectrum |F|^2 of this wavelength's own pupil function (its own
// error E + [LCA(lambda) - LCA(lambda_ref)] I), read straight from the FFT's unshifted output with
// the zero frequency moved to pixel (N/2, N/2) (psf_power_shift.comp), resampled onto the reference
// grid and added, weighted, into R, G, B. As glare/wave/spectral_accumulation.cpp: a PSF computed at lambda
// has pixels of lambda / W, the reference grid pixels of lambda_ref / W, so reference pixel x reads
// source pixel (x - N/2) uScale + N/2, uScale = lambda_ref / lambda, by bilinear interpolation (zero
// outside the grid), times the Jacobian uScale^2 (folded into uWeight with the CIE 1931 CMF weight
// in linear Rec.709). Each wavelength's |F|^2 sums to N^2 sum |A|^2 whatever its phase (Parseval),
// so leaving out the per-wavelength unit-sum normalisation scales every term by the same constant,
// which the final per-channel normalisation removes. Each invocation owns one pixel: no races.
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Spectrum { vec2 spectrum[]; };  // N x N, unshifted FFT output
layout(std430, binding = 1) buffer Spectral { float spectral[]; };          // 3 x N x N, R, G, B sums
uniform int uSize;
uniform float uScale;  // lambda_ref / lambda
uniform vec3 uWeight;  // CMF weight in linear Rec.709 times uScale^2

float power_at(ivec2 p) {
  if (p.x < 0 || p.y < 0 || p.x >= uSize || p.y >= uSize) return 0.0;
  const ivec2 frequency = (p + ivec2(uSize / 2)) % uSize;
  const vec2 value = spectrum[frequency.y * uSize + frequency.x];
  return dot(value, value);
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= uSize || pixel.y >= uSize) return;
  const float centre = float(uSize / 2);
  const vec2 position = (vec2(pixel) - centre) * uScale + centre;
  const vec2 base = floor(position);
  const vec2 f = position - base;
  const ivec2 i = ivec2(base);
  const float value = mix(mix(power_at(i), power_at(i + ivec2(1, 0)), f.x),
                          mix(power_at(i + ivec2(0, 1)), power_at(i + ivec2(1, 1)), f.x), f.y);
  if (value == 0.0) return;
  const int count = uSize * uSize;
  const int index = pixel.y * uSize + pixel.x;
  spectral[index] += uWeight.r * value;
  spectral[count + index] += uWeight.g * value;
  spectral[2 * count + index] += uWeight.b * value;
}
