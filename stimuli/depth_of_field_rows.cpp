#include "stimuli/depth_of_field_rows.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "core/parallel_for.h"

namespace glarelab {
namespace {

using Tap = DirectSumTap;
using TapClass = DirectSumTapClass;
using TapClasses = std::vector<TapClass>;

// The kernel's nonzero taps by row: the sum skips the zero corners of the ellipse.
std::vector<std::vector<Tap>> taps_by_row(const EllipticalKernel& kernel) {
  std::vector<std::vector<Tap>> rows(static_cast<std::size_t>(kernel.height()));
  for (int dy = -kernel.radius_y_px; dy <= kernel.radius_y_px; ++dy)
    for (int dx = -kernel.radius_x_px; dx <= kernel.radius_x_px; ++dx) {
      const double w = kernel.at(dx, dy);
      if (w != 0.0) rows[static_cast<std::size_t>(dy + kernel.radius_y_px)].push_back({dx, static_cast<float>(w)});
    }
  return rows;
}

// A kernel row's taps in the order the AVX-512 form adds them: by the input's pixel offset p = -dx
// modulo 4 (the pixels of a 512-bit register), each class's taps by ascending p, four apart, a zero
// weight where the row has no tap (adding w x = +0 changes no sum). Within a class, the register
// holding output pixels 4j..4j+3 at tap m reads the input vector m + j, so a block's eight
// registers share their loads: one load a tap instead of eight.
TapClasses tap_classes(const std::vector<Tap>& taps) {
  TapClasses classes;
  const auto residue_of = [](const Tap& tap) { return ((-tap.dx % 4) + 4) % 4; };  // of p = -dx
  for (int residue = 0; residue < 4; ++residue) {
    int first = 0, last = 0;  // p range of the class's taps
    bool any = false;
    for (const Tap& tap : taps) {
      const int p = -tap.dx;
      if (residue_of(tap) != residue) continue;
      first = any ? std::min(first, p) : p;
      last = any ? std::max(last, p) : p;
      any = true;
    }
    if (!any) continue;
    TapClass tap_class;
    tap_class.first_offset_px = first;
    tap_class.weights.assign(static_cast<std::size_t>((last - first) / 4 + 1), 0.0f);
    for (const Tap& tap : taps)
      if (residue_of(tap) == residue) tap_class.weights[static_cast<std::size_t>((-tap.dx - first) / 4)] = tap.weight;
    classes.push_back(std::move(tap_class));
  }
  return classes;
}

// One input row as an output row gathers it: its stored floats, where its column 0 would lie in
// them (before the buffer's start for a span far from the rectangle's left edge: only columns the
// pads cover are read), the outputs it reaches and the taps of its kernel row (and their classes,
// for the AVX-512 form).
struct Source {
  const float* stored;
  std::ptrdiff_t column0;  // float index of column 0 relative to `stored`
  int reach_first, reach_last;  // output columns [first, last) it adds to
  const std::vector<Tap>* taps;
  const TapClasses* classes;
};

constexpr int kBlock = kDirectBlockPx;

#if !(defined(__x86_64__) && defined(__GNUC__))
// The block of kBlock output pixels starting at column x (of the blurred rectangle, whose column X
// gathers input column X - radius_x - dx for tap dx): out = sum over sources and taps, in order, of
// weight x input. Scalar form, where the SSE2 one below is not compiled.
void sum_block(const Source* sources, int count, int x, int radius_x, float* __restrict out) {
  float acc[4 * kBlock] = {};
  for (int s = 0; s < count; ++s) {
    const Source& source = sources[s];
    if (x + kBlock <= source.reach_first || x >= source.reach_last) continue;
    for (const Tap& tap : *source.taps) {
      const float* __restrict in =
          source.stored + (source.column0 + 4 * static_cast<std::ptrdiff_t>(x - radius_x - tap.dx));
      for (int k = 0; k < 4 * kBlock; ++k) acc[k] += tap.weight * in[k];
    }
  }
  std::copy(acc, acc + 4 * kBlock, out);
}
#else
// The block of kBlock output pixels starting at column x (of the blurred rectangle, whose column X
// gathers input column X - radius_x - dx for tap dx): out = sum over sources and taps, in order, of
// weight x input, with SSE2 registers, one pixel each: eight accumulators held across the taps, so
// a block is summed as two halves of eight pixels.
void sum_half_block_sse2(const Source* sources, int count, int x, int radius_x, float* __restrict out) {
  __m128 a0 = _mm_setzero_ps(), a1 = a0, a2 = a0, a3 = a0, a4 = a0, a5 = a0, a6 = a0, a7 = a0;
  for (int s = 0; s < count; ++s) {
    const Source& source = sources[s];
    if (x + kBlock / 2 <= source.reach_first || x >= source.reach_last) continue;
    for (const Tap& tap : *source.taps) {
      const float* in = source.stored + (source.column0 + 4 * static_cast<std::ptrdiff_t>(x - radius_x - tap.dx));
      const __m128 w = _mm_set1_ps(tap.weight);
      a0 = _mm_add_ps(a0, _mm_mul_ps(w, _mm_loadu_ps(in)));
      a1 = _mm_add_ps(a1, _mm_mul_ps(w, _mm_loadu_ps(in + 4)));
      a2 = _mm_add_ps(a2, _mm_mul_ps(w, _mm_loadu_ps(in + 8)));
      a3 = _mm_add_ps(a3, _mm_mul_ps(w, _mm_loadu_ps(in + 12)));
      a4 = _mm_add_ps(a4, _mm_mul_ps(w, _mm_loadu_ps(in + 16)));
      a5 = _mm_add_ps(a5, _mm_mul_ps(w, _mm_loadu_ps(in + 20)));
      a6 = _mm_add_ps(a6, _mm_mul_ps(w, _mm_loadu_ps(in + 24)));
      a7 = _mm_add_ps(a7, _mm_mul_ps(w, _mm_loadu_ps(in + 28)));
    }
  }
  _mm_storeu_ps(out, a0);
  _mm_storeu_ps(out + 4, a1);
  _mm_storeu_ps(out + 8, a2);
  _mm_storeu_ps(out + 12, a3);
  _mm_storeu_ps(out + 16, a4);
  _mm_storeu_ps(out + 20, a5);
  _mm_storeu_ps(out + 24, a6);
  _mm_storeu_ps(out + 28, a7);
}

void sum_block_sse2(const Source* sources, int count, int x, int radius_x, float* __restrict out) {
  sum_half_block_sse2(sources, count, x, radius_x, out);
  sum_half_block_sse2(sources, count, x + kBlock / 2, radius_x, out + 2 * kBlock);
}

// Two pixels a register with AVX2, each product added by a fused multiply-add (rounded once, where
// the SSE2 form rounds the product and the sum apart: the bound between the forms is derived in
// depth_of_field_rows.h).
__attribute__((target("avx2,fma"))) void sum_block_avx2(const Source* sources, int count, int x, int radius_x,
                                                        float* __restrict out) {
  __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0, a4 = a0, a5 = a0, a6 = a0, a7 = a0;
  for (int s = 0; s < count; ++s) {
    const Source& source = sources[s];
    if (x + kBlock <= source.reach_first || x >= source.reach_last) continue;
    for (const Tap& tap : *source.taps) {
      const float* in = source.stored + (source.column0 + 4 * static_cast<std::ptrdiff_t>(x - radius_x - tap.dx));
      const __m256 w = _mm256_set1_ps(tap.weight);
      a0 = _mm256_fmadd_ps(w, _mm256_loadu_ps(in), a0);
      a1 = _mm256_fmadd_ps(w, _mm256_loadu_ps(in + 8), a1);
      a2 = _mm256_fmadd_ps(w, _mm256_loadu_ps(in + 16), a2);
      a3 = _mm256_fmadd_ps(w, _mm256_loadu_ps(in + 24), a3);
      a4 = _mm256_fmadd_ps(w, _mm256_loadu_ps(in + 32), a4);
      a5 = _mm256_fmadd_ps(w, _mm256_loadu_ps(in + 40), a5);
      a6 = _mm256_fmadd_ps(w, _mm256_loadu_ps(in + 48), a6);
      a7 = _mm256_fmadd_ps(w, _mm256_loadu_ps(in + 56), a7);
    }
  }
  _mm256_storeu_ps(out, a0);
  _mm256_storeu_ps(out + 8, a1);
  _mm256_storeu_ps(out + 16, a2);
  _mm256_storeu_ps(out + 24, a3);
  _mm256_storeu_ps(out + 32, a4);
  _mm256_storeu_ps(out + 40, a5);
  _mm256_storeu_ps(out + 48, a6);
  _mm256_storeu_ps(out + 56, a7);
}

// The AVX-512 form: N registers of four pixels (N = 8: two blocks, N = 4: one) gather a source's
// taps class by class (TapClasses), each register's products added by fused multiply-adds in that
// order; the input vectors slide through registers, so each tap costs one load and N products.
template <int N>
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"), always_inline)) inline void add_source_avx512(
    __m512 (&acc)[N], const float* base, const TapClasses& classes) {
  for (const TapClass& tap_class : classes) {
    const float* in = base + 4 * static_cast<std::ptrdiff_t>(tap_class.first_offset_px);
    const float* weight = tap_class.weights.data();
    const int taps = static_cast<int>(tap_class.weights.size());
    __m512 window[N];
#pragma GCC unroll 8
    for (int j = 0; j + 1 < N; ++j) window[j] = _mm512_loadu_ps(in + 16 * j);
    for (int m = 0; m < taps; ++m) {
      window[N - 1] = _mm512_loadu_ps(in + 16 * (m + N - 1));
      const __m512 w = _mm512_set1_ps(weight[m]);
#pragma GCC unroll 8
      for (int j = 0; j < N; ++j) acc[j] = _mm512_fmadd_ps(w, window[j], acc[j]);
#pragma GCC unroll 8
      for (int j = 0; j + 1 < N; ++j) window[j] = window[j + 1];
    }
  }
}

// The block at x (low) and the one at x + kBlock (high) at once: each source is added to the
// blocks it reaches (as the other forms skip, so no read leaves a segment's pads), each output in
// the same order whether its block is summed alone or in a pair.
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))) void sum_block_pair_avx512(
    const Source* sources, int count, int x, int radius_x, bool pair, float* __restrict out) {
  __m512 both[8];
#pragma GCC unroll 8
  for (int j = 0; j < 8; ++j) both[j] = _mm512_setzero_ps();
  for (int s = 0; s < count; ++s) {
    const Source& source = sources[s];
    const bool low = !(x + kBlock <= source.reach_first || x >= source.reach_last);
    const bool high = pair && !(x + 2 * kBlock <= source.reach_first || x + kBlock >= source.reach_last);
    const float* base = source.stored + (source.column0 + 4 * static_cast<std::ptrdiff_t>(x - radius_x));
    if (low && high) {
      add_source_avx512<8>(both, base, *source.classes);
    } else if (low) {
      __m512 half[4] = {both[0], both[1], both[2], both[3]};
      add_source_avx512<4>(half, base, *source.classes);
      both[0] = half[0], both[1] = half[1], both[2] = half[2], both[3] = half[3];
    } else if (high) {
      __m512 half[4] = {both[4], both[5], both[6], both[7]};
      add_source_avx512<4>(half, base + 4 * kBlock, *source.classes);
      both[4] = half[0], both[5] = half[1], both[6] = half[2], both[7] = half[3];
    }
  }
#pragma GCC unroll 4
  for (int j = 0; j < 4; ++j) _mm512_storeu_ps(out + 16 * j, both[j]);
  if (pair) {
#pragma GCC unroll 4
    for (int j = 4; j < 8; ++j) _mm512_storeu_ps(out + 16 * j, both[j]);
  }
}
#endif

