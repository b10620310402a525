#version 450
// Monochromatic PSF before normalisation: |F{P E}|^2 (Ritschel et al. 2009, Eq. 3; K is replaced
// by the unit-sum normalisation), with the zero frequency moved to pixel (N/2, N/2) (fftshift).
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Spectrum { vec2 spectrum[]; };
layout(std430, binding = 1) writeonly buffer Power { float power[]; };
uniform int uSize;

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= uSize || pixel.y >= uSize) return;
  const int half_size = uSize / 2;
  const ivec2 frequency = (pixel + ivec2(half_size)) % uSize;
  const vec2 value = spectrum[frequency.y * uSize + frequency.x];
  power[pixel.y * uSize + pixel.x] = dot(value, value);
}
