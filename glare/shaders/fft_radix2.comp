#version 450
// One radix-2 Stockham pass (the first pass for odd powers of two; then fft_radix4.comp) of a batched 1D complex FFT along one axis of a 2D grid (rows or
// columns), reading `source` and writing `destination` (ping-pong, so no pass reads what it writes).
// Formulation of Govindaraju et al. 2008, "High Performance Discrete Fourier Transforms on Graphics
// Processors", FftIteration with R = 2: butterfly j combines elements j and j + L/2 of the input
// and writes elements expand(j, Ns, 2) and expand(j, Ns, 2) + Ns, expand(j, Ns, R) = (j / Ns) * Ns * R + j % Ns.
// After log2(L) passes (Ns = 1, 2, 4, ..., L/2) the output is in natural order (autosort).
// Twiddles exp(-2 pi i m / L_max) come from a table computed in double precision on the CPU:
// GLSL sin/cos in single precision alone is accurate to only about 1e-3 after log2(L) passes.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Source { vec2 source[]; };
layout(std430, binding = 1) writeonly buffer Destination { vec2 destination[]; };
layout(std430, binding = 2) readonly buffer Twiddles { vec2 twiddles[]; };  // (cos, -sin)(2 pi m / L_max), m < L_max

uniform uint uLength;         // L, the transform length along this axis
uniform uint uSpan;           // Ns, the length of the sub-transforms already combined
uniform uint uTwiddleStride;  // L_max / (2 Ns): table index of exp(-2 pi i k / (2 Ns)) is k * stride
uniform uint uAxisStride;     // element step along the axis: 1 for rows, width for columns
uniform uint uLineStride;     // element step between lines: width for rows, 1 for columns
uniform uint uLines;          // number of lines in one layer
uniform uint uLayerStride;    // elements per layer (width * height)
uniform float uConjugate;     // +1 forward (exp(-i...)), -1 inverse (exp(+i...))
uniform float uScale;         // 1, or 1 / (width * height) on the last pass of an inverse transform
uniform bool uLinesAlongX;    // columns: invocation x walks the lines, so neighbours touch adjacent memory

vec2 complex_multiply(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

void main() {
  const uint j = uLinesAlongX ? gl_GlobalInvocationID.y : gl_GlobalInvocationID.x;
  const uint line = uLinesAlongX ? gl_GlobalInvocationID.x : gl_GlobalInvocationID.y;
  if (j >= uLength / 2u || line >= uLines) return;
  const uint base = gl_GlobalInvocationID.z * uLayerStride + line * uLineStride;
  const uint k = j & (uSpan - 1u);  // j % Ns, Ns a power of two
  const vec2 a = source[base + j * uAxisStride];
  const vec2 b = source[base + (j + uLength / 2u) * uAxisStride];
  vec2 w = twiddles[k * uTwiddleStride];
  w.y *= uConjugate;
  const vec2 wb = complex_multiply(w, b);
  const uint out0 = (j - k) * 2u + k;  // expand(j, Ns, 2)
  destination[base + out0 * uAxisStride] = (a + wb) * uScale;
  destination[base + (out0 + uSpan) * uAxisStride] = (a - wb) * uScale;
}
