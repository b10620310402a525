#version 450
// Chromatic blur (Ritschel et al. 2009, section 5): the PSF for wavelength lambda_i is the
// reference PSF scaled in angle, F_lambda_i(x) = F_ref(x lambda_ref / lambda_i), read with bilinear
// interpolation about the centre pixel (N/2, N/2); zero outside the grid. Each wavelength's PSF is
// multiplied by (lambda_ref / lambda_i)^2 so it keeps the reference's integral over angle (a pure
// change of scale; every wavelength carries the same energy before spectral weighting). The sum is
// weighted by the CIE 1931 colour matching functions taken to linear Rec.709 (weights from the CPU),
// and negative values are clamped to 0.
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Reference { float reference[]; };  // N x N, unit sum
layout(std430, binding = 1) writeonly buffer Spectral { float spectral[]; };   // 3 x N x N, R, G, B
layout(std430, binding = 2) readonly buffer Weights { vec4 weights[]; };       // per wavelength: R, G, B, lambda_ref / lambda_i
uniform int uSize;
uniform int uWavelengthCount;

float texel(ivec2 p) {
  if (p.x < 0 || p.y < 0 || p.x >= uSize || p.y >= uSize) return 0.0;
  return reference[p.y * uSize + p.x];
}

float bilinear(vec2 p) {
  const vec2 base = floor(p);
  const vec2 f = p - base;
  const ivec2 i = ivec2(base);
  return mix(mix(texel(i), texel(i + ivec2(1, 0)), f.x), mix(texel(i + ivec2(0, 1)), texel(i + ivec2(1, 1)), f.x), f.y);
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= uSize || pixel.y >= uSize) return;
  const vec2 centre = vec2(uSize / 2);
  const vec2 offset = vec2(pixel) - centre;
  vec3 rgb = vec3(0.0);
  for (int i = 0; i < uWavelengthCount; ++i) {
    const vec4 w = weights[i];
    rgb += w.rgb * (w.a * w.a) * bilinear(centre + offset * w.a);
  }
  rgb = max(rgb, vec3(0.0));
  const int count = uSize * uSize;
  const int index = pixel.y * uSize + pixel.x;
  spectral[index] = rgb.r;
  spectral[count + index] = rgb.g;
  spectral[2 * count + index] = rgb.b;
}
