#version 450
// One radix-4 Stockham pass (Govindaraju et al. 2008, FftIteration with R = 4): butterfly j reads
// elements j + r L/4 (r = 0..3), multiplies element r by exp(-+2 pi i r k / (4 Ns)), k = j % Ns, takes
// the 4-point DFT and writes elements expand(j, Ns, 4) + r Ns, expand(j, Ns, 4) = (j / Ns) 4 Ns + k.
// Half the passes of radix 2, so half the memory traffic; an odd power of two starts with one
// radix-2 pass (fft_radix2.comp). Twiddles from the double-precision table as in fft_radix2.comp.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Source { vec2 source[]; };
layout(std430, binding = 1) writeonly buffer Destination { vec2 destination[]; };
layout(std430, binding = 2) readonly buffer Twiddles { vec2 twiddles[]; };  // (cos, -sin)(2 pi m / L_max), m < L_max

uniform uint uLength;
uniform uint uSpan;           // Ns
uniform uint uTwiddleStride;  // L_max / (4 Ns): exp(-2 pi i r k / (4 Ns)) is entry r k stride
uniform uint uAxisStride;
uniform uint uLineStride;
uniform uint uLines;
uniform uint uLayerStride;
uniform float uConjugate;     // +1 forward, -1 inverse
uniform float uScale;
uniform bool uLinesAlongX;

vec2 complex_multiply(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

vec2 twiddle(uint index) {
  vec2 w = twiddles[index];
  w.y *= uConjugate;
  return w;
}

void main() {
  const uint j = uLinesAlongX ? gl_GlobalInvocationID.y : gl_GlobalInvocationID.x;
  const uint line = uLinesAlongX ? gl_GlobalInvocationID.x : gl_GlobalInvocationID.y;
  const uint quarter = uLength / 4u;
  if (j >= quarter || line >= uLines) return;
  const uint base = gl_GlobalInvocationID.z * uLayerStride + line * uLineStride;
  const uint k = j & (uSpan - 1u);
  const vec2 a0 = source[base + j * uAxisStride];
  const vec2 a1 = complex_multiply(twiddle(k * uTwiddleStride), source[base + (j + quarter) * uAxisStride]);
  const vec2 a2 = complex_multiply(twiddle(2u * k * uTwiddleStride), source[base + (j + 2u * quarter) * uAxisStride]);
  const vec2 a3 = complex_multiply(twiddle(3u * k * uTwiddleStride), source[base + (j + 3u * quarter) * uAxisStride]);
  // 4-point DFT; -i (forward) or +i (inverse) times t = (t.y, -t.x) * uConjugate.
  const vec2 s02 = a0 + a2, d02 = a0 - a2, s13 = a1 + a3, t = a1 - a3;
  const vec2 minus_i_t = vec2(t.y, -t.x) * uConjugate;
  const uint out0 = (j - k) * 4u + k;
  destination[base + out0 * uAxisStride] = (s02 + s13) * uScale;
  destination[base + (out0 + uSpan) * uAxisStride] = (d02 + minus_i_t) * uScale;
  destination[base + (out0 + 2u * uSpan) * uAxisStride] = (s02 - s13) * uScale;
  destination[base + (out0 + 3u * uSpan) * uAxisStride] = (d02 - minus_i_t) * uScale;
}