// `blocks` consecutive blocks from column x, their kBlock x 4 floats each into out.
using BlockSums = void (*)(const Source*, int, int, int, int, float* __restrict);

#if !(defined(__x86_64__) && defined(__GNUC__))
void sums_scalar(const Source* sources, int count, int x, int radius_x, int blocks, float* __restrict out) {
  for (int b = 0; b < blocks; ++b) sum_block(sources, count, x + b * kBlock, radius_x, out + 4 * b * kBlock);
}
#else
void sums_sse2(const Source* sources, int count, int x, int radius_x, int blocks, float* __restrict out) {
  for (int b = 0; b < blocks; ++b) sum_block_sse2(sources, count, x + b * kBlock, radius_x, out + 4 * b * kBlock);
}
__attribute__((target("avx2,fma"))) void sums_avx2(const Source* sources, int count, int x, int radius_x, int blocks,
                                                   float* __restrict out) {
  for (int b = 0; b < blocks; ++b) sum_block_avx2(sources, count, x + b * kBlock, radius_x, out + 4 * b * kBlock);
}
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))) void sums_avx512(const Source* sources, int count, int x,
                                                                              int radius_x, int blocks,
                                                                              float* __restrict out) {
  for (int b = 0; b < blocks; b += 2)
    sum_block_pair_avx512(sources, count, x + b * kBlock, radius_x, b + 2 <= blocks, out + 4 * b * kBlock);
}
#endif

