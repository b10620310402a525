#version 450
// A whole 1D complex FFT of LINES lines of LENGTH elements in one workgroup, in shared memory: the
// lines are read from the buffer once, every radix-4 Stockham stage (one radix-2 stage first for odd
// powers of two) runs between barriers in shared memory, and the result is written back once, to the
// places it was read from. So an axis of a 2D transform costs one read and one write of the grid
// instead of one of each per stage (log4 L passes through global memory).
// Stages as in Govindaraju et al. 2008, "High Performance Discrete Fourier Transforms on Graphics
// Processors", FftIteration with R = 4: butterfly j of a line reads elements j + r L/4 (r = 0..3),
// multiplies element r by exp(-+2 pi i r k / (4 Ns)), k = j % Ns, takes the 4-point DFT and writes
// elements (j - k) 4 + k + r Ns; after the last stage the line is in natural order (autosort).
// Twiddles exp(-2 pi i m / L_max) come from a table computed in double precision on the CPU
// (GLSL's single-precision sin and cos alone are accurate to only about 1e-3 after log2 L stages).
// Same sign convention as FFTW; uConjugate = -1 gives the inverse, uScale scales the written result.
//
// LENGTH, LINES and THREADS are defined by glare/gl/fft.cpp when it builds the program (LENGTH x LINES
// complex values fit the 32 KiB of shared memory OpenGL 4.5 guarantees: at most 4096); the values
// below only let the build's validator compile the file alone.
#ifndef LENGTH
#define LENGTH 1024
#define LINES 4
#define THREADS 256
#endif
layout(local_size_x = THREADS) in;

layout(std430, binding = 0) buffer Data { vec2 data[]; };
layout(std430, binding = 2) readonly buffer Twiddles { vec2 twiddles[]; };  // (cos, -sin)(2 pi m / L_max), m < L_max

uniform uint uAxisStride;      // element step along a line: 1 for rows, width for columns
uniform uint uLineStride;      // element step between lines: width for rows, 1 for columns
uniform uint uLayerStride;     // width * height
uniform uint uTwiddleLength;   // L_max, the table's length
uniform bool uLinesAlongX;     // columns: the workgroup's lines are adjacent in memory
uniform float uConjugate;      // +1 forward, -1 inverse
uniform float uScale;

const uint kElements = uint(LENGTH) * uint(LINES);
const uint kQuarter = uint(LENGTH) / 4u;
const uint kButterflies4 = kElements / 4u;  // radix-4 butterflies per stage, all lines
// THREADS divides the butterflies of every stage (all powers of two, THREADS <= kElements / 4), so
// every invocation takes the same number and the loops over them have constant trip counts.
const uint kPerThread4 = kButterflies4 / uint(THREADS);
const uint kPerThread2 = kElements / 2u / uint(THREADS);

shared vec2 line_values[kElements];

vec2 complex_multiply(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

vec2 twiddle(uint index) {
  vec2 w = twiddles[index];
  w.y *= uConjugate;
  return w;
}

// Element `element` of the workgroup's lines (line-major in shared memory) in the buffer. For
// columns, consecutive invocations take the same element of adjacent lines, which lie side by side
// in the buffer, so the reads and writes of a warp are contiguous either way.
uint buffer_index(uint element, out uint shared_index) {
  uint line, along;
  if (uLinesAlongX) {
    line = element % uint(LINES);
    along = element / uint(LINES);
  } else {
    line = element / uint(LENGTH);
    along = element % uint(LENGTH);
  }
  shared_index = line * uint(LENGTH) + along;
  const uint first_line = gl_WorkGroupID.x * uint(LINES);
  return gl_WorkGroupID.y * uLayerStride + (first_line + line) * uLineStride + along * uAxisStride;
}

void main() {
  const uint thread = gl_LocalInvocationID.x;
  for (uint element = thread; element < kElements; element += uint(THREADS)) {
    uint shared_index;
    const uint index = buffer_index(element, shared_index);
    line_values[shared_index] = data[index];
  }
  barrier();

  uint span = 1u;
  if ((uint(LENGTH) & 0xAAAAAAAAu) != 0u) {
    // Odd power of two: one radix-2 stage with Ns = 1 (every twiddle is 1): elements j and j + L/2
    // give elements 2j and 2j + 1.
    vec2 sums[kPerThread2], differences[kPerThread2];
    for (uint n = 0u; n < kPerThread2; ++n) {
      const uint butterfly = thread + n * uint(THREADS);
      const uint line = butterfly / (uint(LENGTH) / 2u), j = butterfly % (uint(LENGTH) / 2u);
      const vec2 a0 = line_values[line * uint(LENGTH) + j];
      const vec2 a1 = line_values[line * uint(LENGTH) + j + uint(LENGTH) / 2u];
      sums[n] = a0 + a1;
      differences[n] = a0 - a1;
    }
    barrier();
    for (uint n = 0u; n < kPerThread2; ++n) {
      const uint butterfly = thread + n * uint(THREADS);
      const uint line = butterfly / (uint(LENGTH) / 2u), j = butterfly % (uint(LENGTH) / 2u);
      line_values[line * uint(LENGTH) + 2u * j] = sums[n];
      line_values[line * uint(LENGTH) + 2u * j + 1u] = differences[n];
    }
    barrier();
    span = 2u;
  }

  for (; span < uint(LENGTH); span *= 4u) {
    const uint twiddle_stride = uTwiddleLength / (4u * span);
    vec2 outputs[kPerThread4 * 4u];
    for (uint n = 0u; n < kPerThread4; ++n) {
      const uint butterfly = thread + n * uint(THREADS);
      const uint line = butterfly / kQuarter, j = butterfly % kQuarter;
      const uint base = line * uint(LENGTH) + j;
      const uint k = j & (span - 1u);
      const vec2 a0 = line_values[base];
      const vec2 a1 = complex_multiply(twiddle(k * twiddle_stride), line_values[base + kQuarter]);
      const vec2 a2 = complex_multiply(twiddle(2u * k * twiddle_stride), line_values[base + 2u * kQuarter]);
      const vec2 a3 = complex_multiply(twiddle(3u * k * twiddle_stride), line_values[base + 3u * kQuarter]);
      // 4-point DFT; -i (forward) or +i (inverse) times t = (t.y, -t.x) * uConjugate.
      const vec2 s02 = a0 + a2, d02 = a0 - a2, s13 = a1 + a3, t = a1 - a3;
      const vec2 minus_i_t = vec2(t.y, -t.x) * uConjugate;
      outputs[4u * n] = s02 + s13;
      outputs[4u * n + 1u] = d02 + minus_i_t;
      outputs[4u * n + 2u] = s02 - s13;
      outputs[4u * n + 3u] = d02 - minus_i_t;
    }
    barrier();
    for (uint n = 0u; n < kPerThread4; ++n) {
      const uint butterfly = thread + n * uint(THREADS);
      const uint line = butterfly / kQuarter, j = butterfly % kQuarter;
      const uint k = j & (span - 1u);
      const uint out0 = line * uint(LENGTH) + (j - k) * 4u + k;
      line_values[out0] = outputs[4u * n];
      line_values[out0 + span] = outputs[4u * n + 1u];
      line_values[out0 + 2u * span] = outputs[4u * n + 2u];
      line_values[out0 + 3u * span] = outputs[4u * n + 3u];
    }
    barrier();
  }

  for (uint element = thread; element < kElements; element += uint(THREADS)) {
    uint shared_index;
    const uint index = buffer_index(element, shared_index);
    data[index] = line_values[shared_index] * uScale;
  }
}
