#pragma once
// Four floats worked at once, for the CPU engine's per-pixel loops (the acuity stage's passes, the
// spectacle warp): SSE2's registers where the compiler targets them (every x86-64), else four
// scalars with the same IEEE single-precision results, operation for operation. GCC 12 at -O2
// leaves scalar the loops these stages need (a load of R, G, B that skips A, a select whose arm it
// has folded to a constant under the default trapping-math rules), so the lanes are written out.
// min and max are SSE's: the second operand where the comparison fails (a NaN).
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace glarelab {

#if defined(__SSE2__)

struct Mask4 {
  __m128 bits;
  static Mask4 of(bool l0, bool l1, bool l2, bool l3) {
    return {_mm_castsi128_ps(_mm_set_epi32(l3 ? -1 : 0, l2 ? -1 : 0, l1 ? -1 : 0, l0 ? -1 : 0))};
  }
  bool any() const { return _mm_movemask_ps(bits) != 0; }
  bool all() const { return _mm_movemask_ps(bits) == 0xF; }
  bool lane(int k) const { return ((_mm_movemask_ps(bits) >> k) & 1) != 0; }
  friend Mask4 operator&(Mask4 a, Mask4 b) { return {_mm_and_ps(a.bits, b.bits)}; }
  friend Mask4 operator|(Mask4 a, Mask4 b) { return {_mm_or_ps(a.bits, b.bits)}; }
};

struct Float4 {
  __m128 v;
  static Float4 load(const float* p) { return {_mm_loadu_ps(p)}; }
  static Float4 all(float x) { return {_mm_set1_ps(x)}; }
  void store(float* p) const { _mm_storeu_ps(p, v); }
  friend Float4 operator+(Float4 a, Float4 b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Float4 operator-(Float4 a, Float4 b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Float4 operator*(Float4 a, Float4 b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Float4 operator/(Float4 a, Float4 b) { return {_mm_div_ps(a.v, b.v)}; }
  friend Mask4 operator<(Float4 a, Float4 b) { return {_mm_cmplt_ps(a.v, b.v)}; }
  friend Mask4 operator<=(Float4 a, Float4 b) { return {_mm_cmple_ps(a.v, b.v)}; }
  friend Mask4 operator>(Float4 a, Float4 b) { return {_mm_cmpgt_ps(a.v, b.v)}; }
  friend Mask4 operator!=(Float4 a, Float4 b) { return {_mm_cmpneq_ps(a.v, b.v)}; }
  friend Float4 min(Float4 a, Float4 b) { return {_mm_min_ps(a.v, b.v)}; }
  friend Float4 max(Float4 a, Float4 b) { return {_mm_max_ps(a.v, b.v)}; }
  // when ? a : b, lane by lane.
  friend Float4 select(Mask4 when, Float4 a, Float4 b) {
    return {_mm_or_ps(_mm_and_ps(when.bits, a.v), _mm_andnot_ps(when.bits, b.v))};
  }
  // The bits as an unsigned integer, divided by 3, back to a float's bits (cube_root's first guess).
  Float4 bits_third_plus(std::uint32_t offset) const {
    // No unsigned 32-bit division in SSE2: the bits of a positive float are below 2^31, so a signed
    // multiply-high by ceil(2^33 / 3) and a shift give floor(bits / 3) exactly for them.
    const __m128i bits = _mm_castps_si128(v);
    const __m128i magic = _mm_set1_epi32(static_cast<int>(0xAAAAAAABu));
    // Even and odd lanes: 32 x 32 -> 64-bit products, the high words kept.
    const __m128i even = _mm_srli_epi64(_mm_mul_epu32(bits, magic), 33);
    const __m128i odd = _mm_srli_epi64(_mm_mul_epu32(_mm_srli_epi64(bits, 32), magic), 33);
    const __m128i third = _mm_or_si128(even, _mm_slli_epi64(odd, 32));
    return {_mm_castsi128_ps(_mm_add_epi32(third, _mm_set1_epi32(static_cast<int>(offset))))};
  }
};

// Four RGBA pixels (16 floats from p) as their R, G, B and A lanes.
inline void load_rgba4(const float* p, Float4& r, Float4& g, Float4& b, Float4& a) {
  __m128 p0 = _mm_loadu_ps(p), p1 = _mm_loadu_ps(p + 4), p2 = _mm_loadu_ps(p + 8), p3 = _mm_loadu_ps(p + 12);
  _MM_TRANSPOSE4_PS(p0, p1, p2, p3);
  r = {p0};
  g = {p1};
  b = {p2};
  a = {p3};
}

// The inverse: R, G, B and A lanes stored as four RGBA pixels.
inline void store_rgba4(float* p, Float4 r, Float4 g, Float4 b, Float4 a) {
  _MM_TRANSPOSE4_PS(r.v, g.v, b.v, a.v);
  _mm_storeu_ps(p, r.v);
  _mm_storeu_ps(p + 4, g.v);
  _mm_storeu_ps(p + 8, b.v);
  _mm_storeu_ps(p + 12, a.v);
}

#else

struct Mask4 {
  bool bits[4];
  static Mask4 of(bool l0, bool l1, bool l2, bool l3) { return {{l0, l1, l2, l3}}; }
  bool any() const { return bits[0] || bits[1] || bits[2] || bits[3]; }
  bool all() const { return bits[0] && bits[1] && bits[2] && bits[3]; }
  bool lane(int k) const { return bits[k]; }
  friend Mask4 operator&(Mask4 a, Mask4 b) { return {{a.bits[0] && b.bits[0], a.bits[1] && b.bits[1], a.bits[2] && b.bits[2], a.bits[3] && b.bits[3]}}; }
  friend Mask4 operator|(Mask4 a, Mask4 b) { return {{a.bits[0] || b.bits[0], a.bits[1] || b.bits[1], a.bits[2] || b.bits[2], a.bits[3] || b.bits[3]}}; }
};

struct Float4 {
  float v[4];
  static Float4 load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
  static Float4 all(float x) { return {{x, x, x, x}}; }
  void store(float* p) const { std::memcpy(p, v, sizeof v); }
  template <typename Op>
  friend Float4 lanes(Float4 a, Float4 b, Op op) {
    return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
  }
  template <typename Op>
  friend Mask4 compare(Float4 a, Float4 b, Op op) {
    return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
  }
  friend Float4 operator+(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x + y; }); }
  friend Float4 operator-(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x - y; }); }
  friend Float4 operator*(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x * y; }); }
  friend Float4 operator/(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x / y; }); }
  friend Mask4 operator<(Float4 a, Float4 b) { return compare(a, b, [](float x, float y) { return x < y; }); }
  friend Mask4 operator<=(Float4 a, Float4 b) { return compare(a, b, [](float x, float y) { return x <= y; }); }
  friend Mask4 operator>(Float4 a, Float4 b) { return compare(a, b, [](float x, float y) { return x > y; }); }
  friend Mask4 operator!=(Float4 a, Float4 b) { return compare(a, b, [](float x, float y) { return x != y; }); }
  friend Float4 min(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x < y ? x : y; }); }
  friend Float4 max(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x > y ? x : y; }); }
  friend Float4 select(Mask4 when, Float4 a, Float4 b) {
    return {{when.bits[0] ? a.v[0] : b.v[0], when.bits[1] ? a.v[1] : b.v[1], when.bits[2] ? a.v[2] : b.v[2],
             when.bits[3] ? a.v[3] : b.v[3]}};
  }
  Float4 bits_third_plus(std::uint32_t offset) const {
    Float4 out;
    for (int k = 0; k < 4; ++k) {
      std::uint32_t bits;
      std::memcpy(&bits, &v[k], sizeof bits);
      bits = bits / 3u + offset;
      std::memcpy(&out.v[k], &bits, sizeof bits);
    }
    return out;
  }
};

inline void load_rgba4(const float* p, Float4& r, Float4& g, Float4& b, Float4& a) {
  r = {{p[0], p[4], p[8], p[12]}};
  g = {{p[1], p[5], p[9], p[13]}};
  b = {{p[2], p[6], p[10], p[14]}};
  a = {{p[3], p[7], p[11], p[15]}};
}

inline void store_rgba4(float* p, Float4 r, Float4 g, Float4 b, Float4 a) {
  for (int k = 0; k < 4; ++k) {
    p[4 * k] = r.v[k];
    p[4 * k + 1] = g.v[k];
    p[4 * k + 2] = b.v[k];
    p[4 * k + 3] = a.v[k];
  }
}

#endif

}  // namespace glarelab