BlockSums block_sums_for(VectorIsa isa) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (!vector_isa_available(isa)) return sums_sse2;
  return isa == VectorIsa::avx512 ? sums_avx512 : isa == VectorIsa::avx2_fma ? sums_avx2 : sums_sse2;
#else
  (void)isa;
  return sums_scalar;
#endif
}

}  // namespace

int min_segment_gap_px(const EllipticalKernel& kernel) { return 2 * kernel.radius_x_px + kBlock; }

void LayerRows::lay_out(int x0, int y0, int width, int height, const std::vector<RowSpan>& row_spans,
                        const EllipticalKernel& kernel) {
  if (row_spans.size() != static_cast<std::size_t>(height))
    throw std::invalid_argument("stimuli/depth_of_field_rows: " + std::to_string(row_spans.size()) +
                                " row spans for a " + std::to_string(height) + "-row layer");
  std::vector<std::size_t> row_first(static_cast<std::size_t>(height) + 1, 0);
  std::vector<RowSpan> row_segments;
  for (int y = 0; y < height; ++y) {
    const RowSpan& span = row_spans[static_cast<std::size_t>(y)];
    if (span.first < span.last) row_segments.push_back(span);
    row_first[static_cast<std::size_t>(y) + 1] = row_segments.size();
  }
  lay_out_segments(x0, y0, width, height, row_first, row_segments, kernel);
}

