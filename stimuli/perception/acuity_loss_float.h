#pragma once
// The acuity loss of acuity_loss.h (Luidolt 2020, section 5.3; Eqs. 5.14-5.16) on float32 planes,
// split over row chunks (core/parallel_for.h), in place: what sessions run. apply_acuity_loss, the
// float64 version, is its reference (tests/perception_float_test.cpp: within 1e-5 relative by
// stage_timing.h's pixel metric). Each row chunk makes one sweep down its rows (so the frame is read
// from memory once, the rows in between staying in cache), three rows' work per step:
//   1. row y + 2r (r the cap's kernel radius): which 16-pixel blocks hold a dark pixel (L* < 1);
//   2. row y + r: L* in float of the blocks within a kernel of a dark pixel (Y by the Rec.709 row
//      of lab_colour.h, a cube root only above (6/29)^3) and the horizontal pass, into a ring of
//      2r + 1 rows;
//   3. row y: the vertical pass with the sigma of the horizontally filtered lightness (or of the
//      original, SecondPassSigma), and the pixel rebuilt from its new L* with a*, b* kept.
// Only pixels with L* < 1 change (Eq. 5.16's support: there sigma > 0; elsewhere the first pass
// leaves L* as it is and the second pass, seeing L* >= 1, does too), so the second pass rebuilds
// those alone and leaves every other pixel's bytes untouched. Rebuilding a dark pixel needs no
// full L*a*b* round trip: its f(Y / Y_n) lies on the linear branch, and with L* moving by d, each
// of f(X / X_n), f(Y / Y_n), f(Z / Z_n) moves by d / 116 (a*, b* kept); the linear branch is carried
// as f - 4/29, which has no cancellation near black (lab_colour.h's formulas, rearranged).
// Sigma: below the lightness where Eq. 5.15 reaches max_sigma_px (found once per call by bisection;
// Eq. 5.15 falls monotonically with L*), sigma is the cap without evaluating Eq. 5.14. A block whose
// dark pixels all take the cap (every dark pixel on a desktop display at the default cap) runs in
// float, four pixels at a time (stimuli/float4.h): the kernel sums, the rebuild; any other block
// pixel by pixel, its kernel sums and rebuild in double.
#include "core/image.h"
#include "core/perception_settings.h"
#include "core/vector_isa.h"

namespace glarelab {

// `frame` (linear Rec.709 cd/m2) blurred in place; alpha and depth kept. Throws std::invalid_argument
// as apply_acuity_loss does. The result does not depend on `threads` (>= 1), nor on `isa`, the form
// of the rows' marking (acuity_marking.h: the same bits in each).
void apply_acuity_loss_float(ImageRGBA& frame, const AcuitySettings& settings, double pixels_per_degree, int threads,
                             VectorIsa isa = widest_vector_isa());

}  // namespace glarelab
