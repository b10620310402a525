#version 450
// A whole 1D complex FFT of LINES lines of LENGTH elements in one workgroup, in shared memory: the
// lines are read from the buffer once, every Stockham stage runs between barriers in shared memory,
// and the result is written back once, to the places it was read from. So an axis of a 2D transform
// costs one read and one write of the grid instead of one of each per stage.
// LENGTH is 2^a 3^b 5^c (glare/gl/fft.cpp): a padded convolution grid fitted to the frame instead of
// the next power of two (1080 rows and a 256-pixel PSF: 1350 instead of 2048). Its stages have radix
// 4 (while two factors of 2 are left), 2, 3 and 5, in the order STAGE_LIST gives them.
// Stages as in Govindaraju et al. 2008, "High Performance Discrete Fourier Transforms on Graphics
// Processors", FftIteration for any radix R: butterfly j of a line reads elements j + r L/R
// (r < R), multiplies element r by exp(-+2 pi i r k / (R Ns)), k = j mod Ns, Ns the product of the
// earlier stages' radices, takes the R-point DFT and writes elements (j - k) R + k + q Ns (q < R);
// after the last stage the line is in natural order (autosort).
// Twiddles exp(-2 pi i m / LENGTH) come from a table computed in double precision on the CPU
// (GLSL's single-precision sin and cos alone are accurate to only about 1e-3 after log2 L stages).
// Same sign convention as FFTW; uConjugate = -1 gives the inverse, uScale scales the written result.
//
// LENGTH, LINES, THREADS and STAGE_LIST are defined by glare/gl/fft.cpp when it builds the program
// (LENGTH x LINES complex values fit the 32 KiB of shared memory OpenGL 4.5 guarantees: at most
// 4096); the values below only let the build's validator compile the file alone.
#ifndef LENGTH
#define LENGTH 960
#define LINES 4
#define THREADS 256
#define STAGE_LIST STAGE(4u, 1u) STAGE(4u, 4u) STAGE(4u, 16u) STAGE(3u, 64u) STAGE(5u, 192u)
#endif
layout(local_size_x = THREADS) in;

layout(std430, binding = 0) buffer Data { vec2 data[]; };
layout(std430, binding = 2) readonly buffer Twiddles { vec2 twiddles[]; };  // (cos, -sin)(2 pi m / LENGTH), m < LENGTH

uniform uint uAxisStride;      // element step along a line: 1 for rows, width for columns
uniform uint uLineStride;      // element step between lines: width for rows, 1 for columns
uniform uint uLayerStride;     // width * height
uniform bool uLinesAlongX;     // columns: the workgroup's lines are adjacent in memory
uniform float uConjugate;      // +1 forward, -1 inverse
uniform float uScale;

const uint kElements = uint(LENGTH) * uint(LINES);
// A stage's butterflies over all lines, kElements / R, are shared out in turn; an invocation takes
// at most ceil(kElements / (R THREADS)) of them and keeps their R outputs each until the barrier.
const uint kMaxOutputs = (kElements + uint(THREADS) - 1u) / uint(THREADS) + 5u;

shared vec2 line_values[kElements];
vec2 outputs[kMaxOutputs];

vec2 complex_multiply(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

// -i z forward, +i z inverse.
vec2 minus_i(vec2 z) { return vec2(z.y, -z.x) * uConjugate; }

// The butterflies of one stage (radix, span = Ns) from shared memory into `outputs`.
void butterflies(const uint radix, const uint span) {
  const uint per_line = uint(LENGTH) / radix;
  const uint count = kElements / radix;
  const uint twiddle_step = uint(LENGTH) / (radix * span);
  for (uint n = 0u; n * uint(THREADS) < count; ++n) {
    const uint butterfly = gl_LocalInvocationID.x + n * uint(THREADS);
    if (butterfly >= count) break;
    const uint line = butterfly / per_line, j = butterfly % per_line;
    const uint base = line * uint(LENGTH) + j;
    const uint k = j % span;
    vec2 a[5];
    a[0] = line_values[base];
    for (uint r = 1u; r < radix; ++r) {
      vec2 w = twiddles[r * k * twiddle_step];
      w.y *= uConjugate;
      a[r] = complex_multiply(w, line_values[base + r * per_line]);
    }
    const uint first = radix * n;
    if (radix == 2u) {
      outputs[first] = a[0] + a[1];
      outputs[first + 1u] = a[0] - a[1];
    } else if (radix == 3u) {
      // exp(-2 pi i / 3) = -1/2 - i sqrt(3)/2.
      const vec2 t = a[1] + a[2], m = 0.86602540378443865 * minus_i(a[1] - a[2]);
      const vec2 c = a[0] - 0.5 * t;
      outputs[first] = a[0] + t;
      outputs[first + 1u] = c + m;
      outputs[first + 2u] = c - m;
    } else if (radix == 4u) {
      const vec2 s02 = a[0] + a[2], d02 = a[0] - a[2], s13 = a[1] + a[3], m = minus_i(a[1] - a[3]);
      outputs[first] = s02 + s13;
      outputs[first + 1u] = d02 + m;
      outputs[first + 2u] = s02 - s13;
      outputs[first + 3u] = d02 - m;
    } else {
      // Radix 5: c1, s1 = cos, sin(2 pi / 5); c2, s2 = cos, sin(4 pi / 5).
      const float c1 = 0.30901699437494742, s1 = 0.95105651629515357;
      const float c2 = -0.80901699437494742, s2 = 0.58778525229247313;
      const vec2 t1 = a[1] + a[4], d1 = a[1] - a[4], t2 = a[2] + a[3], d2 = a[2] - a[3];
      const vec2 p1 = a[0] + c1 * t1 + c2 * t2, m1 = minus_i(s1 * d1 + s2 * d2);
      const vec2 p2 = a[0] + c2 * t1 + c1 * t2, m2 = minus_i(s2 * d1 - s1 * d2);
      outputs[first] = a[0] + t1 + t2;
      outputs[first + 1u] = p1 + m1;
      outputs[first + 2u] = p2 + m2;
      outputs[first + 3u] = p2 - m2;
      outputs[first + 4u] = p1 - m1;
    }
  }
}

// The outputs of `butterflies` into their autosorted places.
void write_back(const uint radix, const uint span) {
  const uint per_line = uint(LENGTH) / radix;
  const uint count = kElements / radix;
  for (uint n = 0u; n * uint(THREADS) < count; ++n) {
    const uint butterfly = gl_LocalInvocationID.x + n * uint(THREADS);
    if (butterfly >= count) break;
    const uint line = butterfly / per_line, j = butterfly % per_line;
    const uint k = j % span;
    const uint out0 = line * uint(LENGTH) + (j - k) * radix + k;
    for (uint q = 0u; q < radix; ++q) line_values[out0 + q * span] = outputs[radix * n + q];
  }
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

#define STAGE(radix, span) butterflies(radix, span); barrier(); write_back(radix, span); barrier();

void main() {
  const uint thread = gl_LocalInvocationID.x;
  for (uint element = thread; element < kElements; element += uint(THREADS)) {
    uint shared_index;
    const uint index = buffer_index(element, shared_index);
    line_values[shared_index] = data[index];
  }
  barrier();

  STAGE_LIST

  for (uint element = thread; element < kElements; element += uint(THREADS)) {
    uint shared_index;
    const uint index = buffer_index(element, shared_index);
    data[index] = line_values[shared_index] * uScale;
  }
}