void LayerRows::lay_out_segments(int x0, int y0, int width, int height, const std::vector<std::size_t>& row_first,
                                 const std::vector<RowSpan>& row_segments, const EllipticalKernel& kernel) {
  x0_px = x0;
  y0_px = y0;
  width_px = width;
  height_px = height;
  pad_px = 2 * kernel.radius_x_px + kBlock;
  first_segment = row_first;
  segments = row_segments;
  spans.assign(static_cast<std::size_t>(height), RowSpan{});
  for (int y = 0; y < height; ++y) {
    const std::size_t first = first_segment[static_cast<std::size_t>(y)], last = first_segment[static_cast<std::size_t>(y) + 1];
    if (first < last) spans[static_cast<std::size_t>(y)] = {segments[first].first, segments[last - 1].last};
  }
  offsets.resize(segments.size());
  std::size_t size = 0;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    offsets[s] = size;
    size += 4 * static_cast<std::size_t>(segments[s].last - segments[s].first + 2 * pad_px);
  }
  reserve(size);
  const std::size_t pad_floats = 4 * static_cast<std::size_t>(pad_px);
  for (std::size_t s = 0; s < segments.size(); ++s) {
    float* stored = segment_start(s);
    std::fill_n(stored, pad_floats, 0.0f);
    std::fill_n(stored + pad_floats + 4 * static_cast<std::size_t>(segments[s].last - segments[s].first), pad_floats,
                0.0f);
  }
}

void LayerRows::reserve(std::size_t floats) {
  if (floats <= capacity_) return;
  storage_.reset(new float[floats]);  // not value-initialised: lay_out writes what is read
  capacity_ = floats;
}

void copy_layer_rows(const LayerImage& layer, const std::vector<RowSpan>& spans, const EllipticalKernel& kernel,
                     LayerRows& rows) {
  rows.lay_out(layer.x0_px, layer.y0_px, layer.width_px, layer.height_px, spans, kernel);
  for (int y = 0; y < layer.height_px; ++y) {
    const RowSpan& span = spans[static_cast<std::size_t>(y)];
    if (span.first < span.last)
      std::copy_n(layer.pixel(span.first, y), 4 * static_cast<std::size_t>(span.last - span.first),
                  rows.segment_pixels(rows.first_segment[static_cast<std::size_t>(y)]));
  }
}

LayerImage layer_image_of(const LayerRows& rows) {
  LayerImage layer;
  layer.x0_px = rows.x0_px;
  layer.y0_px = rows.y0_px;
  layer.width_px = rows.width_px;
  layer.height_px = rows.height_px;
  layer.rgba.assign(4 * static_cast<std::size_t>(rows.width_px) * rows.height_px, 0.0f);
  for (int y = 0; y < rows.height_px; ++y)
    for (std::size_t s = rows.first_segment[static_cast<std::size_t>(y)];
         s < rows.first_segment[static_cast<std::size_t>(y) + 1]; ++s)
      std::copy_n(rows.segment_pixels(s), 4 * static_cast<std::size_t>(rows.segments[s].last - rows.segments[s].first),
                  layer.pixel(rows.segments[s].first, y));
  return layer;
}

