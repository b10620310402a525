#pragma once
// The float acuity stage's marking of a row (stimuli/perception/acuity_loss_float.h, step 1): each
// pixel's Y / Y_n (lab_colour.h: Y_n the reference white), kept for the later passes, and whether a
// block of pixels holds a dark one (L* < 1, which holds only on L*'s linear branch: t <= (6/29)^3 and
// L* = lightness_per_t t < 1). Y / Y_n is (c_R R + c_G G) + c_B B in float, in that order. A full
// block (16 pixels) is worked four pixels at a time on SSE2 (stimuli/float4.h), or eight with AVX2,
// a 256-bit register holding pixels k and k + 4 so that one in-lane transpose serves two groups of
// four: the same operations in the same order and no fused multiply-add, so the same bits.
#include "core/vector_isa.h"

namespace glarelab {

class AcuityMarking {
 public:
  static constexpr int kBlockPx = 16;
  // `isa`: the form of the full blocks; one this CPU does not run takes SSE2.
  AcuityMarking(double reference_white_cd_m2, float dark_below_t, float lightness_per_t, VectorIsa isa);
  float relative(const float* rgb) const { return coefficient_[0] * rgb[0] + coefficient_[1] * rgb[1] + coefficient_[2] * rgb[2]; }
  bool dark(float t) const { return (t <= dark_below_t_) & (lightness_per_t_ * t < 1.0f); }
  // Y / Y_n of `count` RGBA pixels into relative[0 .. count); true when one of them is dark.
  bool block(const float* rgba, int count, float* relative) const;

 private:
  float coefficient_[3];
  float dark_below_t_, lightness_per_t_;
  VectorIsa isa_;
};

}  // namespace glarelab
