#include "stimuli/depth_of_field_tiles.h"

#include <algorithm>
#include <atomic>
#include <limits>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "core/parallel_for.h"

namespace glarelab {
namespace {

// target = w x (r, g, b, 1) over `pixels` pixels of `source`: the source's alpha replaced by 1, whose
// product is w exactly (SSE2 where compiled: the same products a lane). Returns whether every
// source R, G and B lies in [0, FLT_MAX] (inspect_pixels' clean pixels), found on the loads the
// products make anyway: every pixel is read by its own layer, so the frame's check costs no pass.
bool weighted_pixels(float* __restrict target, const float* __restrict source, float weight, int pixels) {
#if defined(__x86_64__) && defined(__GNUC__)
  const __m128 colour_mask = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
  const __m128 alpha_one = _mm_set_ps(1.0f, 0.0f, 0.0f, 0.0f);
  const __m128 w = _mm_set1_ps(weight);
  const __m128 zero = _mm_setzero_ps(), largest = _mm_set1_ps(std::numeric_limits<float>::max());
  __m128 in_range = _mm_castsi128_ps(_mm_set1_epi32(-1));
  for (int x = 0; x < pixels; ++x, target += 4, source += 4) {
    const __m128 value = _mm_or_ps(_mm_and_ps(_mm_loadu_ps(source), colour_mask), alpha_one);
    in_range = _mm_and_ps(in_range, _mm_and_ps(_mm_cmpge_ps(value, zero), _mm_cmple_ps(value, largest)));
    _mm_storeu_ps(target, _mm_mul_ps(w, value));
  }
  return _mm_movemask_ps(in_range) == 0xF;
#else
  bool in_range = true;
  for (int x = 0; x < pixels; ++x, target += 4, source += 4) {
    for (int c = 0; c < 3; ++c) {
      in_range = in_range && source[c] >= 0.0f && source[c] <= std::numeric_limits<float>::max();
      target[c] = weight * source[c];
    }
    target[3] = weight;
  }
  return in_range;
#endif
}

#if defined(__x86_64__) && defined(__GNUC__)
// weighted_pixels four pixels a register: the same lanes' operations (alpha replaced by 1, the
// ordered comparisons, the product), so the same bits and the same answer.
__attribute__((target("avx512f,avx512vl,avx512dq"))) bool weighted_pixels_avx512(float* __restrict target,
                                                                                 const float* __restrict source,
                                                                                 float weight, int pixels) {
  constexpr __mmask16 kAlphaLanes = 0x8888;
  const __m512 w = _mm512_set1_ps(weight), one = _mm512_set1_ps(1.0f);
  const __m512 zero = _mm512_setzero_ps(), largest = _mm512_set1_ps(std::numeric_limits<float>::max());
  __mmask16 in_range = 0xFFFF;
  int x = 0;
  for (; x + 4 <= pixels; x += 4) {
    const __m512 pixels_read = _mm512_loadu_ps(source + 4 * static_cast<std::size_t>(x));
    const __m512 value = _mm512_mask_blend_ps(kAlphaLanes, pixels_read, one);
    // Compared on their own, then ANDed: through the carried mask each block waited on the last's.
    const __mmask16 at_least_zero = _mm512_cmp_ps_mask(value, zero, _CMP_GE_OQ);
    in_range &= _mm512_mask_cmp_ps_mask(at_least_zero, value, largest, _CMP_LE_OQ);
    _mm512_storeu_ps(target + 4 * static_cast<std::size_t>(x), _mm512_mul_ps(w, value));
  }
  const bool rest_in_range = weighted_pixels(target + 4 * static_cast<std::size_t>(x),
                                             source + 4 * static_cast<std::size_t>(x), weight, pixels - x);
  return in_range == 0xFFFF && rest_in_range;
}
#endif

// sum += transmission x the blurred layer (premultiplied colour and coverage alike) over `pixels`
// pixels, each product and sum rounded once (SSE2 where compiled: the same operations a lane).
void add_transmitted_row(float* __restrict sum, const float* __restrict transmission, const float* __restrict rgba,
                         int pixels) {
#if defined(__x86_64__) && defined(__GNUC__)
  for (int x = 0; x < pixels; ++x, sum += 4, rgba += 4)
    _mm_storeu_ps(sum, _mm_add_ps(_mm_loadu_ps(sum), _mm_mul_ps(_mm_set1_ps(transmission[x]), _mm_loadu_ps(rgba))));
#else
  for (int x = 0; x < pixels; ++x, sum += 4, rgba += 4) {
    const float t = transmission[x];
    for (int c = 0; c < 4; ++c) sum[c] += t * rgba[c];
  }
#endif
}

// sum = transmission x the blurred layer: the same bits as adding it to a zero sum (0 + p is p;
// p is never -0, the layers being non-negative).
void set_transmitted_row(float* __restrict sum, const float* __restrict transmission, const float* __restrict rgba,
                         int pixels) {
#if defined(__x86_64__) && defined(__GNUC__)
  for (int x = 0; x < pixels; ++x, sum += 4, rgba += 4)
    _mm_storeu_ps(sum, _mm_mul_ps(_mm_set1_ps(transmission[x]), _mm_loadu_ps(rgba)));
#else
  for (int x = 0; x < pixels; ++x, sum += 4, rgba += 4) {
    const float t = transmission[x];
    for (int c = 0; c < 4; ++c) sum[c] = t * rgba[c];
  }
#endif
}

// The same where nothing hides the row yet (transmission 1: 1 x v is v, so the same bits).
void add_row(float* __restrict sum, const float* __restrict rgba, int pixels) {
  for (int k = 0; k < 4 * pixels; ++k) sum[k] += rgba[k];
}

// One of the three above, or the copy (add: sum += [transmission x] rgba; else sum = [transmission
// x] rgba; transmission nullptr where nothing hides the row yet).
void put_row(float* sum, const float* transmission, const float* rgba, int pixels, bool add) {
  if (transmission == nullptr) {
    if (add)
      add_row(sum, rgba, pixels);
    else
      std::copy_n(rgba, 4 * static_cast<std::size_t>(pixels), sum);
  } else if (add) {
    add_transmitted_row(sum, transmission, rgba, pixels);
  } else {
    set_transmitted_row(sum, transmission, rgba, pixels);
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
// Four pixels' transmissions, each in its pixel's four lanes. (The masked forms with every lane set:
// the unmasked ones start from an undefined register, which GCC 12 reports as maybe uninitialised.)
__attribute__((target("avx512f,avx512vl,avx512dq"))) inline __m512 four_transmissions(const float* transmission) {
  const __m512 zero = _mm512_setzero_ps();
  const __m512i spread = _mm512_set_epi32(3, 3, 3, 3, 2, 2, 2, 2, 1, 1, 1, 1, 0, 0, 0, 0);
  return _mm512_mask_permutexvar_ps(zero, 0xFFFF, spread,
                                    _mm512_mask_broadcast_f32x4(zero, 0xFFFF, _mm_loadu_ps(transmission)));
}

// The operations of the three above (add: sum += [transmission x] rgba; else sum = [transmission x]
// rgba), four pixels a register where the stage's form is AVX-512: each lane's product and sum
// rounded once, the same bits. Contraction is off: GCC's default for C++ would fuse a product and
// its sum into one multiply-add (one rounding, other bits) where the target has FMA.
__attribute__((target("avx512f,avx512vl,avx512dq"), optimize("fp-contract=off"))) void put_row_avx512(
    float* __restrict sum, const float* __restrict transmission, const float* __restrict rgba, int pixels, bool add) {
  int x = 0;
  for (; x + 4 <= pixels; x += 4) {
    float* out = sum + 4 * static_cast<std::size_t>(x);
    __m512 value = _mm512_loadu_ps(rgba + 4 * static_cast<std::size_t>(x));
    if (transmission != nullptr) value = _mm512_mul_ps(four_transmissions(transmission + x), value);
    _mm512_storeu_ps(out, add ? _mm512_add_ps(_mm512_loadu_ps(out), value) : value);
  }
  if (x == pixels) return;
  put_row(sum + 4 * static_cast<std::size_t>(x), transmission == nullptr ? nullptr : transmission + x,
          rgba + 4 * static_cast<std::size_t>(x), pixels - x, add);
}
#endif

// sum's row y on `clip` (frame columns) given the layer's blurred values there. `written` is the
// row's stretch that holds sums (outside it the sum is zero and not stored): the values are added
// inside it and written outside, the columns between it and `clip` zeroed, and it grows to hold
// both. transmission: the row's, or nullptr where nothing hides it yet. wide: the AVX-512 form.
void accumulate_row(float* sum_row, const float* transmission_row, RowSpan& written, const RowSpan& clip,
                    const float* rgba, bool wide) {
  const auto put = [&](int first, int last, bool add) {
    if (first >= last) return;
    float* out = sum_row + 4 * static_cast<std::size_t>(first);
    const float* in = rgba + 4 * static_cast<std::size_t>(first - clip.first);
#if defined(__x86_64__) && defined(__GNUC__)
    if (wide) {
      put_row_avx512(out, transmission_row == nullptr ? nullptr : transmission_row + first, in, last - first, add);
      return;
    }
#else
    (void)wide;
#endif
    put_row(out, transmission_row == nullptr ? nullptr : transmission_row + first, in, last - first, add);
  };
  if (written.first >= written.last) {
    put(clip.first, clip.last, false);
    written = clip;
    return;
  }
  // Zeros between the stretch and the clip, where they do not meet.
  if (clip.last < written.first)
    std::fill(sum_row + 4 * static_cast<std::size_t>(clip.last), sum_row + 4 * static_cast<std::size_t>(written.first), 0.0f);
  if (clip.first > written.last)
    std::fill(sum_row + 4 * static_cast<std::size_t>(written.last), sum_row + 4 * static_cast<std::size_t>(clip.first), 0.0f);
  put(clip.first, std::min(clip.last, written.first), false);
  put(std::max(clip.first, written.first), std::min(clip.last, written.last), true);
  put(std::max(clip.first, written.last), clip.last, false);
  written = {std::min(written.first, clip.first), std::max(written.last, clip.last)};
}

// t *= 1 - coverage over `count` pixels (SSE2 where compiled: the same operations a lane).
void transmit_through(float* __restrict t, const float* __restrict coverage, int count) {
  int x = 0;
#if defined(__x86_64__) && defined(__GNUC__)
  const __m128 one = _mm_set1_ps(1.0f);
  for (; x + 4 <= count; x += 4)
    _mm_storeu_ps(t + x, _mm_mul_ps(_mm_loadu_ps(t + x), _mm_sub_ps(one, _mm_loadu_ps(coverage + x))));
#endif
  for (; x < count; ++x) t[x] *= 1.0f - coverage[x];
}

// The pixels [first, last) of a frame row of the layers' sum divided by their coverage (a pixel's
// coverage is > 0 wherever the sum is stored: every pixel belongs to a layer whose kernel keeps
// light at its centre; 1 is taken for any other), max(x, 0) as std::max(0, x) (0 for a NaN), each
// lane's quotient rounded once, alpha the input's.
void divide_pixels(float* __restrict out, const float* __restrict image, int first, int last) {
  for (int x = first; x < last; ++x) {
    float* pixel = out + 4 * static_cast<std::size_t>(x);
    const float coverage = pixel[3] > 0.0f ? pixel[3] : 1.0f;
    const float alpha = image[4 * static_cast<std::size_t>(x) + 3];
#if defined(__x86_64__) && defined(__GNUC__)
    _mm_storeu_ps(pixel, _mm_max_ps(_mm_div_ps(_mm_loadu_ps(pixel), _mm_set1_ps(coverage)), _mm_setzero_ps()));
#else
    for (int c = 0; c < 3; ++c) pixel[c] = std::max(0.0f, pixel[c] / coverage);
#endif
    pixel[3] = alpha;
  }
}

// A zero sum's pixels [first, last): max(0 / 1, 0) = 0, alpha the input's.
void zero_pixels(float* __restrict out, const float* __restrict image, int first, int last) {
  for (int x = first; x < last; ++x) {
    float* pixel = out + 4 * static_cast<std::size_t>(x);
    pixel[0] = pixel[1] = pixel[2] = 0.0f;
    pixel[3] = image[4 * static_cast<std::size_t>(x) + 3];
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
// divide_pixels four pixels a register: the same lanes' operations (ordered comparison, quotient,
// max with +0 as its second operand), so the same bits.
__attribute__((target("avx512f,avx512vl,avx512dq"))) void divide_pixels_avx512(float* __restrict out,
                                                                               const float* __restrict image,
                                                                               int first, int last) {
  const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f);
  constexpr __mmask16 kAlphaLanes = 0x8888;
  int x = first;
  for (; x + 4 <= last; x += 4) {
    float* pixels = out + 4 * static_cast<std::size_t>(x);
    const __m512 sum = _mm512_loadu_ps(pixels);
    // Each pixel's coverage in its four lanes (masked forms, as in four_transmissions).
    const __m512 alpha = _mm512_mask_permute_ps(sum, 0xFFFF, sum, 0xFF);
    const __m512 coverage = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(alpha, zero, _CMP_GT_OQ), one, alpha);
    const __m512 colour = _mm512_mask_max_ps(zero, 0xFFFF, _mm512_div_ps(sum, coverage), zero);
    const __m512 image_pixels = _mm512_loadu_ps(image + 4 * static_cast<std::size_t>(x));
    _mm512_storeu_ps(pixels, _mm512_mask_blend_ps(kAlphaLanes, colour, image_pixels));
  }
  divide_pixels(out, image, x, last);
}

__attribute__((target("avx512f,avx512vl,avx512dq"))) void zero_pixels_avx512(float* __restrict out,
                                                                             const float* __restrict image, int first,
                                                                             int last) {
  int x = first;
  for (; x + 4 <= last; x += 4)
    _mm512_storeu_ps(out + 4 * static_cast<std::size_t>(x),
                     _mm512_maskz_mov_ps(0x8888, _mm512_loadu_ps(image + 4 * static_cast<std::size_t>(x))));
  zero_pixels(out, image, x, last);
}
#endif

// The frame rows [first, last) from the layers' sum (premultiplied, stored on each row's `written`
// stretch, zero outside): colour divided by coverage, alpha the input's.
void divide_by_coverage(const ImageRGBA& image_cd_m2, const std::vector<RowSpan>& written, int first, int last,
                        bool wide, ImageRGBA& result) {
  const int width = result.width_px;
  for (int y = first; y < last; ++y) {
    const RowSpan& stored = written[static_cast<std::size_t>(y)];
    const int inside_first = std::clamp(stored.first, 0, width);
    const int inside_last = std::clamp(stored.last, inside_first, width);
    float* out = result.pixel(0, y);
    const float* image = image_cd_m2.pixel(0, y);
#if defined(__x86_64__) && defined(__GNUC__)
    if (wide) {
      zero_pixels_avx512(out, image, 0, inside_first);
      divide_pixels_avx512(out, image, inside_first, inside_last);
      zero_pixels_avx512(out, image, inside_last, width);
      continue;
    }
#endif
    zero_pixels(out, image, 0, inside_first);
    divide_pixels(out, image, inside_first, inside_last);
    zero_pixels(out, image, inside_last, width);
  }
}

// t = 1 over `count` values (SSE2 where compiled: std::fill_n with a float is a loop of scalar stores).
void fill_ones(float* __restrict t, int count) {
  int x = 0;
#if defined(__x86_64__) && defined(__GNUC__)
  const __m128 one = _mm_set1_ps(1.0f);
  for (; x + 4 <= count; x += 4) _mm_storeu_ps(t + x, one);
#endif
  for (; x < count; ++x) t[x] = 1.0f;
}

#if defined(__x86_64__) && defined(__GNUC__)
// coverage = the alpha of `pixels` RGBA pixels, sixteen at a time permuted into one register and
// stored whole (a masked store of four lanes a register took half the function's time).
__attribute__((target("avx512f,avx512vl,avx512dq"))) void copy_alpha_avx512(float* __restrict coverage,
                                                                            const float* __restrict rgba, int pixels) {
  const __m512i two_alphas = _mm512_set_epi32(0, 0, 0, 0, 0, 0, 0, 0, 31, 27, 23, 19, 15, 11, 7, 3);
  const __m512i four_alphas = _mm512_set_epi32(23, 22, 21, 20, 19, 18, 17, 16, 7, 6, 5, 4, 3, 2, 1, 0);
  int x = 0;
  for (const float* in = rgba; x + 16 <= pixels; x += 16, in += 64) {
    const __m512 low = _mm512_permutex2var_ps(_mm512_loadu_ps(in), two_alphas, _mm512_loadu_ps(in + 16));
    const __m512 high = _mm512_permutex2var_ps(_mm512_loadu_ps(in + 32), two_alphas, _mm512_loadu_ps(in + 48));
    _mm512_storeu_ps(coverage + x, _mm512_permutex2var_ps(low, four_alphas, high));
  }
  for (; x < pixels; ++x) coverage[x] = rgba[4 * static_cast<std::size_t>(x) + 3];
}
#endif

// coverage = the alpha of `pixels` RGBA pixels (wide: the AVX-512 form).
void copy_alpha(float* __restrict coverage, const float* __restrict rgba, int pixels, bool wide) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (wide) {
    copy_alpha_avx512(coverage, rgba, pixels);
    return;
  }
#else
  (void)wide;
#endif
  for (int x = 0; x < pixels; ++x) coverage[x] = rgba[4 * static_cast<std::size_t>(x) + 3];
}

// transmission *= 1 - the occluder's coverage on the tile's rows; a row hidden for the first time
// is set to 1 first.
void occlude(DepthOfFieldTileBuffers& work, int width_px, const TileOccluder& occluder) {
  for (std::size_t row = 0; row < occluder.spans.size(); ++row) {
    const RowSpan& span = occluder.spans[row];
    if (span.first >= span.last) continue;
    float* t_row = &work.transmission[row * static_cast<std::size_t>(width_px)];
    if (!work.hidden[row]) {
      fill_ones(t_row, width_px);
      work.hidden[row] = 1;
    }
    transmit_through(t_row + span.first, occluder.coverage.data() + occluder.offsets[row] + span.first,
                     span.last - span.first);
  }
}

// An occluder for the tile's `rows` rows, none of them covered yet, in kept memory.
TileOccluder empty_occluder(double hides_up_to, int rows, int width_px, DepthOfFieldTileBuffers& work) {
  TileOccluder occluder;
  if (!work.coverages.empty()) {
    occluder.coverage = std::move(work.coverages.back());
    work.coverages.pop_back();
  }
  // Row r's values at r x width_px: the memory is sized once and its values are never filled.
  if (occluder.coverage.size() < static_cast<std::size_t>(rows) * width_px)
    occluder.coverage.resize(static_cast<std::size_t>(rows) * width_px);
  occluder.hides_up_to_vergence_dioptres = hides_up_to;
  occluder.spans.assign(static_cast<std::size_t>(rows), RowSpan{});
  occluder.offsets.resize(static_cast<std::size_t>(rows));
  for (int row = 0; row < rows; ++row)
    occluder.offsets[static_cast<std::size_t>(row)] = static_cast<std::size_t>(row) * width_px;
  return occluder;
}

// The occluders that hide a layer at `vergence` applied to the transmission, in the order they
// were kept (near first), their memory returned.
void apply_occluders(DepthOfFieldTileBuffers& work, int width_px, double vergence) {
  for (auto occluder = work.pending.begin(); occluder != work.pending.end();) {
    if (occluder->hides_up_to_vergence_dioptres > vergence) {
      occlude(work, width_px, *occluder);
      work.coverages.push_back(std::move(occluder->coverage));
      occluder = work.pending.erase(occluder);
    } else {
      ++occluder;
    }
  }
}

}  // namespace

bool composite_tile(const TiledFrame& frame, int y_first, int y_last, DepthOfFieldTileBuffers& work) {
  const int width = frame.result.width_px, tile_rows = y_last - y_first;
  // The compositing's AVX-512 form (the same bits as the SSE2 one) where the stage's form is AVX-512.
  const bool wide = frame.isa == VectorIsa::avx512 && vector_isa_available(VectorIsa::avx512);
  work.transmission.resize(static_cast<std::size_t>(width) * tile_rows);
  work.hidden.assign(static_cast<std::size_t>(tile_rows), 0);
  for (TileOccluder& occluder : work.pending) work.coverages.push_back(std::move(occluder.coverage));
  work.pending.clear();
  bool in_range = true;
#if defined(__x86_64__) && defined(__GNUC__)
  // The tile's image rows asked for at once, in order: the layers' fills then find them in the
  // cache instead of each waiting on its own rows (a layer's run is too short a stream for the
  // hardware's prefetcher).
  const char* image_rows = reinterpret_cast<const char*>(frame.image.pixel(0, y_first));
  const std::size_t image_bytes = 16 * static_cast<std::size_t>(width) * tile_rows;
  for (std::size_t byte = 0; byte < image_bytes; byte += 64) _mm_prefetch(image_rows + byte, _MM_HINT_T1);
#endif
  // Near to far (the plan ascends in vergence), as depth_of_field.h describes.
  for (std::size_t index = frame.layers.size(); index-- > 0;) {
    const TiledLayer& layer = frame.layers[index];
    apply_occluders(work, width, layer.vergence_dioptres);
    if (layer.box.x1 < 0) continue;  // no pixel
    const EllipticalKernel& kernel = *layer.kernel;
    const int rx = kernel.radius_x_px, ry = kernel.radius_y_px;
    // The tile's rows the layer's blur reaches, and the layer's rows they gather.
    const int out_first = std::max(y_first, layer.box.y0 - ry), out_last = std::min(y_last, layer.box.y1 + ry + 1);
    if (out_first >= out_last) continue;
    TileOccluder occluder;
    if (layer.occludes) occluder = empty_occluder(layer.hides_up_to_vergence_dioptres, tile_rows, width, work);
    // sum += transmission x the blurred row inside the frame; the occluder keeps its coverage.
    const auto add = [&](int y, int rectangle_x0, int first, int count, const float* rgba) {
      const RowSpan clip{std::max(0, rectangle_x0 + first), std::min(width, rectangle_x0 + first + count)};
      if (clip.first >= clip.last) return;
      const std::size_t row = static_cast<std::size_t>(y - y_first);
      const float* in = rgba + 4 * static_cast<std::size_t>(clip.first - rectangle_x0 - first);
      accumulate_row(&frame.result.rgba[4 * static_cast<std::size_t>(y) * width],
                     work.hidden[row] ? &work.transmission[row * width] : nullptr,
                     frame.written[static_cast<std::size_t>(y)], clip, in, wide);
      if (layer.occludes) {
        occluder.spans[row] = clip;
        copy_alpha(occluder.coverage.data() + occluder.offsets[row] + clip.first, in, clip.last - clip.first, wide);
      }
    };
    if (layer.direct != nullptr) {
      const int in_first = std::max(layer.box.y0, out_first - ry), in_last = std::min(layer.box.y1, out_last - 1 + ry);
      in_range &= fill_layer_rows(frame.image, frame.runs, static_cast<std::uint32_t>(index), layer.box, in_first,
                                  in_last, kernel, work.rows, 1, frame.isa);
      // Output row r of the rows' grown rectangle is frame row in_first - ry + r.
      const int row0 = in_first - ry;
      blur_rows_direct(work.rows, *layer.direct, out_first - row0, out_last - row0, 1, frame.isa,
                       [&](int row, int first, int count, const float* rgba) {
                         add(row0 + row, layer.box.x0 - rx, first, count, rgba);
                       });
    } else {
      const BlurredLayerRows& stored = *layer.blurred;
      for (int y = out_first; y < out_last; ++y) {
        const std::size_t row = static_cast<std::size_t>(y - stored.y0_px);
        const RowSpan& span = stored.spans[row];
        if (span.first < span.last)
          add(y, stored.x0_px, span.first, span.last - span.first, stored.rgba.data() + stored.offsets[row]);
      }
    }
    if (layer.occludes) work.pending.push_back(std::move(occluder));
  }
  divide_by_coverage(frame.image, frame.written, y_first, y_last, wide, frame.result);
  return in_range;
}

// The layer's pixels as premultiplied RGBA on their rows' segments in its bounding rectangle, a
// run of the plan at a time: on its own pixels colour and coverage times 1 - their blend weight, on
// the pixels blended into it from a neighbour times their blend weight, 0 between. A segment is a
// stretch of the layer's runs; a gap too short to part two (min_segment_gap_px) is kept as zeros.
// Returns whether every pixel read was in range (weighted_pixels).
bool fill_layer_rows(const ImageRGBA& image, const std::vector<std::vector<PixelRun>>& runs, std::uint32_t index,
                     const FrameRectangle& box, int first_row, int last_row, const EllipticalKernel& kernel,
                     LayerRows& rows, int threads, VectorIsa isa) {
#if defined(__x86_64__) && defined(__GNUC__)
  const auto weigh = isa == VectorIsa::avx512 && vector_isa_available(VectorIsa::avx512) ? weighted_pixels_avx512
                                                                                        : weighted_pixels;
#else
  (void)isa;
  const auto weigh = weighted_pixels;
#endif
  const int height = last_row - first_row + 1, gap = min_segment_gap_px(kernel);
  std::vector<std::size_t> row_first(static_cast<std::size_t>(height) + 1, 0);
  std::vector<RowSpan> segments;
  for (int y = 0; y < height; ++y) {
    const std::size_t row_start = segments.size();
    for (const PixelRun& run : runs[static_cast<std::size_t>(first_row + y)]) {
      if (run.own != index && run.blended != index) continue;
      const int first = run.first - box.x0, last = run.end - box.x0;
      if (segments.size() > row_start && first - segments.back().last < gap)
        segments.back().last = last;
      else
        segments.push_back({first, last});
    }
    row_first[static_cast<std::size_t>(y) + 1] = segments.size();
  }
  rows.lay_out_segments(box.x0, first_row, box.x1 - box.x0 + 1, height, row_first, segments, kernel);
  std::atomic<bool> in_range{true};
  parallel_chunks(height, threads, [&](int chunk_first, int chunk_last) {
    bool chunk_in_range = true;
    for (int y = chunk_first; y < chunk_last; ++y) {
      const std::vector<PixelRun>& row_runs = runs[static_cast<std::size_t>(first_row + y)];
      auto run = row_runs.begin();
      for (std::size_t s = rows.first_segment[static_cast<std::size_t>(y)];
           s < rows.first_segment[static_cast<std::size_t>(y) + 1]; ++s) {
        const int frame_first = box.x0 + rows.segments[s].first, frame_last = box.x0 + rows.segments[s].last;
        float* target = rows.segment_pixels(s);
        while (run != row_runs.end() && run->end <= frame_first) ++run;
        for (; run != row_runs.end() && run->first < frame_last; ++run) {
          const int first = std::max(run->first, frame_first), last = std::min(run->end, frame_last);
          float* out = target + 4 * static_cast<std::size_t>(first - frame_first);
          if (run->own == index)
            chunk_in_range &= weigh(out, image.pixel(first, first_row + y), 1.0f - run->blend_weight, last - first);
          else if (run->blended == index)
            chunk_in_range &= weigh(out, image.pixel(first, first_row + y), run->blend_weight, last - first);
          else
            std::fill_n(out, 4 * static_cast<std::size_t>(last - first), 0.0f);
        }
        if (run != row_runs.begin()) --run;  // the last run may reach into the next segment
      }
    }
    if (!chunk_in_range) in_range = false;
  });
  return in_range;
}

}  // namespace glarelab
