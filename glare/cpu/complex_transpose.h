#pragma once
// A block of complex values written transposed, as the planned FFT paths move a tile of row
// transforms into column order and back (glare/cpu/pupil_spectrum.cpp, glare/cpu/float_convolution.cpp).
#include <complex>
#include <cstddef>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace glarelab {

// rows x count complex values written transposed: source[r source_stride + k] to
// target[k target_stride + r]. Two by two in SSE2 registers, each complex value one 64-bit lane,
// where the compiler has them (x86-64 always): the compiler made the element-by-element copy one
// scalar move per value with a test of the row count. A copy: the bits are the same either way.
inline void transpose_complex(const std::complex<float>* source, std::size_t source_stride, int rows, std::size_t count,
                              std::complex<float>* target, std::size_t target_stride) {
  const auto row = [&](int r) { return static_cast<std::size_t>(r) * source_stride; };
  std::size_t k = 0;
#if defined(__SSE2__)
  const auto lane = [](const std::complex<float>* value) { return reinterpret_cast<const double*>(value); };
  const auto lane_out = [](std::complex<float>* value) { return reinterpret_cast<double*>(value); };
  for (; k + 2 <= count; k += 2) {
    int r = 0;
    for (; r + 2 <= rows; r += 2) {
      const __m128d upper = _mm_loadu_pd(lane(source + row(r) + k));
      const __m128d lower = _mm_loadu_pd(lane(source + row(r + 1) + k));
      _mm_storeu_pd(lane_out(target + k * target_stride + static_cast<std::size_t>(r)), _mm_unpacklo_pd(upper, lower));
      _mm_storeu_pd(lane_out(target + (k + 1) * target_stride + static_cast<std::size_t>(r)), _mm_unpackhi_pd(upper, lower));
    }
    for (; r < rows; ++r) {
      target[k * target_stride + static_cast<std::size_t>(r)] = source[row(r) + k];
      target[(k + 1) * target_stride + static_cast<std::size_t>(r)] = source[row(r) + k + 1];
    }
  }
#endif
  for (; k < count; ++k)
    for (int r = 0; r < rows; ++r) target[k * target_stride + static_cast<std::size_t>(r)] = source[row(r) + k];
}

// The same for complex doubles, each value one SSE2 register: the compiler's element-by-element
// copy moves each as one 16-byte value already.
inline void transpose_complex(const std::complex<double>* source, std::size_t source_stride, int rows,
                              std::size_t count, std::complex<double>* target, std::size_t target_stride) {
  for (std::size_t k = 0; k < count; ++k)
    for (int r = 0; r < rows; ++r)
      target[k * target_stride + static_cast<std::size_t>(r)] = source[static_cast<std::size_t>(r) * source_stride + k];
}

}  // namespace glarelab
