#include "stimuli/perception/acuity_marking.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "stimuli/float4.h"
#include "stimuli/perception/lab_colour.h"

namespace glarelab {
namespace {

constexpr int kBlockPx = AcuityMarking::kBlockPx;

// A full block four pixels at a time.
bool block_four(const float* rgba, const float* coefficient, float dark_below_t, float lightness_per_t, float* relative) {
  const Float4 c0 = Float4::all(coefficient[0]), c1 = Float4::all(coefficient[1]), c2 = Float4::all(coefficient[2]);
  const Float4 below = Float4::all(dark_below_t), per_t = Float4::all(lightness_per_t), one = Float4::all(1.0f);
  Mask4 dark = Mask4::of(false, false, false, false);
  for (int q = 0; q < kBlockPx; q += 4) {
    Float4 r, g, b, a;
    load_rgba4(rgba + 4 * q, r, g, b, a);
    const Float4 t = c0 * r + c1 * g + c2 * b;
    t.store(relative + q);
    dark = dark | ((t <= below) & (per_t * t < one));
  }
  return dark.any();
}

#if defined(__x86_64__) && defined(__GNUC__)
// A full block eight pixels at a time (AVX2 without FMA: the products and sums round as above).
__attribute__((target("avx2"))) bool block_eight(const float* rgba, const float* coefficient, float dark_below_t,
                                                 float lightness_per_t, float* relative) {
  const __m256 c0 = _mm256_set1_ps(coefficient[0]), c1 = _mm256_set1_ps(coefficient[1]), c2 = _mm256_set1_ps(coefficient[2]);
  const __m256 below = _mm256_set1_ps(dark_below_t), per_t = _mm256_set1_ps(lightness_per_t), one = _mm256_set1_ps(1.0f);
  __m256 dark = _mm256_setzero_ps();
  for (int k = 0; k < kBlockPx; k += 8) {
    // Lane halves: pixels k .. k + 3 low, k + 4 .. k + 7 high, so t stores in pixel order.
    const float* p = rgba + 4 * k;
    const __m256 p0 = _mm256_loadu2_m128(p + 16, p), p1 = _mm256_loadu2_m128(p + 20, p + 4);
    const __m256 p2 = _mm256_loadu2_m128(p + 24, p + 8), p3 = _mm256_loadu2_m128(p + 28, p + 12);
    // _MM_TRANSPOSE4_PS in each half.
    const __m256 low01 = _mm256_unpacklo_ps(p0, p1), low23 = _mm256_unpacklo_ps(p2, p3);
    const __m256 high01 = _mm256_unpackhi_ps(p0, p1), high23 = _mm256_unpackhi_ps(p2, p3);
    const __m256 r = _mm256_shuffle_ps(low01, low23, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 g = _mm256_shuffle_ps(low01, low23, _MM_SHUFFLE(3, 2, 3, 2));
    const __m256 b = _mm256_shuffle_ps(high01, high23, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 t = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(c0, r), _mm256_mul_ps(c1, g)), _mm256_mul_ps(c2, b));
    _mm256_storeu_ps(relative + k, t);
    dark = _mm256_or_ps(dark, _mm256_and_ps(_mm256_cmp_ps(t, below, _CMP_LE_OQ),
                                            _mm256_cmp_ps(_mm256_mul_ps(per_t, t), one, _CMP_LT_OQ)));
  }
  return _mm256_movemask_ps(dark) != 0;
}
#endif

}  // namespace

AcuityMarking::AcuityMarking(double reference_white_cd_m2, float dark_below_t, float lightness_per_t, VectorIsa isa)
    : dark_below_t_(dark_below_t), lightness_per_t_(lightness_per_t), isa_(vector_isa_available(isa) ? isa : VectorIsa::sse2) {
  for (int c = 0; c < 3; ++c) coefficient_[c] = static_cast<float>(kRec709ToXyz[1][c] / reference_white_cd_m2);
}

bool AcuityMarking::block(const float* rgba, int count, float* relative) const {
  if (count == kBlockPx) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (isa_ == VectorIsa::avx2_fma) return block_eight(rgba, coefficient_, dark_below_t_, lightness_per_t_, relative);
#endif
    return block_four(rgba, coefficient_, dark_below_t_, lightness_per_t_, relative);
  }
  bool any = false;
  for (int k = 0; k < count; ++k) {
    relative[k] = this->relative(rgba + 4 * k);
    any = any || dark(relative[k]);
  }
  return any;
}

}  // namespace glarelab