DirectSumKernel direct_sum_kernel(const EllipticalKernel& kernel) {
  DirectSumKernel prepared;
  prepared.radius_x_px = kernel.radius_x_px;
  prepared.radius_y_px = kernel.radius_y_px;
  prepared.taps = taps_by_row(kernel);
  for (const std::vector<Tap>& row_taps : prepared.taps) prepared.classes.push_back(tap_classes(row_taps));
  return prepared;
}

void blur_rows_direct(const LayerRows& rows, const EllipticalKernel& kernel, int threads, VectorIsa isa,
                      const BlurredRowSink& sink) {
  blur_rows_direct(rows, direct_sum_kernel(kernel), 0, rows.height_px + 2 * kernel.radius_y_px, threads, isa, sink);
}

void blur_rows_direct(const LayerRows& rows, const DirectSumKernel& kernel, int first_row, int last_row, int threads,
                      VectorIsa isa, const BlurredRowSink& sink) {
  if (rows.pad_px != 2 * kernel.radius_x_px + kBlock)
    throw std::invalid_argument("stimuli/depth_of_field_rows: rows padded by " + std::to_string(rows.pad_px) +
                                " px were not laid out for a kernel of radius " + std::to_string(kernel.radius_x_px));
  const std::vector<std::vector<Tap>>& taps = kernel.taps;
  const std::vector<TapClasses>& classes = kernel.classes;
  EllipticalKernel radii;  // blurred_row_spans reads the radii only
  radii.radius_x_px = kernel.radius_x_px;
  radii.radius_y_px = kernel.radius_y_px;
  const std::vector<RowSpan> out_spans = blurred_row_spans(rows.spans, radii);
  first_row = std::max(first_row, 0);
  last_row = std::min(last_row, static_cast<int>(out_spans.size()));
  const BlockSums block_sums = block_sums_for(isa);
  const int rx = kernel.radius_x_px, ry = kernel.radius_y_px;
  parallel_chunks(std::max(0, last_row - first_row), threads, [&](int first, int last) {
    std::vector<Source> sources;
    // The chunk's widest row of blocks, its memory not filled (each row's blocks are written whole
    // before they are read): a tile's call is short enough for a zero fill to show.
    int widest_px = 0;
    for (int oy = first_row + first; oy < first_row + last; ++oy)
      widest_px = std::max(widest_px, out_spans[static_cast<std::size_t>(oy)].last - out_spans[static_cast<std::size_t>(oy)].first);
    const std::unique_ptr<float[]> out(new float[4 * static_cast<std::size_t>((widest_px + kBlock - 1) / kBlock) * kBlock]);
    for (int oy = first_row + first; oy < first_row + last; ++oy) {
      const RowSpan& span = out_spans[static_cast<std::size_t>(oy)];
      if (span.first >= span.last) continue;
      sources.clear();
      // Kernel rows top (dy = -ry) to bottom, as the sum's order requires.
      for (int dy = -ry; dy <= ry; ++dy) {
        const int sy = oy - ry - dy;
        if (sy < 0 || sy >= rows.height_px) continue;
        const std::vector<Tap>& row_taps = taps[static_cast<std::size_t>(dy + ry)];
        if (row_taps.empty()) continue;
        for (std::size_t s = rows.first_segment[static_cast<std::size_t>(sy)];
             s < rows.first_segment[static_cast<std::size_t>(sy) + 1]; ++s) {
          const RowSpan& in = rows.segments[s];
          const std::ptrdiff_t column0 = 4 * static_cast<std::ptrdiff_t>(rows.pad_px - in.first);
          sources.push_back({rows.segment_start(s), column0, in.first, in.last + 2 * rx, &row_taps,
                             &classes[static_cast<std::size_t>(dy + ry)]});
        }
      }
      const int count = span.last - span.first;
      const int blocks = (count + kBlock - 1) / kBlock;
      block_sums(sources.data(), static_cast<int>(sources.size()), span.first, rx, blocks, out.get());
      sink(oy, span.first, count, out.get());
    }
  });
}

}  // namespace glarelab
